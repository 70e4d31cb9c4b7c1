# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "effects_membrane: simulation seconds by run and stage" noenhanced
set xlabel "run" noenhanced
set xrange [0:7]
set ylabel "seconds" noenhanced
set yrange [0:*]
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
1 5.16906 "as the scene"
2 3.80881 "telescopic density off"
3 3.76652 "explicit damper"
4 8.24064 "viscosity 0"
5 13.7169 "wall weights added"
EOD
$series1 << EOD
0.88 0.606483 ""
1.88 0.569137 ""
2.88 0.582849 ""
3.88 0.602736 ""
4.88 0.766776 ""
EOD
$series2 << EOD
0.84 0.838005 ""
1.84 0 ""
2.84 0.821124 ""
3.84 0.998421 ""
4.84 1.36497 ""
EOD
$series3 << EOD
0.8 0.212658 ""
1.8 0.274057 ""
2.8 0.205451 ""
3.8 0.20465 ""
4.8 0.316495 ""
EOD
$series4 << EOD
0.76 2.71463 ""
1.76 2.35212 ""
2.76 1.38374 ""
3.76 3.24285 ""
4.76 4.4619 ""
EOD
$series5 << EOD
0.72 0.748941 ""
1.72 0.573897 ""
2.72 0.7292 ""
3.72 3.1275 ""
4.72 6.70361 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "effects_membrane.png"
plot $series0 using 1:2 with points lc 1 lw 2 pt 7 ps 1.4 axes x1y1 title "total" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with points lc 2 lw 2 pt 7 ps 0.8 axes x1y1 title "density" noenhanced, \
     $series2 using 1:2 with points lc 3 lw 2 pt 7 ps 0.8 axes x1y1 title "telescopic_density" noenhanced, \
     $series3 using 1:2 with points lc 4 lw 2 pt 7 ps 0.8 axes x1y1 title "pressure_viscosity_forces" noenhanced, \
     $series4 using 1:2 with points lc 5 lw 2 pt 7 ps 0.8 axes x1y1 title "springs" noenhanced, \
     $series5 using 1:2 with points lc 6 lw 2 pt 7 ps 0.8 axes x1y1 title "collisions" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "effects_membrane.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "effects_membrane.pdf"
replot
unset output
