# written by tools/accuracy/accuracy.py: The medium's shadow on surfaces (phong), error against time
$s0 << EOD
15.6017 0.0547115
22.8471 0.0293134
24.0617 0.00941731
29.8816 0.002466
EOD
$front << EOD
15.6017 0.0547115
22.8471 0.0293134
24.0617 0.00941731
29.8816 0.002466
44.8224 0.002466
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'medium_shadow.png'
set logscale xy
set grid
set key outside right top
set xrange [10.4011:44.8224]
set yrange [0.001233:0.109423]
set xtics ('20' 20)
set ytics ('0.002' 0.002, '0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "The medium's shadow on surfaces (phong)\nAMD EPYC, 2 cores; backend gl; load average 13.83 15.29 16.71 at the start, 15.44 15.52 16.72 at the end;\n2026-11-29 09:29 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'medium_shadow_res', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
