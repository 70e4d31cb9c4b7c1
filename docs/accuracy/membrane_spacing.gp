# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "membrane_spacing: fluid particles through the membrane" noenhanced
set xlabel "seconds (simulation)" noenhanced
set logscale x
set ylabel "particles through" noenhanced
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
17.8618 22 "0.35"
5.12945 8 "0.5"
2.00095 77 "0.7"
0.748541 0 "1.0"
EOD
$series1 << EOD
15.9364 15 "0.35"
4.07498 79 "0.5"
0.800845 85 "0.7"
0.237681 47 "1.0"
EOD
$series2 << EOD
0.237681 0 ""
17.8618 0 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "membrane_spacing.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "telescopic density = true" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "telescopic density = false" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "membrane_spacing.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "membrane_spacing.pdf"
replot
unset output
