# gnuplot histories.gp (in this directory): the Fig. 7 study `fig7c` (gcm250-v2, 1 cm, MRF, 39 rpm, 5 kg/h),
# every run started from the reference plateau's alpha at 611 s (air at rest). Columns: time [s], M [kg].
set terminal pngcairo size 900,540
set output 'histories.png'
set datafile separator ','
set xlabel 'flow time since the warm start [s]'
set ylabel 'loading M [kg]'
set grid
set key outside right
set title 'Fig. 7 variants from the 0.396 kg plateau: the reference stays, the variants move between levels'
plot 'reference.csv' u 1:2 w l lw 2 t 'reference', \
     'rho08.csv' u 1:2 w l lw 2 t 'rho x0.8', \
     'rho12.csv' u 1:2 w l lw 2 t 'rho x1.2', \
     'd12.csv' u 1:2 w l lw 2 t 'd x1.2'
