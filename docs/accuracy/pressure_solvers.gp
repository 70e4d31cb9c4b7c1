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
3.10226 0.000956068 "wcsph c12"
3.57941 0.000700353 "wcsph c14"
4.01783 0.000538494 "wcsph c16"
4.89247 0.000344301 "wcsph c20"
9.25853 8.65284e-05 "wcsph c40"
17.6187 2.07458e-05 "wcsph c80"
32.836 4.72218e-06 "wcsph c160"
EOD
$series1 << EOD
4.67734 0.000991004 "wcsph c12 bp"
5.42196 0.000727072 "wcsph c14 bp"
6.11747 0.000558531 "wcsph c16 bp"
7.49317 0.000358631 "wcsph c20 bp"
14.3448 8.99286e-05 "wcsph c40 bp"
28.0192 2.24717e-05 "wcsph c80 bp"
EOD
$series2 << EOD
1.25056 0.000953893 "wcsph c12 cfl1"
EOD
$series3 << EOD
2.01944 0.000985112 "wcsph c12 bp cfl1"
2.28411 0.000730354 "wcsph c14 bp cfl1"
EOD
$series4 << EOD
1.79473 0.000688618 "dfsph 1%"
1.76774 0.000674264 "dfsph 0.3%"
1.84399 0.000516611 "dfsph 0.1%"
2.32659 0.000380714 "dfsph 0.03%"
EOD
$series5 << EOD
1.1949 0.001237 "dfsph 0.3% step 0.8"
1.32381 0.000893569 "dfsph 0.1% step 0.8"
1.66159 0.000728924 "dfsph 0.03% step 0.8"
EOD
$series6 << EOD
1.12519 0.00146653 "dfsph 0.1% step 1"
EOD
$series7 << EOD
1.42521 0.000782258 "dfsph 1% ww"
1.43092 0.000624561 "dfsph 0.1% ww"
EOD
$series8 << EOD
1.74531 0.000571295 "1%"
1.87106 0.000482223 "0.1%"
2.29284 0.000375419 "0.03%"
EOD
$series9 << EOD
1.12519 0.001 ""
32.836 0.001 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "wcsph, wall weights" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "wcsph, boundary particles" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with linespoints lc 3 lw 2 pt 7 ps 1 axes x1y1 title "wcsph, wall weights, cfl 1" noenhanced, \
     $series2 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series3 using 1:2 with linespoints lc 4 lw 2 pt 7 ps 1 axes x1y1 title "wcsph, boundary particles, cfl 1" noenhanced, \
     $series3 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series4 using 1:2 with linespoints lc 5 lw 2 pt 7 ps 1 axes x1y1 title "dfsph (jacobi)" noenhanced, \
     $series4 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series5 using 1:2 with linespoints lc 6 lw 2 pt 7 ps 1 axes x1y1 title "dfsph (jacobi), cfl and pressure factor 0.8" noenhanced, \
     $series5 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series6 using 1:2 with linespoints lc 7 lw 2 pt 7 ps 1 axes x1y1 title "dfsph (jacobi), cfl and pressure factor 1" noenhanced, \
     $series6 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series7 using 1:2 with linespoints lc 8 lw 2 pt 7 ps 1 axes x1y1 title "dfsph, wall weights" noenhanced, \
     $series7 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series8 using 1:2 with linespoints lc 9 lw 2 pt 5 ps 1 axes x1y1 title "dfsph cg" noenhanced, \
     $series8 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series9 using 1:2 with lines lc rgb "#808080" lw 1 pt 5 ps 1 axes x1y1 title "accepted error 0.001" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
