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
1 3.74184 "as the scene"
2 2.54337 "telescopic density off"
3 2.29165 "explicit damper"
4 5.77932 "viscosity 0"
5 8.71556 "wall weights added"
EOD
$series1 << EOD
0.88 0.295852 ""
1.88 0.24223 ""
2.88 0.290343 ""
3.88 0.319452 ""
4.88 0.41843 ""
EOD
$series2 << EOD
0.84 0.615843 ""
1.84 0 ""
2.84 0.605295 ""
3.84 0.723407 ""
4.84 0.990542 ""
EOD
$series3 << EOD
0.8 0.1463 ""
1.8 0.192357 ""
2.8 0.144494 ""
3.8 0.137712 ""
4.8 0.221794 ""
EOD
$series4 << EOD
0.76 2.16904 ""
1.76 1.8732 ""
2.76 0.737133 ""
3.76 2.54813 ""
4.76 3.4892 ""
EOD
$series5 << EOD
0.72 0.479243 ""
1.72 0.208239 ""
2.72 0.480386 ""
3.72 2.00811 ""
4.72 3.5328 ""
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
