set terminal pngcairo size 820,780 noenhanced
set output 'parity.png.tmp'
set logscale xy
set format x '%g'
set format y '%g'
set grid
set size square
set xrange [0.00505072:0.309165]
set yrange [0.00505072:0.309165]
set xlabel 'M, full run [kg]'
set ylabel 'M, model [kg] (bars: its 95% interval)'
set title "mixer-loading-kriging.json: 7 hold-out runs, mean 92.01%, max 624.20%, 95% coverage 85.71%" font ',10'
set key top left box opaque font ',9'
plot 'parity.dat' index 0 using 1:2:3:4 with yerrorbars pt 7 ps 1.3 lc rgb '#1f77b4' title 'hold-out, inside its 95% interval (6)', 'parity.dat' index 1 using 1:2:3:4 with yerrorbars pt 5 ps 1.3 lc rgb '#d62728' title 'hold-out, outside its 95% interval (1)', x with lines lw 1.5 lc rgb 'black' title 'model = full run', 1.1*x with lines dt 2 lc rgb 'dark-gray' title '±10%', 0.9*x with lines dt 2 lc rgb 'dark-gray' notitle
