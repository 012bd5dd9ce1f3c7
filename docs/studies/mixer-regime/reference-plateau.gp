# gnuplot reference-plateau.gp (in this directory): three histories of the gcm250-v2 reference point
# (Avicel, 39 rpm, 5 kg/h, 1 cm, MRF). One surged to 0.318 kg at 310 s; the other sat at 0.396-0.398 kg to 1100 s, dipped to 0.383 kg, then surged to about 0.33 kg at 1240-1330 s.
set terminal pngcairo size 900,520
set output 'reference-plateau.png'
set datafile separator ','
set xlabel 'flow time [s]'
set ylabel 'loading M [kg]'
set grid
set key bottom right
set yrange [0.28:0.42]
set xrange [0:*]
set title 'gcm250-v2 reference point, 1 cm MRF: a plateau near 0.40 kg, then surges to about 0.32-0.33 kg'
set arrow from graph 0, first 0.311 to graph 1, first 0.311 nohead dt 2 lc rgb 'gray40'
set label "paper 0.311 kg (band 0.274-0.348)" at graph 0.02, first 0.306 tc rgb 'gray40'
plot 'bore165.csv' u 1:2 w l lw 2 t 'calibration run, from 0.30 kg (surged at 310 s)', \
     'reference-plateau.csv' u 1:2 w l lw 2 t 'from 0.32 kg (2026-12-01), verdict at 611 s', \
     'reference-plateau-continued.csv' u 1:2 w l lw 2 t 'run on from it (Fig. 7 study reference)'
