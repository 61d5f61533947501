# written by tools/accuracy/accuracy.py: Light probes: formats, layouts, glossy prefiltering, error against time
$s0 << EOD
20.6193 0.000105339
22.9775 0.000210679
21.1206 0.00208392
EOD
$s1 << EOD
22.5597 0.000105339
22.8575 0.175915
21.9638 0.00208392
EOD
$s2 << EOD
18.7272 0.168306
17.7189 0.470728
18.4062 0.0916314
16.77 0.126869
EOD
$s3 << EOD
20.7482 0.465831
22.2134 0.263301
EOD
$s4 << EOD
484.495 0.0232849
537.657 0.00715596
494.15 0.00250815
746.539 0.000761366
EOD
$s5 << EOD
357.119 0.0219427
557.795 0.00673129
631.169 0.00248681
1024.1 0.00078898
EOD
$s6 << EOD
5.273 0.241
9.715 0.798535
18.684 0.201833
33.935 0.122369
70.017 0.100164
133.608 0.0880509
270.025 0.0873729
12.664 0.186226
21.959 0.133171
40.969 0.0830331
85.848 0.0711398
163.258 0.0684438
273.132 0.0723721
460.602 0.0740416
9.811 0.21044
17.192 0.155065
35.072 0.0978374
71.618 0.0677388
142.136 0.052818
250.031 0.0448164
543.838 0.0399757
EOD
$front << EOD
5.273 0.241
9.811 0.21044
12.664 0.186226
16.77 0.126869
18.4062 0.0916314
20.6193 0.000105339
1536.16 0.000105339
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'probe.png'
set logscale xy
set grid
set key outside right top
set xrange [3.51533:1536.16]
set yrange [0.000105339:1.59707]
set xtics ('5' 5, '10' 10, '20' 20, '50' 50, '100' 100, '200' 200, '500' 500, '1000' 1000)
set ytics ('0.001' 0.001, '0.01' 0.01, '0.1' 0.1, '1' 1)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Light probes: formats, layouts, glossy prefiltering\nAMD EPYC, 2 cores; backend cpu; load average 1.67 1.08 1.82 at the start, 1.44 1.12 1.79 at the end;\n2026-11-29 04:14 UTC; error 0 drawn on the bottom edge"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'probe_format', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'probe_format_sun', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'probe_layout', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'probe_layout_latlong', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'probe_prefilter_nol', \
     $s5 using 1:2 with points pt 4 ps 1.6 lw 1.5 lc rgb '#17becf' title 'probe_prefilter_nol_vis', \
     $s6 using 1:2 with points pt 6 ps 1.6 lw 1.5 lc rgb '#8c564b' title 'probe_prefilter_oracle', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
