# written by tools/accuracy/accuracy.py: Tone mapping: Reinhard's operator, cpu / gl / cl, error against time
$s0 << EOD
1.8028 5.91015e-08
1.7897 0.000147091
12.5643 1.43015e-07
11.3747 0.000147035
2.0796 1.92019e-07
2.1217 0.000147263
EOD
$s1 << EOD
1.385 5.91015e-08
1.3077 7.41918e-05
10.3814 1.18203e-07
11.4414 7.4144e-05
2.4407 1.55679e-07
2.3966 7.43364e-05
EOD
$s2 << EOD
2.0842 5.91015e-08
11.4262 1.43015e-07
2.3239 1.92019e-07
2.2398 0.000210252
16.4715 0.000210252
2.0618 0.000210252
1.7638 0.00275
17.7373 0.00275
2.2312 0.00275
EOD
$front << EOD
1.3077 7.41918e-05
1.385 5.91015e-08
26.6059 5.91015e-08
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'reinhard.png'
set logscale xy
set grid
set key outside right top
set xrange [0.8718:26.6059]
set yrange [5.91015e-08:0.02]
set xtics ('1' 1, '2' 2, '5' 5, '10' 10, '20' 20)
set ytics ('1e-07' 1e-07, '1e-06' 1e-06, '1e-05' 1e-05, '0.0001' 0.0001, '0.001' 0.001, '0.01' 0.01)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Tone mapping: Reinhard's operator, cpu / gl / cl\nAMD EPYC, 2 cores; backend cl, cpu, gl; load average 0.72 1.37 2.04 at the start, 0.80 1.34 2.02 at the end;\n2026-11-28 23:17 UTC; error 0 drawn on the bottom edge"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'reinhard_luminance', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'reinhard_rgb', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'reinhard_input', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
