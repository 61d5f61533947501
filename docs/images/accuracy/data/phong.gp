# written by tools/accuracy/accuracy.py: Local illumination: Phong shading modes, error against time
$s0 << EOD
0.7268 0.417379
1.0526 0.261016
1.5563 0.181062
3.5594 0.105788
15.1246 0.0518171
0.7396 0.419458
0.7305 0.281595
1.3545 0.165394
3.0029 0.0630955
10.526 0.0183173
3.7877 0.337047
3.5518 0.127766
4.331 0.0621691
6.2393 0.0240445
9.961 0.00586814
2.0044 0.339015
2.4694 0.129207
5.1871 0.0626274
8.3651 0.0241821
33.2374 0.00593668
5.1737 0.336616
5.9937 0.127608
6.7218 0.0621482
11.6376 0.0243162
19.0588 0.00723255
EOD
$s1 << EOD
16.8786 0.0740472
17.7734 0.0333969
15.9151 0.00107782
38.7996 0.0236485
19.0146 0.0650213
EOD
$s2 << EOD
33.6534 0.0318115
33.9007 0.0267672
32.0211 0.0241839
38.7087 0.0236485
36.3168 0.0235134
38.669 0.0232671
EOD
$s3 << EOD
15.2975 0.104785
17.4978 0.0398318
13.707 0.00107782
33.121 0.0331824
21.6349 0.0576132
EOD
$s4 << EOD
3.6664 0.0748761
2.6004 0.0570252
21.9784 0.00107782
25.0619 0.00215564
20.6122 0.00380323
EOD
$front << EOD
0.7268 0.417379
0.7305 0.281595
1.0526 0.261016
1.3545 0.165394
2.4694 0.129207
2.6004 0.0570252
6.2393 0.0240445
9.961 0.00586814
13.707 0.00107782
58.1994 0.00107782
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'phong.png'
set logscale xy
set grid
set key outside right top
set xrange [0.484533:58.1994]
set yrange [0.00107782:0.838915]
set xtics ('0.5' 0.5, '1' 1, '2' 2, '5' 5, '10' 10, '20' 20, '50' 50)
set ytics ('0.002' 0.002, '0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2, '0.5' 0.5)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Local illumination: Phong shading modes\nAMD EPYC, 2 cores; backend gl; load average 0.06 0.78 2.35 at the start, 0.34 0.81 2.34 at the end;\n2026-11-28 23:08 UTC; error 0 drawn on the bottom edge"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'phong_sphere', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'phong_bunny', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'phong_mixed', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'phong_depth_cue', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'phong_16lights', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
