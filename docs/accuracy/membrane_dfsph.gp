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
0.738489 34 "100"
0.699861 21 "130"
0.701492 12 "160"
0.62138 3 "200"
0.669245 0 "250"
0.740324 0 "300"
EOD
$series1 << EOD
0.582122 49 "100"
0.585104 27 "130"
0.587567 10 "160"
0.597028 1 "200"
0.567295 0 "250"
0.607956 0 "300"
EOD
$series2 << EOD
0.567295 0 ""
0.740324 0 ""
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
