# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "dam_break_dfsph_support: column height, mean relative error vs Martin & Moyce" noenhanced
set xlabel "seconds (simulation)" noenhanced
set ylabel "column height error" noenhanced
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
14.6954 0.0833948 "h 2"
24.4997 0.0589389 "h 2.5"
38.2411 0.0485193 "h 3"
90.9853 0.0500571 "h 3.5"
EOD
$series1 << EOD
37.7552 0.0507992 "h 3, nu 5e-4"
37.6028 0.0493905 "h 3, nu 7e-4"
EOD
$series2 << EOD
13.1506 0.0551659 "h 3, own step"
EOD
$series3 << EOD
11.6426 0.098798 "h 3, 4 layers"
53.9987 0.0483172 "h 3, 24 layers"
EOD
$series4 << EOD
18.6921 0.0541544 "wcsph ww, h 3"
EOD
$series5 << EOD
11.6426 0.05 ""
90.9853 0.05 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "dam_break_dfsph_support.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "dfsph, 16 layers" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "dfsph, h 3, viscosity" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with linespoints lc 3 lw 2 pt 7 ps 1 axes x1y1 title "dfsph, h 3, its own step" noenhanced, \
     $series2 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series3 using 1:2 with linespoints lc 4 lw 2 pt 7 ps 1 axes x1y1 title "dfsph, h 3, slice depth" noenhanced, \
     $series3 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series4 using 1:2 with linespoints lc 5 lw 2 pt 7 ps 1 axes x1y1 title "wcsph, wall weights" noenhanced, \
     $series4 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series5 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.05" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "dam_break_dfsph_support.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "dam_break_dfsph_support.pdf"
replot
unset output
