# written by tools/accuracy/accuracy.py: Volumetric lighting: multiple scattering in the reference, error against time
$s0 << EOD
1339.62 0.124468
759.316 0.124468
530.619 0.124468
788.69 0.437002
1298.73 0.263463
3208.3 0.0890739
1126.02 0.459361
1391.44 0.26931
2436.33 0.0906846
957.654 0.490156
1748.91 0.272697
2553.36 0.0910792
EOD
$front << EOD
530.619 0.124468
2436.33 0.0906846
3208.3 0.0890739
4812.45 0.0890739
EOD
set terminal pngcairo size 1000,640 noenhanced font ',10'
set output 'volumetric_scattering.png'
set logscale xy
set grid
set key outside right top
set xrange [353.746:4812.45]
set yrange [0.005:0.980312]
set xtics ('500' 500, '1000' 1000, '2000' 2000)
set ytics ('0.005' 0.005, '0.01' 0.01, '0.02' 0.02, '0.05' 0.05, '0.1' 0.1, '0.2' 0.2, '0.5' 0.5)
set xlabel 'time per frame of the timed node (ms, median)'
set ylabel 'relative RMSE against the reference'
set title "Volumetric lighting: multiple scattering in the reference\nAMD EPYC, 2 cores; backend cpu; load average 14.97 14.04 14.24 at the start, 15.10 14.49 14.39 at the end;\n2026-11-29 05:39 UTC"
plot $front using 1:2 with steps lw 2 lc rgb '#404040' title 'Pareto front', \
     $s0 using 1:2 with points pt 5 ps 1.6 lw 1.5 lc rgb '#1f77b4' title 'reference_orders', \
     0.01 with lines dt 2 lw 2 lc rgb '#c00000' title 'target 1% relative RMSE'
