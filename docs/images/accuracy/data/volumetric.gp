# written by tools/accuracy/accuracy.py: Volumetric lighting, error against time
$s0 << EOD
4.5087 0.11009
4.8244 0.131939
10.5382 0.137734
34.6737 0.139119
EOD
$s1 << EOD
4.4352 0.11009
5.6091 0.131939
11.0532 0.137734
25.2201 0.139119
EOD
$s2 << EOD
4.3205 0.161231
6.0719 0.0896919
5.8852 0.131939
5.744 0.0736154
5.6363 0.0503976
5.331 0.0503976
EOD
$s3 << EOD
35.1942 0.00505943
70.17 0.00243065
184.009 0.00140252
674.179 0.00078051
EOD
$s4 << EOD
12.018 0.0130344
17.8012 0.00852969
32.587 0.00443996
94.9058 0.00258889
198.737 0.00148263
EOD
$s5 << EOD
4.9089 0.0216858
6.1286 0.0165672
8.3088 0.0130048
9.4562 0.0123042
13.9569 0.0111702
12.2272 0.0105947
18.9132 0.0099014
17.8373 0.00975476
12.6039 0.0247825
12.1383 0.0171165
19.0293 0.0146162
19.6096 0.0111537
32.8297 0.00981042
32.749 0.00875318
54.5945 0.00851666
55.1176 0.00834828
105.521 0.0100301
106.799 0.00847573
174.589 0.00796881
201.004 0.00791916
EOD
$s6 << EOD
13.3874 0.0146163
14.4433 0.0111644
14.8784 0.0098104
19.8244 0.00875323
24.8949 0.00851556
27.1198 0.00834767
EOD
$s7 << EOD
9.5369 0.0146174
9.6749 0.0111504
12.4535 0.00981129
13.1905 0.00875385
22.888 0.00851586
23.245 0.00834971
EOD
$s8 << EOD
31.0326 0.49956
102.859 0.498678
33.8878 0.0244609
111.112 0.0100301
EOD
$s9 << EOD
17.8714 0.0388354
19.5267 0.00965177
19.4437 0.0146162
19.3641 0.0111537
19.2419 0.045687
19.8593 0.0488272
EOD
$s10 << EOD
29.3049 0.00944888
31.7313 0.00964138
30.4707 0.00981042
33.9209 0.00979311
EOD
$s11 << EOD
18.7131 0.0146162
31.2407 0.00981042
19.1683 0.0113262
36.3117 0.00866862
EOD
$front << EOD
4.3205 0.161231
4.4352 0.11009
4.9089 0.0216858
6.1286 0.0165672
8.3088 0.0130048
9.4562 0.0123042
9.6749 0.0111504
12.2272 0.0105947
12.4535 0.00981129
13.1905 0.00875385
17.8012 0.00852969
22.888 0.00851586
23.245 0.00834971
27.1198 0.00834767
32.587 0.00443996
70.17 0.00243065
184.009 0.00140252
674.179 0.00078051
1011.27 0.00078051
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'volumetric.png'
set logscale xy
set grid
set key outside right top
set xrange [2.88033:1011.27]
set yrange [0.000390255:0.99912]
set xtics ('5' 5, '10' 10, '20' 20, '50' 50, '100' 100, '200' 200, '500' 500, '1000' 1000)
set ytics ('0.001' 0.001, '0.01' 0.01, '0.1' 0.1)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Volumetric lighting\nAMD EPYC, 2 cores; backend cl, cpu, gl; load average 1.24 1.36 1.93 at the start, 1.72 1.45 1.92 at the end;\n2026-11-28 23:20 UTC"
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
