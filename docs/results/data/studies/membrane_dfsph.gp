# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "membrane_dfsph: fluid particles through the membrane" noenhanced
set xlabel "seconds (simulation)" noenhanced
set ylabel "particles through" noenhanced
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
0.791714 0 "10"
0.727032 3 "15"
0.682351 0 "20"
0.670278 0 "25"
0.661528 0 "30"
0.656243 0 "35"
0.645433 0 "40"
0.64445 0 "50"
0.667138 0 "70"
0.679299 0 "100"
EOD
$series1 << EOD
0.654657 85 "10"
0.676894 83 "15"
0.726257 78 "20"
0.665008 66 "25"
0.644439 58 "30"
0.642709 50 "35"
0.661279 35 "40"
0.671376 24 "50"
0.593275 0 "70"
0.596882 0 "100"
EOD
$series2 << EOD
0.593275 0 ""
0.791714 0 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "membrane = telescopic" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "membrane = conventional" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
