# written by tools/accuracy/accuracy.py: Local illumination: Phong shading modes, error against time
$s0 << EOD
1.6609 0.417379
1.3986 0.261016
2.087 0.181062
5.498 0.105788
16.9374 0.0518171
0.9595 0.419458
1.7627 0.281595
1.6092 0.165394
4.5017 0.0630955
12.1127 0.0183173
2.9534 0.337047
3.7128 0.127766
5.0097 0.0621691
7.7787 0.0240445
14.8227 0.00586814
2.835 0.339015
3.1911 0.129207
5.4013 0.0626274
13.6281 0.0241821
47.5853 0.00593668
7.3052 0.336616
8.8139 0.127608
9.736 0.0621482
10.9671 0.0243162
22.6011 0.00723255
EOD
$s1 << EOD
18.158 0.0740472
18.4918 0.0333969
15.8591 0.00107782
35.9571 0.0236485
21.0448 0.0650213
EOD
$s2 << EOD
37.5895 0.0318115
40.3108 0.0267672
44.0971 0.0241838
43.2902 0.0236485
38.9524 0.0235134
42.0374 0.0232671
EOD
$s3 << EOD
16.0028 0.104785
18.7791 0.0398317
20.6073 0.00107782
41.7133 0.0331824
23.8468 0.0576132
EOD
$s4 << EOD
4.8626 0.0748761
3.764 0.0570252
27.1375 0.00107782
26.7 0.00215564
21.969 0.00380323
EOD
$front << EOD
0.9595 0.419458
1.3986 0.261016
1.6092 0.165394
3.1911 0.129207
3.7128 0.127766
3.764 0.0570252
7.7787 0.0240445
12.1127 0.0183173
14.8227 0.00586814
15.8591 0.00107782
71.3779 0.00107782
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'phong.png'
set logscale xy
set grid
set key outside right top
set xrange [0.639667:71.3779]
set yrange [0.00107782:0.838915]
set xtics ('1' 1, '2' 2, '5' 5, '10' 10, '20' 20, '50' 50)
set ytics ('0.002' 0.002, '0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2, '0.5' 0.5)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Local illumination: Phong shading modes\nAMD EPYC, 2 cores; backend gl; load average 0.47 0.69 1.84 at the start, 1.06 0.82 1.85 at the end;\n2026-11-29 04:11 UTC; error 0 drawn on the bottom edge"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'phong_sphere', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'phong_bunny', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'phong_mixed', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'phong_depth_cue', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'phong_16lights', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
