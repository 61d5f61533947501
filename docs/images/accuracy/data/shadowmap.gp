# written by tools/accuracy/accuracy.py: Shadow maps: resolution, fit, bias, error against time
$s0 << EOD
15.448 0.159227
15.163 0.159227
18.8632 0.0800088
15.9636 0.0800088
21.7362 0.0403744
20.401 0.0403744
33.6323 0.0347798
33.1884 0.0347798
77.1442 0.0274453
64.2166 0.0274453
258.986 0.0103191
250.768 0.0103191
EOD
$s1 << EOD
27.8143 0.0198108
33.5237 0.0243424
32.408 0.0347798
33.9517 0.0443437
32.7428 0.058691
EOD
$s2 << EOD
25.2915 0.0350414
25.8765 0.0347798
30.8014 0.0355589
35.1621 0.124828
EOD
$front << EOD
15.163 0.159227
15.9636 0.0800088
20.401 0.0403744
25.2915 0.0350414
25.8765 0.0347798
27.8143 0.0198108
250.768 0.0103191
388.479 0.0103191
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'shadowmap.png'
set logscale xy
set grid
set key outside right top
set xrange [10.1087:388.479]
set yrange [0.005:0.318454]
set xtics ('20' 20, '50' 50, '100' 100, '200' 200)
set ytics ('0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Shadow maps: resolution, fit, bias\nAMD EPYC, 2 cores; backend gl; load average 1.12 0.85 1.83 at the start, 1.25 0.89 1.83 at the end;\n2026-11-29 04:12 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'shadow_resolution', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'shadow_normal_offset', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'shadow_bias', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
