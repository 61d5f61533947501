# written by tools/accuracy/accuracy.py: Light probes: formats, layouts, glossy prefiltering, error against time
$s0 << EOD
17.7452 0.000105339
17.2504 0.000210679
16.6319 0.00208392
EOD
$s1 << EOD
17.628 0.000105339
16.8524 0.175915
16.4499 0.00208392
EOD
$s2 << EOD
17.2223 0.168306
13.8907 0.470728
16.1154 0.0916314
16.1171 0.126869
EOD
$s3 << EOD
17.7571 0.465831
17.0164 0.263301
EOD
$s4 << EOD
375.086 0.0232849
456.352 0.00715596
485.25 0.00250815
762.351 0.000761366
EOD
$s5 << EOD
530.326 0.0219427
569.607 0.00673129
670.837 0.00248681
1071.74 0.00078898
EOD
$s6 << EOD
5.091 0.241
9.168 0.798535
17.605 0.201833
34.814 0.122369
68.016 0.100164
155.79 0.0880509
345.08 0.0873729
12.004 0.186226
22.835 0.133171
44.124 0.0830331
88.164 0.0711398
165.381 0.0684438
314.552 0.0723721
560.908 0.0740416
11.577 0.21044
20.227 0.155065
37.403 0.0978374
79.61 0.0677388
149.631 0.052818
274.505 0.0448164
481.217 0.0399757
EOD
$front << EOD
5.091 0.241
11.577 0.21044
12.004 0.186226
16.1154 0.0916314
16.4499 0.00208392
17.2504 0.000210679
17.628 0.000105339
1607.61 0.000105339
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'probe.png'
set logscale xy
set grid
set key outside right top
set xrange [3.394:1607.61]
set yrange [0.000105339:1.59707]
set xtics ('5' 5, '10' 10, '20' 20, '50' 50, '100' 100, '200' 200, '500' 500, '1000' 1000)
set ytics ('0.001' 0.001, '0.01' 0.01, '0.1' 0.1, '1' 1)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Light probes: formats, layouts, glossy prefiltering\nAMD EPYC, 2 cores; backend cpu; load average 1.41 1.42 1.99 at the start, 1.24 1.36 1.93 at the end;\n2026-11-28 23:19 UTC; error 0 drawn on the bottom edge"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'probe_format', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'probe_format_sun', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'probe_layout', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'probe_layout_latlong', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'probe_prefilter_nol', \
     $s5 using 1:2 with points pt 4 ps 1.6 lw 1.5 lc rgb '#17becf' title 'probe_prefilter_nol_vis', \
     $s6 using 1:2 with points pt 6 ps 1.6 lw 1.5 lc rgb '#8c564b' title 'probe_prefilter_oracle', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
