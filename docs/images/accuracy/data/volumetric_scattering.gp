# written by tools/accuracy/accuracy.py: Volumetric lighting: multiple scattering in the reference, error against time
$s0 << EOD
796.463 0.125603
835.42 0.125603
1001.97 0.125603
870.644 0.430138
1081.83 0.242926
2374.21 0.0891702
806.636 0.462242
1352.76 0.253908
3143.24 0.0917083
848.39 0.49394
1304.11 0.258177
3383.82 0.0925723
EOD
$front << EOD
796.463 0.125603
2374.21 0.0891702
5075.72 0.0891702
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'volumetric_scattering.png'
set logscale xy
set grid
set key outside right top
set xrange [530.975:5075.72]
set yrange [0.005:0.98788]
set xtics ('1000' 1000, '2000' 2000, '5000' 5000)
set ytics ('0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2, '0.5' 0.5)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Volumetric lighting: multiple scattering in the reference\nAMD EPYC, 2 cores; backend cpu; load average 10.44 12.16 13.39 at the start, 13.93 12.78 13.51 at the end;\n2026-11-29 05:46 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'reference_orders', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
