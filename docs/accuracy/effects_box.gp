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
1 23.6412 "as the scene"
2 20.8678 "telescopic density off"
3 22.6152 "muscles removed"
4 22.3794 "viscosity 0"
5 24.3841 "wall weights added"
EOD
$series1 << EOD
0.88 9.36021 ""
1.88 8.97972 ""
2.88 9.10513 ""
3.88 8.2833 ""
4.88 9.22476 ""
EOD
$series2 << EOD
0.84 1.83221 ""
1.84 0 ""
2.84 1.8128 ""
3.84 1.82782 ""
4.84 1.83108 ""
EOD
$series3 << EOD
0.8 3.77855 ""
1.8 3.51733 ""
2.8 3.59935 ""
3.8 3.45339 ""
4.8 4.15798 ""
EOD
$series4 << EOD
0.76 6.41142 ""
1.76 6.16737 ""
2.76 6.41494 ""
3.76 6.49459 ""
4.76 6.73479 ""
EOD
$series5 << EOD
0.72 1.26262 ""
1.72 1.22664 ""
2.72 1.23747 ""
3.72 1.24219 ""
4.72 1.33676 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "effects_box.png"
plot $series0 using 1:2 with points lc 1 lw 2 pt 7 ps 1.4 axes x1y1 title "total" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with points lc 2 lw 2 pt 7 ps 0.8 axes x1y1 title "density" noenhanced, \
     $series2 using 1:2 with points lc 3 lw 2 pt 7 ps 0.8 axes x1y1 title "telescopic_density" noenhanced, \
     $series3 using 1:2 with points lc 4 lw 2 pt 7 ps 0.8 axes x1y1 title "pressure_viscosity_forces" noenhanced, \
     $series4 using 1:2 with points lc 5 lw 2 pt 7 ps 0.8 axes x1y1 title "springs" noenhanced, \
     $series5 using 1:2 with points lc 6 lw 2 pt 7 ps 0.8 axes x1y1 title "collisions" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "effects_box.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "effects_box.pdf"
replot
unset output
