# written by tools/accuracy/accuracy.py: Tone mapping: Reinhard's operator, cpu / gl / cl, error against time
$s0 << EOD
1.8078 5.91015e-08
1.8455 0.000147091
11.1332 1.43015e-07
10.9189 0.000147035
2.1595 1.92019e-07
2.1132 0.000147263
EOD
$s1 << EOD
1.2032 5.91015e-08
1.1977 7.41918e-05
10.8244 1.18203e-07
11.5885 7.4144e-05
1.6506 1.55679e-07
1.7084 7.43364e-05
EOD
$s2 << EOD
1.6549 5.91015e-08
10.0263 1.43015e-07
1.6442 1.92019e-07
1.8337 0.000210252
11.1576 0.000210252
2.0395 0.000210252
1.8066 0.00275
14.2341 0.00275
2.0691 0.00275
EOD
$front << EOD
1.1977 7.41918e-05
1.2032 5.91015e-08
21.3512 5.91015e-08
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'reinhard.png'
set logscale xy
set grid
set key outside right top
set xrange [0.798467:21.3512]
set yrange [5.91015e-08:0.02]
set xtics ('1' 1, '2' 2, '5' 5, '10' 10, '20' 20)
set ytics ('1e-07' 1e-07, '1e-06' 1e-06, '1e-05' 1e-05, '0.0001' 0.0001, '0.001' 0.001, '0.01' 0.01)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Tone mapping: Reinhard's operator, cpu / gl / cl\nAMD EPYC, 2 cores; backend cl, cpu, gl; load average 0.39 0.81 2.33 at the start, 0.53 0.82 2.31 at the end;\n2026-11-28 23:09 UTC; error 0 drawn on the bottom edge"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'reinhard_luminance', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'reinhard_rgb', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'reinhard_input', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
