# written by tools/accuracy/accuracy.py: Volumetric lighting, error against time
$s0 << EOD
24.0489 0.11009
50.3213 0.131939
89.2345 0.137734
353.888 0.139119
EOD
$s1 << EOD
48.4114 0.11009
71.8167 0.131939
97.9315 0.137734
265.736 0.139119
EOD
$s2 << EOD
52.0834 0.161231
44.7101 0.0896919
50.2394 0.131939
49.9511 0.0736154
54.9746 0.0503976
49.2017 0.0503976
EOD
$s3 << EOD
198.996 0.00505945
463.317 0.00243062
997.94 0.00140268
4884.26 0.000780677
EOD
$s4 << EOD
101.372 0.0130343
142.786 0.0085297
241.898 0.00443997
1016.29 0.00258887
2126.38 0.00148267
EOD
$s5 << EOD
79.7964 0.0216858
83.991 0.0165672
19.1764 0.0130048
78.3034 0.0123042
65.4698 0.0111702
46.9178 0.0105947
114.009 0.0099014
78.1395 0.00975476
73.9826 0.0247825
111.302 0.0171165
118.729 0.0146162
132.87 0.0111537
211.051 0.00981042
234.116 0.00875318
296.005 0.00851666
449.346 0.00834828
705.07 0.0100301
920.755 0.00847573
1499.87 0.00796881
1566.14 0.00791975
EOD
$s6 << EOD
87.9119 0.0146163
75.1385 0.0111644
115.944 0.0098104
74.4651 0.00875323
143.32 0.00851556
144.893 0.00834767
EOD
$s7 << EOD
58.6664 0.0146174
65.9522 0.0111504
117.004 0.00981129
110.065 0.00875385
141.874 0.00851586
139.944 0.00834971
EOD
$s8 << EOD
231.458 0.49956
605.916 0.498678
193.303 0.0244609
800.104 0.0100301
EOD
$s9 << EOD
168.006 0.0388354
166.227 0.00965177
137.805 0.0146162
136.266 0.0111537
154.005 0.045687
132.366 0.0488272
EOD
$s10 << EOD
185.874 0.00944888
223.942 0.00964138
229.439 0.00981042
186.494 0.00979311
EOD
$s11 << EOD
135.684 0.0146162
236.405 0.00981042
133.342 0.0113262
253.662 0.00866862
EOD
$s12 << EOD
63.9885 0.520172
216.724 0.273234
812.488 0.269165
1465.95 0.128558
EOD
$front << EOD
19.1764 0.0130048
46.9178 0.0105947
74.4651 0.00875323
139.944 0.00834971
144.893 0.00834767
198.996 0.00505945
241.898 0.00443997
463.317 0.00243062
997.94 0.00140268
4884.26 0.000780677
7326.38 0.000780677
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'volumetric.png'
set logscale xy
set grid
set key outside right top
set xrange [12.7843:7326.38]
set yrange [0.000390338:1.04034]
set xtics ('20' 20, '50' 50, '100' 100, '200' 200, '500' 500, '1000' 1000, '2000' 2000, '5000' 5000)
set ytics ('0.001' 0.001, '0.01' 0.01, '0.1' 0.1, '1' 1)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Volumetric lighting\nAMD EPYC, 2 cores; backend cl, cpu, gl;\nload average 20.43 21.62 17.43 at the start, 18.30 19.90 18.79 at the end; 2026-11-29 02:28 UTC"
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
