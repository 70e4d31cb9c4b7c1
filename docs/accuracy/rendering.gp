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
0.0615503 0.28724 "1"
0.0982136 0.25874 "2"
0.132104 0.236815 "4"
0.215801 0.223394 "8"
0.407435 0.215944 "16"
0.781546 0.212299 "32"
1.56105 0.209901 "64"
EOD
$series1 << EOD
0.0823242 0.177012 "1"
0.130494 0.135259 "2"
0.200096 0.11082 "4"
0.351622 0.097419 "8"
0.677919 0.0892034 "16"
1.38013 0.0839085 "32"
2.57034 0.080291 "64"
EOD
$series2 << EOD
0.0927028 0.157028 "1"
0.151565 0.112352 "2"
0.262513 0.0814752 "4"
0.460727 0.059409 "8"
0.838561 0.0436782 "16"
1.56175 0.0333489 "32"
3.00679 0.0269455 "64"
EOD
$series3 << EOD
0.0840344 0.156045 "1"
0.132479 0.110976 "2"
0.245321 0.0784843 "4"
0.473883 0.055351 "8"
0.841489 0.0392315 "16"
1.65613 0.0281067 "32"
3.63022 0.0210033 "64"
EOD
$series4 << EOD
0.0615503 0.03 ""
3.63022 0.03 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "rendering.png"
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
set output "rendering.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "rendering.pdf"
replot
unset output
