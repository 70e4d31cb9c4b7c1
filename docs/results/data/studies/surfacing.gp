# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "surfacing: mean distance from the exact surface (m)" noenhanced
set xlabel "seconds (surfacing)" noenhanced
set logscale x
set ylabel "mean distance (m)" noenhanced
set logscale y
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
0.468932 0.0002235 "0.05"
0.0762403 0.000785383 "0.1"
0.0282083 0.00197491 "0.15"
0.0153979 0.00301272 "0.2"
0.0104616 0.00601155 "0.25"
0.00498321 0.0143702 "0.35"
0.00186007 0.0136665 "0.5"
0.00108739 0.0244821 "0.75"
0.00107377 0.222285 "1.0"
EOD
$series1 << EOD
0.661235 0.000229254 "0.05"
0.0999257 0.000839545 "0.1"
0.0396784 0.00189621 "0.15"
0.0211105 0.00383585 "0.2"
0.0145826 0.00593291 "0.25"
0.00931017 0.00981529 "0.35"
0.0039645 0.0170474 "0.5"
0.00173113 0.0630487 "0.75"
0.00114911 0.0387992 "1.0"
EOD
$series2 << EOD
0.00107377 0.02 ""
0.661235 0.02 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "surfacing.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "R (m) = 1.5" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "R (m) = 2.0" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.02" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "surfacing.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "surfacing.pdf"
replot
unset output
