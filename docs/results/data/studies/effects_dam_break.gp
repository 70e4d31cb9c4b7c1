# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "effects_dam_break: simulation seconds by run and stage" noenhanced
set xlabel "run" noenhanced
set xrange [0:7]
set ylabel "seconds" noenhanced
set logscale y
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
1 0.253677 "as the scene"
2 0.266656 "viscosity 0"
3 0.289478 "wall weights added"
4 0.256966 "monaghan1992"
5 0.326396 "monaghan1992 + gradient correction"
EOD
$series1 << EOD
0.88 0.0142364 ""
1.88 0.0150423 ""
2.88 0.0139033 ""
3.88 0.0140044 ""
4.88 0.0141536 ""
EOD
$series2 << EOD
0.84 0.145051 ""
1.84 0.157062 ""
2.84 0.161681 ""
3.84 0.145304 ""
4.84 0.146829 ""
EOD
$series3 << EOD
0.8 0.0781052 ""
1.8 0.0758906 ""
2.8 0.0932821 ""
3.8 0.0808815 ""
4.8 0.148057 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with points lc 1 lw 2 pt 7 ps 1.4 axes x1y1 title "total" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with points lc 2 lw 2 pt 7 ps 0.8 axes x1y1 title "neighbour_sort" noenhanced, \
     $series2 using 1:2 with points lc 3 lw 2 pt 7 ps 0.8 axes x1y1 title "density" noenhanced, \
     $series3 using 1:2 with points lc 4 lw 2 pt 7 ps 0.8 axes x1y1 title "pressure_viscosity_forces" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
