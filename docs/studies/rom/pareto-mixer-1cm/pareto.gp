set terminal pngcairo size 860,560 noenhanced
set output 'pareto.png'
set logscale xy
set grid
set format x '1e%L'
set format y '1e%L'
set xlabel 'time per answer [s] (median; full runs: core-seconds)'
set ylabel 'median |relative error| in M'
set title 'Mixer loading: time against error, 24 hold-out runs (reference drawn at 0.0001)'
set offsets graph 0.1, graph 0.1, graph 0.2, graph 0.5
set key inside left bottom font ',9' spacing 1.1 box opaque
plot 'pareto.dat' index 0 using 1:2 with points pt 5 ps 1.6 lc 1 title 'response surface (24) *', 'pareto.dat' index 1 using 1:2 with points pt 7 ps 1.6 lc 2 title 'kriging (loading surrogate) (24) *', 'pareto.dat' index 2 using 1:2 with points pt 9 ps 1.6 lc 3 title 'POD regression of alpha (24) *', 'pareto.dat' index 3 using 1:2 with points pt 11 ps 1.6 lc 4 title 'POD regression of ln(alpha) (24)', 'pareto.dat' index 4 using 1:2 with points pt 13 ps 1.6 lc 5 title 'reduced steady transport on the regressed U (24)', 'pareto.dat' index 5 using 1:2 with points pt 5 ps 1.6 lc 6 title 'full run, 2 cm, v2c-holdout (24)', 'pareto.dat' index 6 using 1:2 with points pt 7 ps 1.6 lc 7 title 'full run, 1.5 cm, v2m-holdout (24)', 'pareto.dat' index 7 using 1:2 with points pt 9 ps 1.6 lc 8 title 'full run, 1 cm (reference, 24) *', '' index 8 using 1:2 with steps lw 2 lc 'red' title 'Pareto front (*)'
