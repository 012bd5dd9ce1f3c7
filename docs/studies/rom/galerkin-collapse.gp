set terminal pngcairo size 1100,480
set output 'galerkin-collapse.png'
set grid
set multiplot layout 1,2 title 'POD-Galerkin collapse (dashed) against the full run (solid)'
set xlabel 't / t*'
set ylabel 'L* = (L - Li) / Li'
set key bottom right font ',8'
plot 'galerkin-collapse.0.dat' u 1:3 w l lw 2 lc 1 t 'full, mu_s 1, I0 0.3 (trained)', '' u 1:2 w l dt 2 lw 2 lc 1 t 'ROM', 'galerkin-collapse.1.dat' u 1:3 w l lw 2 lc 2 t 'full, mu_s 0.9, I0 0.25 (held out)', '' u 1:2 w l dt 2 lw 2 lc 2 t 'ROM', 'galerkin-collapse.2.dat' u 1:3 w l lw 2 lc 3 t 'full, mu_s 1.33, I0 0.3 (held out)', '' u 1:2 w l dt 2 lw 2 lc 3 t 'ROM'
set ylabel 'H* = H / Hi'
plot 'galerkin-collapse.0.dat' u 1:5 w l lw 2 lc 1 notitle, '' u 1:4 w l dt 2 lw 2 lc 1 notitle, 'galerkin-collapse.1.dat' u 1:5 w l lw 2 lc 2 notitle, '' u 1:4 w l dt 2 lw 2 lc 2 notitle, 'galerkin-collapse.2.dat' u 1:5 w l lw 2 lc 3 notitle, '' u 1:4 w l dt 2 lw 2 lc 3 notitle
unset multiplot
