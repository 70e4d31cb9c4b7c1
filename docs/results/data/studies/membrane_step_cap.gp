# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "membrane_step_cap: fluid particles through the membrane" noenhanced
set xlabel "seconds (simulation)" noenhanced
set ylabel "particles through" noenhanced
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
3.69114 8 "adaptive"
10.9811 7 "fixed 2 ms"
4.4585 10 "fixed 5 ms"
2.25583 5 "fixed 10 ms"
EOD
$series1 << EOD
3.72784 8 "adaptive"
11.2179 4 "fixed 2 ms"
4.51768 5 "fixed 5 ms"
2.24742 4 "fixed 10 ms"
EOD
$series2 << EOD
3.76257 8 "adaptive"
11.4888 5 "fixed 2 ms"
4.60064 10 "fixed 5 ms"
2.30798 4 "fixed 10 ms"
EOD
$series3 << EOD
2.24742 0 ""
11.4888 0 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "collision cap = 1" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "collision cap = 4" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with linespoints lc 3 lw 2 pt 7 ps 1 axes x1y1 title "collision cap = 32" noenhanced, \
     $series2 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series3 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
