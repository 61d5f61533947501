# written by tools/accuracy/accuracy.py: Volumetric lighting, error against time
$s0 << EOD
5.8295 0.11009
8.4434 0.131939
16.5853 0.137734
47.5954 0.139119
EOD
$s1 << EOD
6.8171 0.11009
8.6007 0.131939
15.8105 0.137734
43.0261 0.139119
EOD
$s2 << EOD
8.0331 0.161231
7.5143 0.0896919
7.6008 0.131939
7.9248 0.0736154
8.3203 0.0503976
8.1107 0.0503976
EOD
$s3 << EOD
32.7133 0.00505943
96.1279 0.00243065
272.689 0.00140252
693.735 0.00078051
EOD
$s4 << EOD
12.0925 0.0130344
20.4711 0.00852969
36.9684 0.00443996
79.4543 0.00258889
250.103 0.00148263
EOD
$s5 << EOD
7.7157 0.0216858
10.8422 0.0165672
10.8446 0.0130048
8.6282 0.0123042
12.1243 0.0111702
11.828 0.0105947
17.4966 0.0099014
18.4327 0.00975476
13.3014 0.0247825
12.3493 0.0171165
19.5855 0.0146162
22.1351 0.0111537
32.0861 0.00981042
28.8299 0.00875318
58.6272 0.00851666
60.8911 0.00834828
103.873 0.0100301
114.228 0.00847573
213.74 0.00796881
222.268 0.00791916
EOD
$s6 << EOD
15.472 0.0146163
18.3769 0.0111644
17.769 0.0098104
22.0681 0.00875323
28.3701 0.00851556
27.8613 0.00834767
EOD
$s7 << EOD
11.1865 0.0146174
12.1935 0.0111504
14.8804 0.00981129
13.9763 0.00875385
18.7737 0.00851586
19.94 0.00834971
EOD
$s8 << EOD
36.214 0.49956
110.972 0.498678
33.4764 0.0244609
109.525 0.0100301
EOD
$s9 << EOD
24.9839 0.0388354
19.2585 0.00965177
17.8624 0.0146162
17.9552 0.0111537
19.3984 0.045687
20.6133 0.0488272
EOD
$s10 << EOD
30.6916 0.00944888
30.6696 0.00964138
32.7373 0.00981042
34.3373 0.00979311
EOD
$s11 << EOD
19.0261 0.0146162
28.7138 0.00981042
20.6227 0.0113262
35.6382 0.00866862
EOD
$front << EOD
5.8295 0.11009
6.8171 0.11009
7.5143 0.0896919
7.7157 0.0216858
8.6282 0.0123042
11.828 0.0105947
13.9763 0.00875385
18.7737 0.00851586
19.94 0.00834971
27.8613 0.00834767
32.7133 0.00505943
36.9684 0.00443996
79.4543 0.00258889
96.1279 0.00243065
250.103 0.00148263
272.689 0.00140252
693.735 0.00078051
1040.6 0.00078051
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'volumetric.png'
set logscale xy
set grid
set key outside right top
set xrange [3.88633:1040.6]
set yrange [0.000390255:0.99912]
set xtics ('5' 5, '10' 10, '20' 20, '50' 50, '100' 100, '200' 200, '500' 500, '1000' 1000)
set ytics ('0.001' 0.001, '0.01' 0.01, '0.1' 0.1)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Volumetric lighting\nAMD EPYC, 2 cores; backend cl, cpu, gl; load average 1.35 1.52 3.06 at the start, 1.55 1.52 2.93 at the end;\n2026-11-28 23:04 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'screen_samples_gl_dir_hom', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'screen_samples_cpu_dir_hom', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'screen_decay_gl_dir_hom', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'polygonal_shadow_gl_dir_hom', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'polygonal_mesh_gl_dir_hom', \
     $s5 using 1:2 with points pt 4 ps 1.6 lw 1.5 lc rgb '#17becf' title 'froxel_grid_gl_dir_hom', \
     $s6 using 1:2 with points pt 6 ps 1.6 lw 1.5 lc rgb '#8c564b' title 'froxel_grid_cl_dir_hom', \
     $s7 using 1:2 with points pt 8 ps 1.6 lw 1.5 lc rgb '#e377c2' title 'froxel_grid_cpu_dir_hom', \
     $s8 using 1:2 with points pt 10 ps 1.6 lw 1.5 lc rgb '#7f7f7f' title 'froxel_accumulation_gl_dir_hom', \
     $s9 using 1:2 with points pt 12 ps 1.6 lw 1.5 lc rgb '#bcbd22' title 'froxel_znear_gl_dir_hom', \
     $s10 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#d62728' title 'froxel_shadow_gl_dir_hom', \
     $s11 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'froxel_temporal_gl_dir_hom', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
