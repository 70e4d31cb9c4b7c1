# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "pressure_solvers: mean compression of the fluid over the run, fraction of rho0" noenhanced
set xlabel "seconds (simulation)" noenhanced
set logscale x
set ylabel "mean density error" noenhanced
set logscale y
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
16.3196 0.000345072 "wcsph c20"
51.0015 8.64162e-05 "wcsph c40"
64.8549 2.07272e-05 "wcsph c80"
288.401 4.74245e-06 "wcsph c160"
62.7759 9.81243e-05 "wcsph c40 bp"
59.2079 5.05281e-05 "wcsph c80 bp"
4.96022 0.000731628 "dfsph 1%"
4.78854 0.000614954 "dfsph 0.3%"
4.56376 0.00054506 "dfsph 0.1%"
4.71234 0.000433913 "dfsph 0.03%"
EOD
$series1 << EOD
4.56376 0.001 ""
288.401 0.001 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "solver" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.001" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
