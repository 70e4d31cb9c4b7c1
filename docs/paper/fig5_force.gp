# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set xlabel "time in the cycle (s)" noenhanced
set xrange [0:1.5]
set ylabel "ring force per spring (N)" noenhanced
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
unset key
$series0 << EOD
0 0 ""
0.0416667 1127.19 ""
0.0833333 310.466 ""
0.125 631.769 ""
0.166667 788.057 ""
0.208333 1566.28 ""
0.25 1272.01 ""
0.291667 786.548 ""
0.333333 438.88 ""
0.375 1474.69 ""
0.416667 1180.79 ""
0.458333 0 ""
0.5 0 ""
0.541667 0 ""
0.583333 0 ""
0.625 0 ""
0.666667 0 ""
0.708333 0 ""
0.75 0 ""
0.791667 0 ""
0.833333 0 ""
0.875 0 ""
0.916667 0 ""
0.958333 0 ""
1 0 ""
1.04167 0 ""
1.08333 0 ""
1.125 0 ""
1.16667 0 ""
1.20833 0 ""
1.25 0 ""
1.29167 0 ""
1.33333 0 ""
1.375 0 ""
1.41667 0 ""
1.45833 0 ""
1.5 0 ""
EOD
$series1 << EOD
0 0 "1"
0.25 1272.01 "2"
0.5 0 "3"
0.75 0 "4"
1 0 "5"
1.25 0 "6"
EOD
set terminal pngcairo size 1640,328 font "sans,11" fontscale 1.025 linewidth 1.025 pointscale 1.025
set output "fig5_force.png"
plot $series0 using 1:2 with lines lc rgb "#b03061" lw 3 pt 7 ps 1 axes x1y1 title "" noenhanced, \
     $series1 using 1:2 with points lc rgb "#1a1a1a" lw 2 pt 7 ps 1.5 axes x1y1 title "" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced
set terminal svg size 1640,328 font "sans,11" fontscale 1.025 linewidth 1.025
set output "fig5_force.svg"
replot
set terminal pdfcairo size 16.4in,3.28in font "sans,8" fontscale 1.025 linewidth 1.025 pointscale 1.025
set output "fig5_force.pdf"
replot
unset output
