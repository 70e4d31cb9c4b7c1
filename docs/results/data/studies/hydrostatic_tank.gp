# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "hydrostatic_tank: worst interior slab's |p / (rho0 g depth) - 1|, slabs two spacings thick, averaged over the\nsamples" noenhanced
set xlabel "seconds (simulation)" noenhanced
set ylabel "worst slab pressure error" noenhanced
set logscale y
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
1.06588 0.46626 "1%"
1.29134 0.0218046 "0.1%"
3.21823 0.0120689 "0.01%"
EOD
$series1 << EOD
1.25049 0.00735218 "0.01%"
EOD
$series2 << EOD
1.68403 0.0400586 "0.1%"
1.64566 0.00555063 "divergence cg 0.01%"
4.56173 0.00490816 "0.01%"
EOD
$series3 << EOD
1.91469 0.0175943 "k20000"
3.83898 0.0112293 "k80000"
EOD
$series4 << EOD
2.39171 0.0111064 "k20000"
4.78468 0.00992768 "k80000"
EOD
$series5 << EOD
1.06588 0.02 ""
4.78468 0.02 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "dfsph" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "dfsph, divergence cg" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with linespoints lc 3 lw 2 pt 7 ps 1 axes x1y1 title "dfsph, corrected" noenhanced, \
     $series2 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series3 using 1:2 with linespoints lc 4 lw 2 pt 7 ps 1 axes x1y1 title "wcsph" noenhanced, \
     $series3 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series4 using 1:2 with linespoints lc 5 lw 2 pt 7 ps 1 axes x1y1 title "wcsph, corrected" noenhanced, \
     $series4 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series5 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.02" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
