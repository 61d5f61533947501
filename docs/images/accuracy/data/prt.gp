# written by tools/accuracy/accuracy.py: Precomputed radiance transfer (SH), error against time
$s0 << EOD
39.1814 0.649939
128.548 0.64646
480.627 0.645179
37.9595 0.344614
135.94 0.334421
472.222 0.333091
39.705 0.213045
137.791 0.197193
517.139 0.196656
38.7134 0.143612
136.083 0.124498
522.468 0.124948
42.233 0.101382
139.436 0.0746119
506.127 0.0716569
44.3527 0.0975264
144.021 0.0708592
578.194 0.0579681
EOD
$s1 << EOD
14.9469 0.17622
34.536 0.0980731
110.327 0.0763867
13.4036 0.189677
36.6976 0.0926219
119.466 0.0764712
13.3746 0.196349
38.1347 0.101382
133.169 0.0746119
EOD
$s2 << EOD
33.6033 1.74157
131.678 0.0746119
EOD
$s3 << EOD
0.4419 0.27022
5.4401 0.213912
43.3284 0.0753554
0.4588 0.171337
5.7272 0.0823675
43.6006 0.0744931
0.4797 0.387439
6.3305 0.137302
48.6544 0.0748216
EOD
$s4 << EOD
431.716 0.384788
625.004 0.278216
1099.36 0.146955
1989.58 0.0480929
EOD
$s5 << EOD
3.1177 0.197193
3.1945 0.0746119
7.0162 0.197193
5.8477 0.0746119
3.3185 0.197193
3.325 0.0746119
EOD
$front << EOD
0.4419 0.27022
0.4588 0.171337
3.1945 0.0746119
3.325 0.0746119
5.8477 0.0746119
43.6006 0.0744931
144.021 0.0708592
578.194 0.0579681
1989.58 0.0480929
2984.38 0.0480929
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'prt.png'
set logscale xy
set grid
set key outside right top
set xrange [0.2946:2984.38]
set yrange [0.0240465:3.48314]
set xtics ('1' 1, '10' 10, '100' 100, '1000' 1000)
set ytics ('0.05' 0.05, '0.1' 0.1, '0.2' 0.2, '0.5' 0.5, '1' 1, '2' 2)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Precomputed radiance transfer (SH)\nAMD EPYC, 2 cores; backend cl, cpu, gl; load average 1.12 0.88 1.81 at the start, 1.67 1.08 1.82 at the end;\n2026-11-29 04:13 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'prt_bands', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'prt_samplers', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'prt_visibility', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'prt_lighting', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'prt_bounces', \
     $s5 using 1:2 with points pt 4 ps 1.6 lw 1.5 lc rgb '#17becf' title 'prt_dot', \
     0.1 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 10% relative RMSE'
