# written by tools/accuracy/accuracy.py: Texture filtering, error against time
$s0 << EOD
1.4393 0.246552
1.5914 0.202955
1.9236 0.069399
EOD
$s1 << EOD
1.8916 0.069399
17.9721 0.0413771
17.161 0.0413771
16.6691 0.0413771
17.7694 0.0413771
EOD
$front << EOD
1.4393 0.246552
1.5914 0.202955
1.8916 0.069399
16.6691 0.0413771
26.9582 0.0413771
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'textures.png'
set logscale xy
set grid
set key outside right top
set xrange [0.959533:26.9582]
set yrange [0.005:0.493103]
set xtics ('1' 1, '2' 2, '5' 5, '10' 10, '20' 20)
set ytics ('0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Texture filtering\nAMD EPYC, 2 cores; backend gl; load average 1.23 0.89 1.83 at the start, 1.12 0.88 1.81 at the end;\n2026-11-29 04:13 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'textures_filter', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'textures_anisotropy', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
