# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "dam_break_cfl: surge front, mean relative error vs Martin & Moyce" noenhanced
set xlabel "seconds (simulation)" noenhanced
set ylabel "surge front error" noenhanced
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
18.522 0.0678861 "0.1"
9.52913 0.0676437 "0.2"
6.41927 0.0679985 "0.3"
4.9403 0.0674926 "0.4"
3.3012 0.0684149 "0.6"
2.49949 0.0691138 "0.8"
1.99628 0.0699254 "1.0"
EOD
$series1 << EOD
1.99628 0.1 ""
18.522 0.1 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "cfl" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.1" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
