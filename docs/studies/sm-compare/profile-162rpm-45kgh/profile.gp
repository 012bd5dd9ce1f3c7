set terminal pngcairo size 900,800 noenhanced
set output 'profile.png.tmp'
set multiplot layout 2,1
set key top right noenhanced
set grid
set ylabel 'powder per axial layer of cells [kg]'
set yrange [0:*]
plot 'profile.dat' index 0 using 1:2 with linespoints lw 2 title 'mrf-162rpm-45kgh (M 0.1198 kg)', 'profile.dat' index 1 using 1:2 with linespoints lw 2 title 'sm-162rpm-45kgh-36.5s (M 0.4876 kg)'
set xlabel 'x along the shaft, feed end at 0 [m]'
set ylabel 'top of the dense powder, z [m] (axis at 0)'
set yrange [*:*]
plot 'profile.dat' index 0 using 1:4 with linespoints lw 2 title 'mrf-162rpm-45kgh (M 0.1198 kg)', 'profile.dat' index 1 using 1:4 with linespoints lw 2 title 'sm-162rpm-45kgh-36.5s (M 0.4876 kg)'
unset multiplot
