# written by tools/accuracy/accuracy.py: Shadow maps: resolution, fit, bias, error against time
$s0 << EOD
12.8106 0.159227
13.2121 0.159227
13.7331 0.0800088
14.1335 0.0800088
16.5942 0.0403744
16.7265 0.0403744
23.7293 0.0347798
21.134 0.0347798
43.1674 0.0274453
32.7467 0.0274453
133.131 0.0103191
131.725 0.0103191
EOD
$s1 << EOD
18.6566 0.0198108
18.7059 0.0243424
21.1747 0.0347798
21.3474 0.0443437
21.2274 0.058691
EOD
$s2 << EOD
22.393 0.0350414
22.2246 0.0347798
26.052 0.0355589
25.4426 0.124828
EOD
$front << EOD
12.8106 0.159227
13.7331 0.0800088
16.5942 0.0403744
18.6566 0.0198108
131.725 0.0103191
199.697 0.0103191
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'shadowmap.png'
set logscale xy
set grid
set key outside right top
set xrange [8.5404:199.697]
set yrange [0.005:0.318454]
set xtics ('10' 10, '20' 20, '50' 50, '100' 100)
set ytics ('0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Shadow maps: resolution, fit, bias\nAMD EPYC, 2 cores; backend gl; load average 0.57 0.83 2.30 at the start, 0.68 0.85 2.30 at the end;\n2026-11-28 23:09 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'shadow_resolution', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'shadow_normal_offset', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'shadow_bias', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
