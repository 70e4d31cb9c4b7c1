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
0.808895 23 "15"
0.753247 7 "20"
0.746168 1 "25"
0.651926 0 "30"
0.64824 0 "35"
0.774087 1 "40"
0.782247 1 "50"
0.687958 0 "70"
0.706195 0 "100"
EOD
$series1 << EOD
0.666685 81 "15"
0.648984 73 "20"
0.640388 65 "25"
0.654334 57 "30"
0.701543 48 "35"
0.643165 38 "40"
0.595547 13 "50"
0.590587 0 "70"
0.634851 0 "100"
EOD
$series2 << EOD
0.590587 0 ""
0.808895 0 ""
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
