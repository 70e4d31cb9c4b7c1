# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "dam_break_fixed_step: surge front, mean relative error vs Martin & Moyce (6 failed: study.csv)" noenhanced
set xlabel "seconds (simulation)" noenhanced
set ylabel "surge front error" noenhanced
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
19.5303 0.067363 "2.5e-05"
9.94256 0.0679415 "5e-05"
5.04213 0.0676921 "0.0001"
3.40202 0.0683017 "0.00015"
2.60611 0.068874 "0.0002"
EOD
$series1 << EOD
2.60611 0.1 ""
19.5303 0.1 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "fixed step (s)" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.1" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
