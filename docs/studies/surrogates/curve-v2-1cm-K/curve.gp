set terminal pngcairo size 800,520 noenhanced
set output 'curve.png.tmp'
set logscale xy
set title 'Learning curve: kriging (similarity), 14 hold-out runs'
set xlabel 'training runs'
set ylabel 'mean relative error'
set key top right
set grid
set xrange [5.33333:39]
plot 'curve.dat' using 1:2:3:4 with yerrorlines lw 2 title 'hold-out (90% bootstrap)', '' using 1:5 with linespoints dt 2 title 'leave-one-out', 0.66276*x**(-0.209867) dt 2 lw 2 lc rgb 'dark-gray' title 'power law'
