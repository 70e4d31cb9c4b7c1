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
1.35253 0.0218046 "0.4"
1.35696 0.0142626 "0.399"
1.36608 0.0263715 "0.398"
1.35807 0.0218409 "0.397"
EOD
$series1 << EOD
1.76375 0.0400586 "0.4"
1.78793 0.0370574 "0.399"
1.77113 0.0428862 "0.398"
1.77129 0.0262461 "0.397"
EOD
$series2 << EOD
17.3707 0.060118 "0.4"
17.5689 0.0298074 "0.399"
17.1193 0.00735454 "0.398"
16.3015 0.0339452 "0.397"
EOD
$series3 << EOD
21.9462 0.0327463 "0.4"
22.3062 0.0233858 "0.399"
22.4728 0.0240307 "0.398"
21.7977 0.0407261 "0.397"
EOD
$series4 << EOD
1.24382 0.00735218 "0.4"
1.275 0.00445617 "0.399"
1.24795 0.00769698 "0.398"
1.27387 0.00774759 "0.397"
EOD
$series5 << EOD
13.9144 0.0108809 "0.4"
13.6157 0.0134582 "0.399"
13.8283 0.0122636 "0.398"
14.1141 0.0162596 "0.397"
EOD
$series6 << EOD
1.67082 0.00555063 "0.4"
1.66045 0.00852913 "0.399"
1.67196 0.00509258 "0.398"
1.66627 0.0125307 "0.397"
EOD
$series7 << EOD
17.2453 0.00663372 "0.4"
17.0592 0.00567717 "0.399"
18.348 0.0110542 "0.398"
18.0747 0.00890777 "0.397"
EOD
$series8 << EOD
1.88986 0.0175943 "0.4"
1.96852 0.0170105 "0.399"
1.88028 0.0176641 "0.398"
1.86915 0.0178701 "0.397"
EOD
$series9 << EOD
29.6667 0.0285588 "0.4"
29.3506 0.0266057 "0.399"
29.1048 0.027113 "0.398"
29.0641 0.0286384 "0.397"
EOD
$series10 << EOD
1.24382 0.02 ""
29.6667 0.02 ""
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
