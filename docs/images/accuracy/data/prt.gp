# written by tools/accuracy/accuracy.py: Precomputed radiance transfer (SH), error against time
$s0 << EOD
40.9256 0.649939
136.56 0.64646
508.163 0.645179
37.4138 0.344614
130.859 0.334421
486.896 0.333091
37.1134 0.213045
107.133 0.197193
488.12 0.196656
37.9996 0.143612
135.348 0.124498
502.948 0.124948
41.2936 0.101382
138.647 0.0746119
526.258 0.0716569
40.195 0.0975264
135.247 0.0708592
470.625 0.0579681
EOD
$s1 << EOD
13.8817 0.17622
33.5677 0.0980731
110.629 0.0763867
12.2423 0.189677
35.8833 0.0926219
120.995 0.0764712
13.8562 0.196349
40.3322 0.101382
135.817 0.0746119
EOD
$s2 << EOD
37.963 1.74157
131.282 0.0746119
EOD
$s3 << EOD
0.4218 0.27022
5.7303 0.213912
44.0781 0.0753554
0.426 0.171337
5.7953 0.0823675
42.7436 0.0744931
0.4654 0.387439
5.7558 0.137302
44.7982 0.0748216
EOD
$s4 << EOD
508.395 0.384788
707.109 0.278216
1086.28 0.146955
1500.51 0.0480929
EOD
$s5 << EOD
3.6468 0.197193
3.6932 0.0746119
4.8971 0.197193
4.4544 0.0746119
3.4397 0.197193
3.7138 0.0746119
EOD
$front << EOD
0.4218 0.27022
0.426 0.171337
3.6932 0.0746119
3.7138 0.0746119
4.4544 0.0746119
42.7436 0.0744931
135.247 0.0708592
470.625 0.0579681
1500.51 0.0480929
2250.77 0.0480929
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'prt.png'
set logscale xy
set grid
set key outside right top
set xrange [0.2812:2250.77]
set yrange [0.0240465:3.48314]
set xtics ('1' 1, '10' 10, '100' 100, '1000' 1000)
set ytics ('0.05' 0.05, '0.1' 0.1, '0.2' 0.2, '0.5' 0.5, '1' 1, '2' 2)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Precomputed radiance transfer (SH)\nAMD EPYC, 2 cores; backend cl, cpu, gl; load average 1.16 1.53 3.29 at the start, 1.58 1.58 3.21 at the end;\n2026-11-28 23:02 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'prt_bands', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'prt_samplers', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'prt_visibility', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'prt_lighting', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'prt_bounces', \
     $s5 using 1:2 with points pt 4 ps 1.6 lw 1.5 lc rgb '#17becf' title 'prt_dot', \
     0.1 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 10% relative RMSE'
