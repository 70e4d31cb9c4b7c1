# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "rendering: RMSE vs reference (sRGB)" noenhanced
set xlabel "seconds (rendering)" noenhanced
set logscale x
set ylabel "RMSE (sRGB)" noenhanced
set logscale y
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
0.0509197 0.237857 "1"
0.0546551 0.210058 "2"
0.0892871 0.192877 "4"
0.147496 0.184828 "8"
0.259485 0.181581 "16"
0.488002 0.179981 "32"
0.941788 0.179165 "64"
EOD
$series1 << EOD
0.0539496 0.134191 "1"
0.0800884 0.0950135 "2"
0.129932 0.0724075 "4"
0.222819 0.0606073 "8"
0.41749 0.0545004 "16"
0.786587 0.0513077 "32"
1.54877 0.0496603 "64"
EOD
$series2 << EOD
0.0612367 0.118811 "1"
0.0932476 0.0817611 "2"
0.153491 0.0577143 "4"
0.274287 0.0420141 "8"
0.509575 0.031614 "16"
0.997294 0.0249822 "32"
1.93605 0.0208232 "64"
EOD
$series3 << EOD
0.065062 0.120867 "1"
0.0936484 0.0845281 "2"
0.160575 0.0595811 "4"
0.289479 0.0427499 "8"
0.545861 0.0308371 "16"
1.03543 0.02279 "32"
2.10197 0.0171675 "64"
EOD
$series4 << EOD
0.0509197 0.03 ""
2.10197 0.03 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "max depth = 1" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "max depth = 2" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with linespoints lc 3 lw 2 pt 7 ps 1 axes x1y1 title "max depth = 4" noenhanced, \
     $series2 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series3 using 1:2 with linespoints lc 4 lw 2 pt 7 ps 1 axes x1y1 title "max depth = 8" noenhanced, \
     $series3 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series4 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.03" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
