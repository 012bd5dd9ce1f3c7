# gnuplot phases.gp: MRF's steady loading against the frozen rotor's angle (2 cm, 45 kg/h), with SM's
set terminal pngcairo size 1000,450 noenhanced
set output 'phases.png'
set datafile separator ','
set multiplot layout 1,2 title 'MRF (frozen rotor) loading against the paddles angle, gcm250-v2, 2 cm, 45 kg/h'
set grid
stats 'phases.csv' every ::1 using ($1==39?$4:1/0) name 'S39' nooutput
stats 'phases.csv' every ::1 using ($1==162?$4:1/0) name 'S162' nooutput
sm39 = 0.91822  # SM's steady loading at 39 rpm x 45 kg/h (the sm-compare study's methods.md)
set xlabel 'paddle phase [deg] (period 90)'
set ylabel 'M [kg]'
set xrange [-10:100]
set key bottom right
set title '39 rpm'
set yrange [0:1]
plot 'phases.csv' every ::1 using ($1==39?$3:1/0):4 with linespoints pt 7 ps 1.5 title 'MRF', \
     S39_mean with lines dt 2 lc 1 title sprintf('MRF, mean of %d angles %.3f', S39_records, S39_mean), \
     sm39 with lines lw 2 lc 3 title sprintf('SM (turning), %.3f', sm39)
set title '162 rpm'
set yrange [0:0.2]
plot 'phases.csv' every ::1 using ($1==162?$3:1/0):4 with linespoints pt 7 ps 1.5 title 'MRF', \
     S162_mean with lines dt 2 lc 1 title sprintf('MRF, mean of %d angles %.3f', S162_records, S162_mean)
unset multiplot
