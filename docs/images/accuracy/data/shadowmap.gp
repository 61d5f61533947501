# written by tools/accuracy/accuracy.py: Shadow maps: resolution, fit, bias, error against time
$s0 << EOD
14.6802 0.159227
14.2183 0.159227
16.1403 0.0800088
16.91 0.0800088
19.1082 0.0403744
17.0377 0.0403744
24.6491 0.0347798
24.5215 0.0347798
44.782 0.0274453
34.8662 0.0274453
131.676 0.0103191
133.92 0.0103191
EOD
$s1 << EOD
21.6702 0.0198108
20.9484 0.0243424
16.3887 0.0347798
14.1938 0.0443437
16.5853 0.058691
EOD
$s2 << EOD
13.9638 0.0350414
17.4494 0.0347798
16.9829 0.0355589
14.3613 0.124828
EOD
$front << EOD
13.9638 0.0350414
16.3887 0.0347798
20.9484 0.0243424
21.6702 0.0198108
131.676 0.0103191
200.88 0.0103191
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'shadowmap.png'
set logscale xy
set grid
set key outside right top
set xrange [9.3092:200.88]
set yrange [0.005:0.318454]
set xtics ('10' 10, '20' 20, '50' 50, '100' 100, '200' 200)
set ytics ('0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Shadow maps: resolution, fit, bias\nAMD EPYC, 2 cores; backend gl; load average 0.81 1.34 2.01 at the start, 0.91 1.35 2.01 at the end;\n2026-11-28 23:18 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'shadow_resolution', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'shadow_normal_offset', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'shadow_bias', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
