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
1 10.9023 "as the scene"
2 9.52641 "telescopic density off"
3 10.1647 "muscles removed"
4 10.7394 "viscosity 0"
5 11.131 "wall weights added"
EOD
$series1 << EOD
0.88 1.84515 ""
1.88 1.81433 ""
2.88 1.74333 ""
3.88 1.81071 ""
4.88 1.91302 ""
EOD
$series2 << EOD
0.84 1.31856 ""
1.84 0 ""
2.84 1.3047 ""
3.84 1.30332 ""
4.84 1.30469 ""
EOD
$series3 << EOD
0.8 2.13949 ""
1.8 2.10178 ""
2.8 2.02955 ""
3.8 1.93288 ""
4.8 2.31322 ""
EOD
$series4 << EOD
0.76 4.67645 ""
1.76 4.68065 ""
2.76 4.61296 ""
3.76 4.6127 ""
4.76 4.60931 ""
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
