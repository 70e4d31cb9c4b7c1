# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "effects_box: simulation seconds by run and stage" noenhanced
set xlabel "run" noenhanced
set xrange [0:7]
set ylabel "seconds" noenhanced
set yrange [0:*]
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
1 13.1665 "as the scene"
2 11.7915 "telescopic density off"
3 12.6016 "muscles removed"
4 12.4709 "viscosity 0"
5 12.9504 "wall weights added"
EOD
$series1 << EOD
0.88 3.7038 ""
1.88 3.65563 ""
2.88 3.64041 ""
3.88 3.40543 ""
4.88 3.66337 ""
EOD
$series2 << EOD
0.84 1.33236 ""
1.84 0 ""
2.84 1.32953 ""
3.84 1.29315 ""
4.84 1.27648 ""
EOD
$series3 << EOD
0.8 2.37169 ""
1.8 2.3279 ""
2.8 2.27406 ""
3.8 2.09662 ""
4.8 2.45043 ""
EOD
$series4 << EOD
0.76 4.66821 ""
1.76 4.69575 ""
2.76 4.67923 ""
3.76 4.54456 ""
4.76 4.4849 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with points lc 1 lw 2 pt 7 ps 1.4 axes x1y1 title "total" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with points lc 2 lw 2 pt 7 ps 0.8 axes x1y1 title "density" noenhanced, \
     $series2 using 1:2 with points lc 3 lw 2 pt 7 ps 0.8 axes x1y1 title "telescopic_density" noenhanced, \
     $series3 using 1:2 with points lc 4 lw 2 pt 7 ps 0.8 axes x1y1 title "pressure_viscosity_forces" noenhanced, \
     $series4 using 1:2 with points lc 5 lw 2 pt 7 ps 0.8 axes x1y1 title "springs" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
