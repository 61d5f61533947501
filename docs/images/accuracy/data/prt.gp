# written by tools/accuracy/accuracy.py: Precomputed radiance transfer (SH), error against time
$s0 << EOD
40.4449 0.649939
134.93 0.64646
502.591 0.645179
38.1256 0.344614
133.592 0.334421
491.918 0.333091
38.7505 0.213045
133.692 0.197193
523.329 0.196656
39.2539 0.143612
130.867 0.124498
510.984 0.124948
32.8163 0.101382
116.802 0.0746119
523.704 0.0716569
41.9591 0.0975264
136.932 0.0708592
527.599 0.0579681
EOD
$s1 << EOD
13.7009 0.17622
34.8568 0.0980731
114.783 0.0763867
12.8603 0.189677
36.0348 0.0926219
123.135 0.0764712
13.2275 0.196349
39.6047 0.101382
137.545 0.0746119
EOD
$s2 << EOD
61.4535 1.74157
119.876 0.0746119
EOD
$s3 << EOD
0.4618 0.27022
5.4393 0.213912
40.7527 0.0753554
0.482 0.171337
5.9837 0.0823675
46.1474 0.0744931
0.516 0.387439
5.987 0.137302
47.3056 0.0748216
EOD
$s4 << EOD
527.432 0.384788
733.852 0.278216
1302.32 0.146955
1612.61 0.0480929
EOD
$s5 << EOD
4.0369 0.197193
3.7628 0.0746119
4.956 0.197193
6.2313 0.0746119
3.6245 0.197193
3.6497 0.0746119
EOD
$front << EOD
0.4618 0.27022
0.482 0.171337
3.6497 0.0746119
6.2313 0.0746119
46.1474 0.0744931
136.932 0.0708592
527.599 0.0579681
1612.61 0.0480929
2418.92 0.0480929
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'prt.png'
set logscale xy
set grid
set key outside right top
set xrange [0.307867:2418.92]
set yrange [0.0240465:3.48314]
set xtics ('1' 1, '10' 10, '100' 100, '1000' 1000)
set ytics ('0.05' 0.05, '0.1' 0.1, '0.2' 0.2, '0.5' 0.5, '1' 1, '2' 2)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Precomputed radiance transfer (SH)\nAMD EPYC, 2 cores; backend cl, cpu, gl; load average 0.91 1.35 2.01 at the start, 1.41 1.42 1.99 at the end;\n2026-11-28 23:18 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'prt_bands', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'prt_samplers', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'prt_visibility', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'prt_lighting', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'prt_bounces', \
     $s5 using 1:2 with points pt 4 ps 1.6 lw 1.5 lc rgb '#17becf' title 'prt_dot', \
     0.1 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 10% relative RMSE'
