set terminal pngcairo size 1000,700 noenhanced
set output 'histories.png'
set multiplot layout 2,1 title 'gcm250-v2, 1 cm, 39 rpm, 5 kg/h: the first pass and its continuation (10-revolution means)'
set grid
set ylabel 'M [kg]'
set key bottom right
plot 'reference.dat' u 1:2 w lp pt 7 ps 0.5 t 'reference (Avicel)', 'rho+50_mus-10.dat' u 1:2 w lp pt 7 ps 0.5 t 'rho +50%, mu_s -10%', 'rho+50_mus-32.dat' u 1:2 w lp pt 7 ps 0.5 t 'rho +50%, mu_s -32%', 0.331 w l dt 2 t 'calibrated 0.331 kg'
set xlabel 'flow time [s]'
set ylabel 'outflow [kg/h]'
set yrange [0:10]
plot 'reference.dat' u 1:3 w l t 'reference', 'rho+50_mus-10.dat' u 1:3 w l t 'rho +50%, mu_s -10%', 'rho+50_mus-32.dat' u 1:3 w l t 'rho +50%, mu_s -32%', 5 w l dt 2 t 'feed'
unset multiplot
