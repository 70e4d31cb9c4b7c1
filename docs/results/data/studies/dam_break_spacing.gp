# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "dam_break_spacing: column height, mean relative error vs Martin & Moyce" noenhanced
set xlabel "seconds (simulation)" noenhanced
set logscale x
set ylabel "column height error" noenhanced
set logscale y
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
0.601282 0.0509565 "10"
2.16884 0.0380425 "15"
5.26755 0.038983 "20"
10.4623 0.0400927 "25"
18.1819 0.0384797 "30"
EOD
$series1 << EOD
0.666701 1.59128 "10"
2.24453 1.71713 "15"
5.29862 1.91022 "20"
10.6866 2.08949 "25"
18.3878 2.25122 "30"
EOD
$series2 << EOD
0.601282 0.1 ""
18.3878 0.1 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "walls = free_slip" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "walls = no_slip" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.1" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
