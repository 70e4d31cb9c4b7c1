# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "pressure_solvers: mean compression of the fluid over the run, fraction of rho0" noenhanced
set xlabel "seconds (simulation)" noenhanced
set logscale x
set ylabel "mean density error" noenhanced
set logscale y
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
5.33157 0.000956068 "wcsph c12"
6.191 0.000700353 "wcsph c14"
6.89984 0.000538494 "wcsph c16"
8.36428 0.000344301 "wcsph c20"
15.8116 8.65284e-05 "wcsph c40"
29.7614 2.07458e-05 "wcsph c80"
54.8346 4.72218e-06 "wcsph c160"
EOD
$series1 << EOD
5.61326 0.000991004 "wcsph c12 bp"
6.48517 0.000727072 "wcsph c14 bp"
7.30323 0.000558531 "wcsph c16 bp"
9.04471 0.000358631 "wcsph c20 bp"
17.153 8.99286e-05 "wcsph c40 bp"
33.6148 2.24717e-05 "wcsph c80 bp"
EOD
$series2 << EOD
2.01678 0.000688618 "dfsph 1%"
1.97873 0.000674264 "dfsph 0.3%"
2.04161 0.000516611 "dfsph 0.1%"
2.55193 0.000380714 "dfsph 0.03%"
EOD
$series3 << EOD
1.62029 0.000782258 "dfsph 1% ww"
1.70841 0.000624561 "dfsph 0.1% ww"
EOD
$series4 << EOD
1.92339 0.000571295 "1%"
2.06044 0.000482223 "0.1%"
2.55152 0.000375419 "0.03%"
EOD
$series5 << EOD
1.62029 0.001 ""
54.8346 0.001 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "wcsph, wall weights" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "wcsph, boundary particles" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with linespoints lc 3 lw 2 pt 7 ps 1 axes x1y1 title "dfsph (jacobi)" noenhanced, \
     $series2 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series3 using 1:2 with linespoints lc 4 lw 2 pt 7 ps 1 axes x1y1 title "dfsph, wall weights" noenhanced, \
     $series3 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series4 using 1:2 with linespoints lc 5 lw 2 pt 7 ps 1 axes x1y1 title "dfsph cg" noenhanced, \
     $series4 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series5 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.001" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
