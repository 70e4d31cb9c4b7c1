# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "effects_dam_break: simulation seconds by run and stage" noenhanced
set xlabel "run" noenhanced
set xrange [0:7]
set ylabel "seconds" noenhanced
set yrange [0:*]
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
1 0.546954 "as the scene"
2 0.536128 "viscosity 0"
3 0.600372 "wall weights added"
4 0.573101 "monaghan1992"
5 0.66591 "monaghan1992 + gradient correction"
EOD
$series1 << EOD
0.88 0.403148 ""
1.88 0.395179 ""
2.88 0.429628 ""
3.88 0.416455 ""
4.88 0.409652 ""
EOD
$series2 << EOD
0.84 0.108156 ""
1.84 0.10258 ""
2.84 0.127973 ""
3.84 0.117943 ""
4.84 0.218733 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "effects_dam_break.png"
plot $series0 using 1:2 with points lc 1 lw 2 pt 7 ps 1.4 axes x1y1 title "total" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with points lc 2 lw 2 pt 7 ps 0.8 axes x1y1 title "density" noenhanced, \
     $series2 using 1:2 with points lc 3 lw 2 pt 7 ps 0.8 axes x1y1 title "pressure_viscosity_forces" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "effects_dam_break.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "effects_dam_break.pdf"
replot
unset output
