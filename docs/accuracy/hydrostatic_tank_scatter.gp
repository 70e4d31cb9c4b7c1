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
1.34784 0.0218046 "0.4"
1.34643 0.0142626 "0.399"
1.34416 0.0263715 "0.398"
1.35321 0.0218409 "0.397"
EOD
$series1 << EOD
1.61189 0.0400586 "0.4"
1.60893 0.0370574 "0.399"
1.58985 0.0428862 "0.398"
1.60283 0.0262461 "0.397"
EOD
$series2 << EOD
16.9359 0.060118 "0.4"
16.9186 0.0298074 "0.399"
16.5393 0.00735454 "0.398"
16.7172 0.0339452 "0.397"
EOD
$series3 << EOD
23.2396 0.0327463 "0.4"
23.8129 0.0233858 "0.399"
23.5848 0.0240307 "0.398"
23.4615 0.0407261 "0.397"
EOD
$series4 << EOD
1.87995 0.014641 "0.4"
1.87948 0.00918911 "0.399"
1.96376 0.0105283 "0.398"
1.97917 0.00625655 "0.397"
EOD
$series5 << EOD
36.2738 0.00928181 "0.4"
38.3636 0.0149575 "0.399"
38.1641 0.0141983 "0.398"
38.9169 0.0175677 "0.397"
EOD
$series6 << EOD
2.34125 0.0042034 "0.4"
2.43045 0.00919692 "0.399"
2.33035 0.00293782 "0.398"
2.43216 0.00485503 "0.397"
EOD
$series7 << EOD
51.1771 0.0152398 "0.4"
46.1861 0.00985112 "0.399"
48.2228 0.00865199 "0.398"
53.2723 0.0048783 "0.397"
EOD
$series8 << EOD
1.98146 0.0175943 "0.4"
1.96542 0.0170105 "0.399"
1.97501 0.0176641 "0.398"
1.95905 0.0178701 "0.397"
EOD
$series9 << EOD
31.6053 0.0285588 "0.4"
31.4219 0.0266057 "0.399"
31.2765 0.027113 "0.398"
31.2098 0.0286384 "0.397"
EOD
$series10 << EOD
1.34416 0.02 ""
53.2723 0.02 ""
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
