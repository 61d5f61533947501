# written by tools/accuracy/accuracy.py: Volumetric lighting: heterogeneous media, error against time
$s0 << EOD
465.194 0.543277
555.761 0.183597
667.563 0.392085
591.911 0.100639
1472.11 0.265913
2284.03 0.0852053
EOD
$s1 << EOD
243.809 0.106712
191.023 0.0425145
157.999 0.0537447
190.84 0.0422626
585.913 0.0432982
494.003 0.0421777
EOD
$s2 << EOD
236.029 0.580885
401.668 0.57559
1271.83 0.166515
1450.01 0.127446
EOD
$front << EOD
157.999 0.0537447
190.84 0.0422626
494.003 0.0421777
3426.05 0.0421777
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'volumetric_media.png'
set logscale xy
set grid
set key outside right top
set xrange [105.333:3426.05]
set yrange [0.005:1.16177]
set xtics ('200' 200, '500' 500, '1000' 1000, '2000' 2000)
set ytics ('0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2, '0.5' 0.5, '1' 1)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Volumetric lighting: heterogeneous media\nAMD EPYC, 2 cores; backend cpu; load average 4.58 9.54 13.62 at the start, 8.85 9.27 11.92 at the end;\n2026-11-29 09:40 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'froxel_grid_cpu_dir_fbm', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'froxel_grid_cpu_dir_height', \
     $s2 using 1:2 with points pt 9 ps 1.6 lw 1.5 lc rgb '#2ca02c' title 'froxel_cloud_cpu', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
