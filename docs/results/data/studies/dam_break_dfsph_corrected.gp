# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "dam_break_dfsph_corrected: column height, mean relative error vs Martin & Moyce" noenhanced
set xlabel "seconds (simulation)" noenhanced
set ylabel "column height error" noenhanced
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
81.8008 0.0468186 "0.0001"
54.1834 0.0488041 "0.00015"
43.8306 0.0449002 "0.0002"
29.5775 0.0463726 "0.0003"
EOD
$series1 << EOD
81.1468 0.0447823 "0.0001"
54.4904 0.0439567 "0.00015"
43.5671 0.0440287 "0.0002"
29.1638 0.0480129 "0.0003"
EOD
$series2 << EOD
82.5916 0.0429045 "0.0001"
53.9755 0.0478733 "0.00015"
43.7296 0.0465629 "0.0002"
31.6336 0.0459612 "0.0003"
EOD
$series3 << EOD
29.1638 0.05 ""
82.5916 0.05 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "nu = 0.0005" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "nu = 0.0006" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with linespoints lc 3 lw 2 pt 7 ps 1 axes x1y1 title "nu = 0.0007" noenhanced, \
     $series2 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series3 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.05" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
