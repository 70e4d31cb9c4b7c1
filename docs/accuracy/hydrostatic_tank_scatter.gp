# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "hydrostatic_tank_scatter: worst interior slab's |p / (rho0 g depth) - 1|, slabs two spacings thick, averaged\nover the samples" noenhanced
set xlabel "seconds (simulation)" noenhanced
set logscale x
set ylabel "worst slab pressure error" noenhanced
set logscale y
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
1.56281 0.0218046 "0.4"
1.54342 0.0142626 "0.399"
1.54625 0.0263715 "0.398"
1.54799 0.0218409 "0.397"
EOD
$series1 << EOD
1.82273 0.0400586 "0.4"
1.83258 0.0370574 "0.399"
1.82791 0.0428862 "0.398"
1.86083 0.0262461 "0.397"
EOD
$series2 << EOD
18.0016 0.060118 "0.4"
17.9134 0.0298074 "0.399"
18.2143 0.00735454 "0.398"
18.3571 0.0339452 "0.397"
EOD
$series3 << EOD
23.5273 0.0327463 "0.4"
23.6485 0.0233858 "0.399"
23.5522 0.0240307 "0.398"
23.8514 0.0407261 "0.397"
EOD
$series4 << EOD
2.03942 0.014641 "0.4"
2.03261 0.00918911 "0.399"
2.08984 0.0105283 "0.398"
2.10697 0.00625655 "0.397"
EOD
$series5 << EOD
36.6974 0.00928181 "0.4"
39.0347 0.0149575 "0.399"
37.555 0.0141983 "0.398"
38.3277 0.0175677 "0.397"
EOD
$series6 << EOD
2.52479 0.0042034 "0.4"
2.58271 0.00919692 "0.399"
2.48657 0.00293782 "0.398"
2.56201 0.00485503 "0.397"
EOD
$series7 << EOD
48.5315 0.0152398 "0.4"
44.5822 0.00985112 "0.399"
47.3783 0.00865199 "0.398"
50.135 0.0048783 "0.397"
EOD
$series8 << EOD
2.59765 0.0175943 "0.4"
2.60254 0.0170105 "0.399"
2.63881 0.0176641 "0.398"
2.66294 0.0178701 "0.397"
EOD
$series9 << EOD
41.2164 0.0285588 "0.4"
41.7135 0.0266057 "0.399"
41.2979 0.027113 "0.398"
41.4036 0.0286384 "0.397"
EOD
$series10 << EOD
1.54342 0.02 ""
50.135 0.02 ""
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
     $series4 using 1:2 with linespoints lc 5 lw 2 pt 7 ps 1 axes x1y1 title "setting = 1 m, calm" noenhanced, \
     $series4 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series5 using 1:2 with linespoints lc 6 lw 2 pt 7 ps 1 axes x1y1 title "setting = 0.5 m, calm" noenhanced, \
     $series5 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series6 using 1:2 with linespoints lc 7 lw 2 pt 7 ps 1 axes x1y1 title "setting = 1 m, calm corrected" noenhanced, \
     $series6 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series7 using 1:2 with linespoints lc 8 lw 2 pt 7 ps 1 axes x1y1 title "setting = 0.5 m, calm corrected" noenhanced, \
     $series7 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series8 using 1:2 with linespoints lc 9 lw 2 pt 5 ps 1 axes x1y1 title "setting = 1 m, wcsph" noenhanced, \
     $series8 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series9 using 1:2 with linespoints lc 10 lw 2 pt 5 ps 1 axes x1y1 title "setting = 0.5 m, wcsph" noenhanced, \
     $series9 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series10 using 1:2 with lines lc rgb "#808080" lw 1 pt 5 ps 1 axes x1y1 title "accepted error 0.02" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
