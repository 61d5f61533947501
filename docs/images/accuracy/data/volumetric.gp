# written by tools/accuracy/accuracy.py: Volumetric lighting, error against time
$s0 << EOD
5.0659 0.11009
5.6003 0.131939
15.6505 0.137734
47.3016 0.139119
EOD
$s1 << EOD
6.8984 0.11009
8.484 0.131939
13.0183 0.137734
42.0943 0.139119
EOD
$s2 << EOD
7.1862 0.161231
6.974 0.0896919
6.6423 0.131939
7.5771 0.0736154
7.6214 0.0503976
7.4961 0.0503976
EOD
$s3 << EOD
35.5823 0.00505945
94.5807 0.00243062
241.805 0.00140268
768.941 0.000780677
EOD
$s4 << EOD
12.6508 0.0130343
18.9743 0.0085297
36.2263 0.00443997
98.1516 0.00258887
279.484 0.00148267
EOD
$s5 << EOD
6.354 0.0216858
6.9929 0.0165672
10.1213 0.0130048
8.9287 0.0123042
12.6826 0.0111702
13.9812 0.0105947
19.5612 0.0099014
18.7787 0.00975476
13.5989 0.0247825
13.9629 0.0171165
18.0142 0.0146162
20.1205 0.0111537
33.3257 0.00981042
31.6169 0.00875318
58.7293 0.00851666
55.5029 0.00834828
109.049 0.0100301
109.205 0.00847573
191.481 0.00796881
195.662 0.00791975
EOD
$s6 << EOD
15.7665 0.0146163
16.9247 0.0111644
18.6092 0.0098104
21.4569 0.00875323
27.1364 0.00851556
26.1017 0.00834767
EOD
$s7 << EOD
11.8999 0.0146174
14.8936 0.0111504
16.781 0.00981129
20.7049 0.00875385
23.0186 0.00851586
27.4379 0.00834971
EOD
$s8 << EOD
34.0165 0.49956
102.485 0.498678
33.4861 0.0244609
109.22 0.0100301
EOD
$s9 << EOD
17.4582 0.0388354
18.7021 0.00965177
18.6976 0.0146162
20.2908 0.0111537
19.6056 0.045687
19.4489 0.0488272
EOD
$s10 << EOD
31.3934 0.00944888
31.881 0.00964138
33.1237 0.00981042
35.14 0.00979311
EOD
$s11 << EOD
20.2081 0.0146162
33.1945 0.00981042
24.4095 0.0113262
38.4024 0.00866862
EOD
$s12 << EOD
8.8258 0.520172
28.7377 0.273234
92.43 0.269165
171.925 0.128558
EOD
$front << EOD
5.0659 0.11009
6.354 0.0216858
6.9929 0.0165672
8.9287 0.0123042
12.6826 0.0111702
13.9812 0.0105947
16.781 0.00981129
18.6092 0.0098104
18.7021 0.00965177
18.9743 0.0085297
23.0186 0.00851586
26.1017 0.00834767
35.5823 0.00505945
36.2263 0.00443997
94.5807 0.00243062
241.805 0.00140268
768.941 0.000780677
1153.41 0.000780677
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'volumetric.png'
set logscale xy
set grid
set key outside right top
set xrange [3.37727:1153.41]
set yrange [0.000390338:1.04034]
set xtics ('5' 5, '10' 10, '20' 20, '50' 50, '100' 100, '200' 200, '500' 500, '1000' 1000)
set ytics ('0.001' 0.001, '0.01' 0.01, '0.1' 0.1, '1' 1)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Volumetric lighting\nAMD EPYC, 2 cores; backend cl, cpu, gl; load average 1.44 1.12 1.79 at the start, 1.80 1.31 1.78 at the end;\n2026-11-29 04:15 UTC"
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
     $s12 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'classroom_blinds_gl', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
