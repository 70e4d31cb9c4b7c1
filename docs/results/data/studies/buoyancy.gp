# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "buoyancy: |submerged fraction - specific gravity| (4 failed: study.csv)" noenhanced
set xlabel "seconds (simulation)" noenhanced
set logscale x
set ylabel "|fraction - s.g.|" noenhanced
set logscale y
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
32.5141 0.000284103 "0.375"
3.22876 0.0118687 "0.5"
0.316808 0.05 "0.75"
0.233166 0.0198653 "1.0"
EOD
$series1 << EOD
3.62922 0.0430135 "0.5"
1.18731 0.0551136 "0.75"
0.954603 0.0670034 "1.0"
EOD
$series2 << EOD
1.88619 0.0180135 "0.5"
0.613303 0.0323864 "0.75"
0.488234 0.0333333 "1.0"
EOD
$series3 << EOD
0.316802 0.0423295 "0.75"
0.251265 0.0703704 "1.0"
EOD
$series4 << EOD
0.233166 0.05 ""
32.5141 0.05 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "step = adaptive" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "step = fixed 4 ms" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with linespoints lc 3 lw 2 pt 7 ps 1 axes x1y1 title "step = fixed 8 ms" noenhanced, \
     $series2 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series3 using 1:2 with linespoints lc 4 lw 2 pt 7 ps 1 axes x1y1 title "step = fixed 16 ms" noenhanced, \
     $series3 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series4 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.05" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
