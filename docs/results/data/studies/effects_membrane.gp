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
1 3.61257 "as the scene"
2 2.47528 "telescopic density off"
3 2.13233 "explicit damper"
4 5.69301 "viscosity 0"
5 8.65719 "wall weights added"
EOD
$series1 << EOD
0.88 0.161433 ""
1.88 0.149156 ""
2.88 0.157245 ""
3.88 0.190011 ""
4.88 0.285298 ""
EOD
$series2 << EOD
0.84 0.617922 ""
1.84 0 ""
2.84 0.600461 ""
3.84 0.730348 ""
4.84 1.00532 ""
EOD
$series3 << EOD
0.8 0.140234 ""
1.8 0.182341 ""
2.8 0.137039 ""
3.8 0.138499 ""
4.8 0.236132 ""
EOD
$series4 << EOD
0.76 2.18244 ""
1.76 1.92854 ""
2.76 0.733275 ""
3.76 2.58528 ""
4.76 3.56295 ""
EOD
$series5 << EOD
0.72 0.475162 ""
1.72 0.18717 ""
2.72 0.470593 ""
3.72 2.00448 ""
4.72 3.50242 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with points lc 1 lw 2 pt 7 ps 1.4 axes x1y1 title "total" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with points lc 2 lw 2 pt 7 ps 0.8 axes x1y1 title "density" noenhanced, \
     $series2 using 1:2 with points lc 3 lw 2 pt 7 ps 0.8 axes x1y1 title "telescopic_density" noenhanced, \
     $series3 using 1:2 with points lc 4 lw 2 pt 7 ps 0.8 axes x1y1 title "pressure_viscosity_forces" noenhanced, \
     $series4 using 1:2 with points lc 5 lw 2 pt 7 ps 0.8 axes x1y1 title "springs" noenhanced, \
     $series5 using 1:2 with points lc 6 lw 2 pt 7 ps 0.8 axes x1y1 title "collisions" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
