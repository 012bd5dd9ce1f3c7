# gnuplot bore165.gp (in this directory): the 0.165 m calibration run's loading and outflow.
set terminal pngcairo size 900,520
set output 'bore165.png'
set datafile separator ','
set datafile missing ''
set xlabel 'flow time [s]'
set ylabel 'loading M [kg]'
set y2label 'outflow, 20 s mean [kg/h]'
set ytics nomirror
set y2tics
set grid
set key bottom right
set title 'bore 0.165 m (the gcm250-v2 geometry), 39 rpm, 5 kg/h, from 0.30 kg: overshoot, surge, steady at 0.331 kg'
set arrow from graph 0, first 0.311 to graph 1, first 0.311 nohead dt 2 lc rgb 'gray40'
set label "paper 0.311 kg" at graph 0.02, first 0.306 tc rgb 'gray40'
plot 'bore165.csv' u 1:2 w l lw 2 t 'M', '' u 1:5 w l lw 1 t 'M in cells > half powder', \
     '' u 1:6 w l lw 1 lc rgb 'orange' t 'outflow (right)' axes x1y2
