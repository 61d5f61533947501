# written by tools/accuracy/accuracy.py: Light probes: formats, layouts, glossy prefiltering, error against time
$s0 << EOD
18.2519 0.000105339
18.2903 0.000210679
17.4685 0.00208392
EOD
$s1 << EOD
17.2332 0.000105339
16.0555 0.175915
17.7443 0.00208392
EOD
$s2 << EOD
14.7074 0.168306
16.0203 0.470728
17.1098 0.0916314
15.1788 0.126869
EOD
$s3 << EOD
14.3567 0.465831
15.459 0.263301
EOD
$s4 << EOD
387.295 0.0232849
394.855 0.00715596
558.55 0.00250815
1051.91 0.000761366
EOD
$s5 << EOD
376.039 0.0219427
586.302 0.00673129
674.255 0.00248681
1041.81 0.00078898
EOD
$s6 << EOD
5.89 0.241
11.015 0.798535
21.832 0.201833
43.542 0.122369
89.64 0.100164
177.299 0.0880509
310.323 0.0873729
11.375 0.186226
22.905 0.133171
44.603 0.0830331
88.383 0.0711398
171.429 0.0684438
317.977 0.0723721
568.26 0.0740416
12.201 0.21044
23.39 0.155065
44.743 0.0978374
88.987 0.0677388
171.099 0.052818
318.648 0.0448164
456.384 0.0399757
EOD
$front << EOD
5.89 0.241
11.375 0.186226
14.7074 0.168306
15.1788 0.126869
17.1098 0.0916314
17.2332 0.000105339
1577.87 0.000105339
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'probe.png'
set logscale xy
set grid
set key outside right top
set xrange [3.92667:1577.87]
set yrange [0.000105339:1.59707]
set xtics ('5' 5, '10' 10, '20' 20, '50' 50, '100' 100, '200' 200, '500' 500, '1000' 1000)
set ytics ('0.001' 0.001, '0.01' 0.01, '0.1' 0.1, '1' 1)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Light probes: formats, layouts, glossy prefiltering\nAMD EPYC, 2 cores; backend cpu; load average 1.58 1.58 3.21 at the start, 1.35 1.52 3.06 at the end;\n2026-11-28 23:03 UTC; error 0 drawn on the bottom edge"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'probe_format', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'probe_format_sun', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'probe_layout', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'probe_layout_latlong', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'probe_prefilter_nol', \
     $s5 using 1:2 with points pt 4 ps 1.6 lw 1.5 lc rgb '#17becf' title 'probe_prefilter_nol_vis', \
     $s6 using 1:2 with points pt 6 ps 1.6 lw 1.5 lc rgb '#8c564b' title 'probe_prefilter_oracle', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
