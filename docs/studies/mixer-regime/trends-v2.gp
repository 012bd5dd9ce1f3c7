# gnuplot trends-v2.gp (in this directory): the calibrated scene gcm250-v2 (1 cm, MRF, Avicel) at
# 39, 162 and 254 rpm and 5 and 45 kg/h; each point a steady verdict of `mixload mixer` from a deposit.
# The 39 rpm x 5 kg/h point is the calibrated 0.331 kg; its 0.396 kg plateau is drawn as an open symbol.
set terminal pngcairo size 800,520
set output 'trends-v2.png'
set datafile separator ','
set logscale y
set xlabel 'impeller speed [rpm]'
set ylabel 'loading M [kg]'
set grid
set key top right
set xrange [0:280]
set title 'gcm250-v2: M falls with speed and rises with feed'
plot "< awk -F, '$2==45' trends-v2.csv | sort -t, -n -k1" u 1:3 w lp pt 7 ps 1.5 lw 2 t '45 kg/h', \
     "< awk -F, '$2==5' trends-v2.csv | sort -t, -n -k1" u 1:3 w lp pt 5 ps 1.5 lw 2 t '5 kg/h', \
     "< awk -F, '$2==5 && $1==39' trends-v2.csv" u 1:9 w p pt 4 ps 1.8 lc rgb 'gray30' t '39 rpm x 5 kg/h: the 0.396 kg plateau'
