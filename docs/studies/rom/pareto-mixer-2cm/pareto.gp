set terminal pngcairo size 860,560 noenhanced
set output 'pareto.png'
set logscale xy
set grid
set format x '1e%L'
set format y '1e%L'
set xlabel 'time per answer [s] (median; full runs: core-seconds)'
set ylabel 'median |relative error| in M'
set title 'Mixer loading: time against error, 30 hold-out runs (reference drawn at 0.0001)'
set offsets graph 0.1, graph 0.3, graph 0.2, graph 0.2
set key bottom left
plot 'pareto.dat' index 0 using 1:2 with points pt 7 ps 1.5 lc 'blue' title 'methods', '' index 0 using 1:($2*$5):3 with labels font ',9' notitle, '' index 1 using 1:2 with steps lw 2 lc 'red' title 'Pareto front'
