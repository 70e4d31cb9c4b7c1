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
0.0719777 0.245004 "1"
0.0984352 0.218133 "2"
0.154608 0.201636 "4"
0.264103 0.193961 "8"
0.479621 0.190853 "16"
0.912544 0.189338 "32"
1.75404 0.188557 "64"
EOD
$series1 << EOD
0.0884205 0.136957 "1"
0.130789 0.0969941 "2"
0.22183 0.0741566 "4"
0.400832 0.0622318 "8"
0.750925 0.0560588 "16"
1.42826 0.0528715 "32"
2.80728 0.0512543 "64"
EOD
$series2 << EOD
0.0995104 0.122365 "1"
0.153811 0.0838347 "2"
0.267788 0.0591899 "4"
0.513045 0.0430303 "8"
0.973245 0.0324184 "16"
1.84522 0.0256713 "32"
3.64347 0.021511 "64"
EOD
$series3 << EOD
0.0999039 0.124161 "1"
0.158181 0.0862222 "2"
0.278529 0.0606384 "4"
0.508279 0.0432984 "8"
0.962732 0.0311164 "16"
1.88459 0.0229736 "32"
3.73369 0.0172306 "64"
EOD
$series4 << EOD
0.0719777 0.03 ""
3.73369 0.03 ""
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
