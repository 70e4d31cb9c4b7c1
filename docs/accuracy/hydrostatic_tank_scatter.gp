# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "hydrostatic_tank_scatter: worst interior slab's |p / (rho0 g depth) - 1|, averaged over the samples" noenhanced
set xlabel "seconds (simulation)" noenhanced
set logscale x
set ylabel "worst slab pressure error" noenhanced
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
1.76183 0.044885 "0.4"
1.77058 0.0354841 "0.399"
1.76383 0.0437927 "0.398"
1.77754 0.038297 "0.397"
EOD
$series1 << EOD
2.06532 0.033242 "0.4"
2.03409 0.0248064 "0.399"
2.04373 0.0340104 "0.398"
2.03268 0.0136417 "0.397"
EOD
$series2 << EOD
21.1378 0.0510997 "0.4"
21.4819 0.0443802 "0.399"
20.9816 0.0227461 "0.398"
20.2816 0.0253875 "0.397"
EOD
$series3 << EOD
27.7271 0.0312588 "0.4"
28.6406 0.0437124 "0.399"
28.5814 0.0219353 "0.398"
27.5698 0.0407327 "0.397"
EOD
$series4 << EOD
1.76183 0.02 ""
28.6406 0.02 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "setting = 1 m" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "setting = 1 m, corrected" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with linespoints lc 3 lw 2 pt 7 ps 1 axes x1y1 title "setting = 0.5 m" noenhanced, \
     $series2 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series3 using 1:2 with linespoints lc 4 lw 2 pt 7 ps 1 axes x1y1 title "setting = 0.5 m, corrected" noenhanced, \
     $series3 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series4 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.02" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
