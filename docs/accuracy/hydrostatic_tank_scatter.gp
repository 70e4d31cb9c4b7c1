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
1.98821 0.0305139 "0.4"
1.94882 0.0226052 "0.399"
2.16725 0.0344521 "0.398"
2.16791 0.0296475 "0.397"
EOD
$series1 << EOD
2.38078 0.0454667 "0.4"
2.24804 0.043186 "0.399"
2.3176 0.053768 "0.398"
2.30393 0.0351262 "0.397"
EOD
$series2 << EOD
24.7864 0.0612452 "0.4"
23.7149 0.031977 "0.399"
21.4986 0.0121167 "0.398"
21.2063 0.0350227 "0.397"
EOD
$series3 << EOD
28.3915 0.0343695 "0.4"
28.646 0.0320152 "0.399"
28.278 0.0245392 "0.398"
28.0919 0.0435743 "0.397"
EOD
$series4 << EOD
2.54124 0.0158946 "0.4"
2.56188 0.0142589 "0.399"
2.64392 0.018242 "0.398"
2.65315 0.0160304 "0.397"
EOD
$series5 << EOD
43.0286 0.0104326 "0.4"
43.8432 0.0157155 "0.399"
44.7862 0.0147033 "0.398"
47.4737 0.0178997 "0.397"
EOD
$series6 << EOD
2.85233 0.0124218 "0.4"
2.95588 0.0157847 "0.399"
2.731 0.0103686 "0.398"
2.81737 0.0127832 "0.397"
EOD
$series7 << EOD
61.4944 0.022903 "0.4"
55.5631 0.0156022 "0.399"
59.1097 0.0151982 "0.398"
61.253 0.0113215 "0.397"
EOD
$series8 << EOD
2.85459 0.0216723 "0.4"
2.86103 0.0218688 "0.399"
2.90596 0.0221466 "0.398"
2.89251 0.0220324 "0.397"
EOD
$series9 << EOD
48.096 0.028903 "0.4"
47.8234 0.028655 "0.399"
47.3203 0.0285575 "0.398"
46.6619 0.0297979 "0.397"
EOD
$series10 << EOD
1.94882 0.02 ""
61.4944 0.02 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "hydrostatic_tank_scatter.png"
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
set output "hydrostatic_tank_scatter.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "hydrostatic_tank_scatter.pdf"
replot
unset output
