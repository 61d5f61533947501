# written by tools/accuracy/accuracy.py: Shadow maps: resolution, fit, bias, PCF and PCSS against exact visibility, error against time
$s0 << EOD
228.549 0.113035
121.301 0.0634137
232.671 0.0604503
835.637 0.048297
160.651 0.133373
220.383 0.0910335
447.69 0.0505399
799.606 0.0424751
259.669 0.167703
281.707 0.114948
331.643 0.0697297
510.853 0.0448356
231.931 0.190865
291.663 0.138127
405.303 0.0877918
789.733 0.0520105
634.619 0.219757
193.17 0.155107
227.535 0.103398
915.514 0.0628146
EOD
$s1 << EOD
256.566 0.0590835
425.25 0.0438655
767.103 0.0380361
EOD
$s2 << EOD
352.686 0.0479931
410.012 0.0419677
679.606 0.0620435
EOD
$s3 << EOD
147.286 0.0813344
182.208 0.0508857
218.898 0.0352039
263.949 0.0266205
125.558 0.05934
147.604 0.0454215
161.608 0.0329535
256.178 0.022876
166.046 0.0714673
136.392 0.0492574
122.005 0.0358717
191.654 0.026136
67.7464 0.0826117
67.2594 0.0585543
95.6658 0.0406233
201.996 0.0295087
109.737 0.0932814
241.051 0.0673814
299.871 0.0484042
407.457 0.0329325
EOD
$s4 << EOD
315.808 0.0455247
347.75 0.0293585
594.408 0.0233203
EOD
$s5 << EOD
440.633 0.0355137
374.458 0.0298512
1027.84 0.0215412
EOD
$s6 << EOD
246.289 0.0654813
351.685 0.0401644
492.528 0.0295369
1268.05 0.0184038
334.321 0.065052
451.734 0.038527
385.403 0.0225982
1907.27 0.0180462
507.418 0.0711795
637.915 0.0448673
707.592 0.0322308
1056.91 0.0200682
279.493 0.0819251
431.654 0.0611315
328.26 0.0364392
1188.21 0.0234781
373.318 0.100251
431.806 0.0608507
576.123 0.0453426
980.128 0.0281355
EOD
$s7 << EOD
503.901 0.0354766
649.451 0.028463
1081.67 0.0180077
EOD
$s8 << EOD
572.319 0.0541766
1033.88 0.0309583
1959.98 0.0176169
EOD
$s9 << EOD
136.841 0.21744
128.106 0.21744
93.0177 0.113035
164.148 0.113035
87.7838 0.0634137
183.429 0.0634137
283.698 0.0604503
273.596 0.0604503
527.502 0.048297
444.156 0.048297
1055.49 0.0386461
1439.44 0.0386461
EOD
$s10 << EOD
251.331 0.0427718
199.531 0.0432652
223.462 0.0604503
451.703 0.0710133
280.006 0.0869165
EOD
$s11 << EOD
226.454 0.0596128
229.453 0.0604503
271.26 0.0612764
294.7 0.173288
EOD
$front << EOD
67.2594 0.0585543
95.6658 0.0406233
122.005 0.0358717
161.608 0.0329535
191.654 0.026136
256.178 0.022876
385.403 0.0225982
1027.84 0.0215412
1056.91 0.0200682
1081.67 0.0180077
1959.98 0.0176169
2939.97 0.0176169
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'shadowmap.png'
set logscale xy
set grid
set key outside right top
set xrange [44.8396:2939.97]
set yrange [0.005:0.439515]
set xtics ('50' 50, '100' 100, '200' 200, '500' 500, '1000' 1000, '2000' 2000)
set ytics ('0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Shadow maps: resolution, fit, bias, PCF and PCSS against exact visibility\nAMD EPYC, 2 cores; backend gl; load average 16.39 17.37 18.03 at the start, 14.20 15.66 17.19 at the end;\n2026-11-29 09:21 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'shadow_directional_pcf', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'shadow_directional_pcss1', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'shadow_directional_pcss2', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'shadow_spot_pcf', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'shadow_spot_pcss1', \
     $s5 using 1:2 with points pt 4 ps 1.6 lw 1.5 lc rgb '#17becf' title 'shadow_spot_pcss2', \
     $s6 using 1:2 with points pt 6 ps 1.6 lw 1.5 lc rgb '#8c564b' title 'shadow_point_pcf', \
     $s7 using 1:2 with points pt 8 ps 1.6 lw 1.5 lc rgb '#e377c2' title 'shadow_point_pcss1', \
     $s8 using 1:2 with points pt 10 ps 1.6 lw 1.5 lc rgb '#7f7f7f' title 'shadow_point_pcss2', \
     $s9 using 1:2 with points pt 12 ps 1.6 lw 1.5 lc rgb '#bcbd22' title 'shadow_resolution', \
     $s10 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#d62728' title 'shadow_normal_offset', \
     $s11 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'shadow_bias', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
