set terminal pngcairo size 700,600 noenhanced
set output 'fidelity.png.tmp'
set title 'fine against coarse mesh, 20 pairs'
set xlabel 'M, coarse mesh [kg]'
set ylabel 'M, fine mesh [kg]'
set key top left Left reverse
set grid
set logscale xy
plot 'fidelity.dat' using 1:2 with points pt 7 ps 1.5 title 'steady in both', exp(-0.0486722)*x**0.812587 lw 2 title sprintf('log-space fit: r2 %.2f, scatter %.2f', 0.95733, 0.245731), x dt 2 lc rgb 'gray' title 'equal'
