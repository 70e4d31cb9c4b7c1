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
11.5629 0.000344301 "wcsph c20"
24.8859 8.65284e-05 "wcsph c40"
46.0016 2.07458e-05 "wcsph c80"
82.7093 4.72218e-06 "wcsph c160"
32.1075 9.82773e-05 "wcsph c40 bp"
54.0512 5.25438e-05 "wcsph c80 bp"
3.76474 0.000744387 "dfsph 1%"
3.36682 0.000629016 "dfsph 0.3%"
3.55058 0.000550611 "dfsph 0.1%"
4.32839 0.000439412 "dfsph 0.03%"
EOD
$series1 << EOD
3.36682 0.001 ""
82.7093 0.001 ""
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
