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
3.84996 0.000956068 "wcsph c12"
4.20685 0.000700353 "wcsph c14"
4.72762 0.000538494 "wcsph c16"
5.83705 0.000344301 "wcsph c20"
11.2065 8.65284e-05 "wcsph c40"
21.2507 2.07458e-05 "wcsph c80"
40.5208 4.72218e-06 "wcsph c160"
EOD
$series1 << EOD
5.91886 0.000991004 "wcsph c12 bp"
6.75814 0.000727072 "wcsph c14 bp"
7.54083 0.000558531 "wcsph c16 bp"
9.20318 0.000358631 "wcsph c20 bp"
17.4988 8.99286e-05 "wcsph c40 bp"
34.203 2.24717e-05 "wcsph c80 bp"
EOD
$series2 << EOD
1.50945 0.000953893 "wcsph c12 cfl1"
EOD
$series3 << EOD
2.48072 0.000985112 "wcsph c12 bp cfl1"
2.78904 0.000730354 "wcsph c14 bp cfl1"
EOD
$series4 << EOD
2.32224 0.000688618 "dfsph 1%"
2.3105 0.000674264 "dfsph 0.3%"
2.40515 0.000516611 "dfsph 0.1%"
3.03479 0.000380714 "dfsph 0.03%"
EOD
$series5 << EOD
1.57535 0.001237 "dfsph 0.3% step 0.8"
1.76467 0.000893569 "dfsph 0.1% step 0.8"
2.2176 0.000728924 "dfsph 0.03% step 0.8"
EOD
$series6 << EOD
1.49546 0.00146653 "dfsph 0.1% step 1"
EOD
$series7 << EOD
1.81173 0.000782258 "dfsph 1% ww"
1.86142 0.000624561 "dfsph 0.1% ww"
EOD
$series8 << EOD
2.27361 0.000580672 "1%"
2.34173 0.000474049 "0.1%"
3.003 0.000376222 "0.03%"
EOD
$series9 << EOD
1.89761 0.0025952 "1%"
1.94455 0.00163251 "0.3%"
2.33968 0.000974169 "0.1%"
3.62761 0.000497139 "0.03%"
EOD
$series10 << EOD
1.49546 0.001 ""
40.5208 0.001 ""
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
     $series9 using 1:2 with linespoints lc 10 lw 2 pt 5 ps 1 axes x1y1 title "iisph" noenhanced, \
     $series9 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series10 using 1:2 with lines lc rgb "#808080" lw 1 pt 5 ps 1 axes x1y1 title "accepted error 0.001" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
