# written by tools/accuracy/accuracy.py: Texture filtering, error against time
$s0 << EOD
7.0985 0.246552
5.5266 0.202955
12.0502 0.069399
EOD
$s1 << EOD
1.7368 0.069399
147.895 0.0413771
213.291 0.0413771
159.593 0.0413771
167.003 0.0413771
EOD
$front << EOD
1.7368 0.069399
147.895 0.0413771
319.937 0.0413771
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'textures.png'
set logscale xy
set grid
set key outside right top
set xrange [1.15787:319.937]
set yrange [0.005:0.493103]
set xtics ('2' 2, '5' 5, '10' 10, '20' 20, '50' 50, '100' 100, '200' 200)
set ytics ('0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Texture filtering\nAMD EPYC, 2 cores; backend gl; load average 21.39 20.25 19.20 at the start, 21.43 20.58 19.41 at the end;\n2026-11-29 02:44 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'textures_filter', \
     $s1 using 1:2 with points pt 7 ps 1.6 lw 1.5 lc rgb '#d62728' title 'textures_anisotropy', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
