# The prefilter study's plot (tools/prefilter_study.py runs it): split-sum error against
# the Monte Carlo oracle vs prefilter wall time, log-log, one curve per roughness (n = v),
# solid with source-lod filtering (the default), dashed without.
# gnuplot -e "csv='docs/images/prefilter_study.csv'; png='docs/images/prefilter_study.png'" tools/prefilter_study.gp
set datafile separator ','
set terminal pngcairo size 900,600 font ',11'
set output png
set logscale xy
set format x '10^{%L}'
set format y '10^{%L}'
set xlabel 'prefilter wall time (s), cube face 64, 6 levels; samples per texel 16 .. 4096 along each curve'
set ylabel 'relative RMS error of the split sum vs the oracle (n = v)'
set title 'GGX prefiltering: error vs time (forest probe)'
set key outside right top
set grid
rs = '0.10 0.25 0.50 0.75 1.00'
colors = '#1b9e77 #d95f02 #7570b3 #e7298a #66a61e'
sel(mode, r) = sprintf("< awk -F, '$1==\"%s\" && $5==\"%s\" && $6==\"n=v\"' %s", mode, r, csv)
plot for [i=1:5] sel('source-lod', word(rs, i)) using 3:7 with linespoints lw 2 pt 7 \
       lc rgb word(colors, i) title sprintf('r = %s, source lod', word(rs, i)), \
     for [i=1:5] sel('no-source-lod', word(rs, i)) using 3:7 with linespoints lw 2 dt 2 pt 6 \
       lc rgb word(colors, i) title sprintf('r = %s, level 0 only', word(rs, i))
