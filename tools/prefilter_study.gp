# The prefilter study's plot (tools/prefilter_study.py runs it): split-sum error against
# the Monte Carlo oracle vs prefilter wall time, log-log, one curve per roughness, n = v.
# Left: the default n.l weighting, with source-lod filtering (solid) and reading level 0
# only (dashed). Right: the n.l Vis weighting (exact at n = v but for sampling).
# gnuplot -e "csv='docs/images/prefilter_study.csv'; png='docs/images/prefilter_study.png'" tools/prefilter_study.gp
set datafile separator ','
set terminal pngcairo size 1400,560 font ',11'
set output png
set logscale xy
set format x '10^{%L}'
set format y '10^{%L}'
set xlabel 'prefilter wall time (s); along a curve 16, 32, ..., 4096 samples per texel'
set ylabel 'relative RMS error of the split sum vs the oracle (n = v)'
set key bottom left font ',9'
set grid
set yrange [1e-3:1]
rs = '0.10 0.25 0.50 0.75 1.00'
colors = '#1b9e77 #d95f02 #7570b3 #e7298a #66a61e'
sel(mode, r) = sprintf("< awk -F, '$1==\"%s\" && $5==\"%s\" && $6==\"n=v\"' %s", mode, r, csv)
set multiplot layout 1,2
set title 'n.l weighting (default; Karis 2013, Filament)'
plot for [i=1:5] sel('source-lod', word(rs, i)) using 3:7 with linespoints lw 2 pt 7 \
       lc rgb word(colors, i) title sprintf('r = %s, source lod', word(rs, i)), \
     for [i=1:5] sel('no-source-lod', word(rs, i)) using 3:7 with linespoints lw 1 dt 2 pt 6 \
       lc rgb word(colors, i) title sprintf('r = %s, level 0 only', word(rs, i))
set title 'n.l Vis weighting (LG\_PROBE\_WEIGHT\_NOL\_VIS), source lod'
plot for [i=1:5] sel('source-lod-vis', word(rs, i)) using 3:7 with linespoints lw 2 pt 7 \
       lc rgb word(colors, i) title sprintf('r = %s', word(rs, i))
unset multiplot
