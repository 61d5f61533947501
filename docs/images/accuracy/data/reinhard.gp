# written by tools/accuracy/accuracy.py: Tone mapping: Reinhard's operator, cpu / gl / cl, error against time
$s0 << EOD
1.8393 5.91015e-08
1.8288 0.000147091
10.8365 1.43015e-07
17.0926 0.000147035
2.0305 1.92019e-07
2.0227 0.000147263
EOD
$s1 << EOD
1.4073 5.91015e-08
1.3641 7.41918e-05
18.0972 1.18203e-07
18.4977 7.4144e-05
1.4928 1.55679e-07
2.0974 7.43364e-05
EOD
$s2 << EOD
1.8913 5.91015e-08
18.1004 1.43015e-07
2.0443 1.92019e-07
1.8752 0.000210252
15.9045 0.000210252
2.1827 0.000210252
1.8252 0.00275
15.5286 0.00275
1.8164 0.00275
EOD
$front << EOD
1.3641 7.41918e-05
1.4073 5.91015e-08
27.7465 5.91015e-08
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'reinhard.png'
set logscale xy
set grid
set key outside right top
set xrange [0.9094:27.7465]
set yrange [5.91015e-08:0.02]
set xtics ('1' 1, '2' 2, '5' 5, '10' 10, '20' 20)
set ytics ('1e-07' 1e-07, '1e-06' 1e-06, '1e-05' 1e-05, '0.0001' 0.0001, '0.001' 0.001, '0.01' 0.01)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Tone mapping: Reinhard's operator, cpu / gl / cl\nAMD EPYC, 2 cores; backend cl, cpu, gl; load average 1.06 0.82 1.85 at the start, 1.12 0.85 1.83 at the end;\n2026-11-29 04:12 UTC; error 0 drawn on the bottom edge"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'reinhard_luminance', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'reinhard_rgb', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'reinhard_input', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
