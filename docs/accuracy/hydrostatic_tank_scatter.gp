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
1.35993 0.0218046 "0.4"
1.33107 0.0142626 "0.399"
1.34619 0.0263715 "0.398"
1.34735 0.0218409 "0.397"
EOD
$series1 << EOD
1.69218 0.0400586 "0.4"
1.67852 0.0370574 "0.399"
1.65879 0.0428862 "0.398"
1.67087 0.0262461 "0.397"
EOD
$series2 << EOD
17.7013 0.060118 "0.4"
17.6384 0.0298074 "0.399"
17.4477 0.00735454 "0.398"
17.6953 0.0339452 "0.397"
EOD
$series3 << EOD
21.8004 0.0327463 "0.4"
22.315 0.0233858 "0.399"
22.1321 0.0240307 "0.398"
21.7666 0.0407261 "0.397"
EOD
$series4 << EOD
1.326 0.0082276 "0.4"
1.34709 0.0055316 "0.399"
1.34759 0.00325903 "0.398"
1.35764 0.00232636 "0.397"
EOD
$series5 << EOD
14.5874 0.017497 "0.4"
14.9754 0.017415 "0.399"
15.097 0.0151998 "0.398"
15.0703 0.0152332 "0.397"
EOD
$series6 << EOD
1.74728 0.00832909 "0.4"
1.80064 0.00504898 "0.399"
1.80213 0.00552448 "0.398"
1.7302 0.0049684 "0.397"
EOD
$series7 << EOD
18.923 0.00565654 "0.4"
19.0075 0.00900877 "0.399"
18.0775 0.00854766 "0.398"
19.4694 0.00602677 "0.397"
EOD
$series8 << EOD
1.89183 0.0175943 "0.4"
1.86884 0.0170105 "0.399"
1.86393 0.0176641 "0.398"
1.86239 0.0178701 "0.397"
EOD
$series9 << EOD
29.7871 0.0285588 "0.4"
30.1784 0.0266057 "0.399"
30.0894 0.027113 "0.398"
29.6406 0.0286384 "0.397"
EOD
$series10 << EOD
1.326 0.02 ""
30.1784 0.02 ""
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
