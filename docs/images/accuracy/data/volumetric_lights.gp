# written by tools/accuracy/accuracy.py: Volumetric lighting: point and spot lights, error against time
$s0 << EOD
141.444 0.05918
194.726 0.0644299
132.774 0.0661714
447.812 0.0667072
EOD
$s1 << EOD
2119.97 0.0578999
6135.89 0.0290744
23384.7 0.0149036
70533.9 0.00785504
EOD
$s2 << EOD
1039.19 0.452815
917.095 0.452292
1329.91 0.452873
1018.55 0.453386
2558.33 0.453616
1834.74 0.453819
EOD
$s3 << EOD
978.769 0.452818
1041.82 0.452315
1308.52 0.452875
1303.9 0.453389
2466.24 0.453617
3231.01 0.45382
EOD
$s4 << EOD
1859.82 0.572505
4780 0.342783
2145.77 0.263032
4949.95 0.252213
1482.04 0.230373
5328.84 0.228381
1238.81 0.232933
7091.9 0.229848
1460.82 0.232917
10867.9 0.229838
EOD
$s5 << EOD
73.2834 0.0349457
179.031 0.0273799
221.22 0.0240554
439.934 0.0238139
EOD
$s6 << EOD
363.884 0.0121915
1510.22 0.0121915
2357.63 0.0121915
14665.8 0.0121915
EOD
$s7 << EOD
139.892 0.63946
149.96 0.639121
423.816 0.637397
436.08 0.635014
782.744 0.63661
697.494 0.634882
EOD
$s8 << EOD
185.936 0.639482
185.686 0.639123
353.916 0.637402
623.263 0.635016
1080.87 0.636612
966.597 0.634884
EOD
$front << EOD
73.2834 0.0349457
179.031 0.0273799
221.22 0.0240554
363.884 0.0121915
70533.9 0.00785504
105801 0.00785504
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'volumetric_lights.png'
set logscale xy
set grid
set key outside right top
set xrange [48.8556:105801]
set yrange [0.00392752:1.27896]
set xtics ('100' 100, '1000' 1000, '10000' 10000, '100000' 100000)
set ytics ('0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2, '0.5' 0.5, '1' 1)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Volumetric lighting: point and spot lights\nAMD EPYC, 2 cores; backend cl, cpu, gl;\nload average 24.37 24.83 18.91 at the start, 15.04 16.85 17.82 at the end; 2026-11-29 09:06 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'screen_samples_gl_point_hom', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'polygonal_shadow_gl_point_hom', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'froxel_grid_cl_point_hom', \
     $s3 using 1:2 with points pt 11 ps 1.6 lw 1.5 lc rgb '#9467bd' title 'froxel_grid_cpu_point_hom', \
     $s4 using 1:2 with points pt 13 ps 1.6 lw 1.5 lc rgb '#ff7f0e' title 'froxel_point_cpu_point_hom', \
     $s5 using 1:2 with points pt 4 ps 1.6 lw 1.5 lc rgb '#17becf' title 'screen_samples_gl_spot_hom', \
     $s6 using 1:2 with points pt 6 ps 1.6 lw 1.5 lc rgb '#8c564b' title 'polygonal_shadow_gl_spot_hom', \
     $s7 using 1:2 with points pt 8 ps 1.6 lw 1.5 lc rgb '#e377c2' title 'froxel_grid_cl_spot_hom', \
     $s8 using 1:2 with points pt 10 ps 1.6 lw 1.5 lc rgb '#7f7f7f' title 'froxel_grid_cpu_spot_hom', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
