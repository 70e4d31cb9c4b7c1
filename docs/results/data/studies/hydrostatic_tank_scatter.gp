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
1.30631 0.0218046 "0.4"
1.31148 0.0142626 "0.399"
1.29947 0.0263715 "0.398"
1.31654 0.0218409 "0.397"
EOD
$series1 << EOD
1.69426 0.0400586 "0.4"
1.69074 0.0370574 "0.399"
1.67753 0.0428862 "0.398"
1.68512 0.0262461 "0.397"
EOD
$series2 << EOD
16.9112 0.060118 "0.4"
16.7319 0.0298074 "0.399"
16.6078 0.00735454 "0.398"
16.7508 0.0339452 "0.397"
EOD
$series3 << EOD
22.5174 0.0327463 "0.4"
23.0877 0.0233858 "0.399"
22.3927 0.0240307 "0.398"
22.188 0.0407261 "0.397"
EOD
$series4 << EOD
1.2473 0.00735218 "0.4"
1.23584 0.00445617 "0.399"
1.24204 0.00769698 "0.398"
1.25067 0.00774759 "0.397"
EOD
$series5 << EOD
14.0123 0.0108809 "0.4"
13.8327 0.0134582 "0.399"
14.0436 0.0122636 "0.398"
14.4296 0.0162596 "0.397"
EOD
$series6 << EOD
1.65929 0.00555063 "0.4"
1.62856 0.00852913 "0.399"
1.67658 0.00509258 "0.398"
1.66302 0.0125307 "0.397"
EOD
$series7 << EOD
17.7563 0.00663372 "0.4"
17.2153 0.00567717 "0.399"
18.9702 0.0110542 "0.398"
18.4808 0.00890777 "0.397"
EOD
$series8 << EOD
1.62221 0.0050689 "0.4"
1.63021 0.0169058 "0.399"
1.61613 0.0137008 "0.398"
1.58749 0.0112547 "0.397"
EOD
$series9 << EOD
17.9248 0.0114134 "0.4"
18.2049 0.00647432 "0.399"
16.8962 0.00429824 "0.398"
17.1858 0.00359615 "0.397"
EOD
$series10 << EOD
1.85337 0.0175943 "0.4"
1.84427 0.0170105 "0.399"
1.82145 0.0176641 "0.398"
1.84096 0.0178701 "0.397"
EOD
$series11 << EOD
28.8711 0.0285588 "0.4"
28.4741 0.0266057 "0.399"
28.9859 0.027113 "0.398"
29.4245 0.0286384 "0.397"
EOD
$series12 << EOD
1.23584 0.02 ""
29.4245 0.02 ""
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
     $series8 using 1:2 with linespoints lc 9 lw 2 pt 5 ps 1 axes x1y1 title "setting = 1 m, calm 0.02 corrected" noenhanced, \
     $series8 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series9 using 1:2 with linespoints lc 10 lw 2 pt 5 ps 1 axes x1y1 title "setting = 0.5 m, calm 0.02 corrected" noenhanced, \
     $series9 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series10 using 1:2 with linespoints lc 11 lw 2 pt 5 ps 1 axes x1y1 title "setting = 1 m, wcsph" noenhanced, \
     $series10 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series11 using 1:2 with linespoints lc 12 lw 2 pt 5 ps 1 axes x1y1 title "setting = 0.5 m, wcsph" noenhanced, \
     $series11 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series12 using 1:2 with lines lc rgb "#808080" lw 1 pt 5 ps 1 axes x1y1 title "accepted error 0.02" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
