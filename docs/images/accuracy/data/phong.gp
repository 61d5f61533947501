# written by tools/accuracy/accuracy.py: Local illumination: Phong shading modes, error against time
$s0 << EOD
0.8564 0.417379
1.002 0.261016
1.6832 0.181062
4.5315 0.105788
15.0152 0.0518171
0.7698 0.419458
0.8722 0.281595
1.3853 0.165394
3.0363 0.0630955
11.0493 0.0183173
4.1971 0.337047
5.2423 0.127766
6.1873 0.0621691
8.8913 0.0240445
11.1801 0.00586814
2.0274 0.339015
2.5579 0.129207
3.9085 0.0626274
8.4693 0.0241821
31.3377 0.00593668
6.1239 0.336616
8.3253 0.127608
7.8984 0.0621482
9.7279 0.0243162
20.841 0.00723255
EOD
$s1 << EOD
18.3501 0.0740472
17.8257 0.0333969
17.4145 0.00107782
36.8543 0.0236485
20.4855 0.0650213
EOD
$s2 << EOD
42.0055 0.0318115
40.766 0.0267672
40.0371 0.0241839
38.4763 0.0236485
36.201 0.0235134
32.8443 0.0232671
EOD
$s3 << EOD
16.2894 0.104785
15.1008 0.0398318
15.7417 0.00107782
37.53 0.0331824
23.51 0.0576132
EOD
$s4 << EOD
4.2627 0.0748761
2.981 0.0570252
26.4643 0.00107782
27.1542 0.00215564
24.3748 0.00380323
EOD
$front << EOD
0.7698 0.419458
0.8564 0.417379
0.8722 0.281595
1.002 0.261016
1.3853 0.165394
2.5579 0.129207
2.981 0.0570252
8.4693 0.0241821
8.8913 0.0240445
11.0493 0.0183173
11.1801 0.00586814
15.7417 0.00107782
63.0082 0.00107782
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'phong.png'
set logscale xy
set grid
set key outside right top
set xrange [0.5132:63.0082]
set yrange [0.00107782:0.838915]
set xtics ('1' 1, '2' 2, '5' 5, '10' 10, '20' 20, '50' 50)
set ytics ('0.002' 0.002, '0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2, '0.5' 0.5)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Local illumination: Phong shading modes\nAMD EPYC, 2 cores; backend gl; load average 0.60 1.40 2.07 at the start, 0.72 1.37 2.04 at the end;\n2026-11-28 23:17 UTC; error 0 drawn on the bottom edge"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'phong_sphere', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'phong_bunny', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'phong_mixed', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'phong_depth_cue', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'phong_16lights', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
