# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "effects_box_damper: simulation seconds by run and stage" noenhanced
set xlabel "run" noenhanced
set xrange [0:4]
set ylabel "seconds" noenhanced
set logscale y
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
1 0.250925 "implicit"
2 55.8197 "explicit"
EOD
$series1 << EOD
0.88 0.0374918 ""
1.88 12.129 ""
EOD
$series2 << EOD
0.84 0.034271 ""
1.84 11.3996 ""
EOD
$series3 << EOD
0.8 0.0446605 ""
1.8 14.8723 ""
EOD
$series4 << EOD
0.76 0.121443 ""
1.76 13.9431 ""
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
