set terminal pngcairo size 820,780 noenhanced
set output 'parity.png.tmp'
set logscale xy
set format x '%g'
set format y '%g'
set grid
set size square
set xrange [0.000601452:4.38818]
set yrange [0.000601452:4.38818]
set xlabel 'M, full run [kg]'
set ylabel 'M, model [kg] (bars: its 95% interval)'
set title "mixer-loading-kriging.json: 26 training runs, leave-one-out, mean 29.50%, max 118.54%, 95% coverage 92.31%" font ',10'
set key top left box opaque font ',9'
plot 'parity.dat' index 0 using 1:2:3:4 with yerrorbars pt 6 ps 1.0 lc rgb '#7f7f7f' title 'training runs, leave-one-out (26)', x with lines lw 1.5 lc rgb 'black' title 'model = full run', 1.1*x with lines dt 2 lc rgb 'dark-gray' title '±10%', 0.9*x with lines dt 2 lc rgb 'dark-gray' notitle
