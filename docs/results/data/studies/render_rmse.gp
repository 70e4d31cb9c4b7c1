# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "render_rmse: RMSE vs reference (sRGB)" noenhanced
set xlabel "seconds (rendering)" noenhanced
set logscale x
set ylabel "RMSE (sRGB)" noenhanced
set logscale y
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
0.0393681 0.174508 "1 spp"
0.0676659 0.119762 "4 spp"
0.220489 0.0723709 "16 spp"
0.811212 0.0455872 "64 spp"
EOD
$series1 << EOD
0.0395627 0.106752 "1 spp"
0.100735 0.0630136 "4 spp"
0.346215 0.0350473 "16 spp"
1.29987 0.0182509 "64 spp"
EOD
$series2 << EOD
0.114135 0.0252371 "4 spp"
0.372365 0.0133977 "16 spp"
EOD
$series3 << EOD
0.653809 0.0387095 "0.1 (4-64)"
3.83993 0.0184917 "0.05 (8-256)"
EOD
$series4 << EOD
0.0336526 0.0717905 "1 spp, 4 sky"
0.0822792 0.0447737 "4 spp, 4 sky"
0.170116 0.0446108 "4 spp, 16 sky"
EOD
$series5 << EOD
0.0336526 0.03 ""
3.83993 0.03 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "today: sky by BSDF, no split" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with linespoints lc 2 lw 2 pt 7 ps 1 axes x1y1 title "path MIS + split" noenhanced, \
     $series1 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series2 using 1:2 with linespoints lc 3 lw 2 pt 7 ps 1 axes x1y1 title "path MIS + split + denoiser" noenhanced, \
     $series2 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series3 using 1:2 with linespoints lc 4 lw 2 pt 7 ps 1 axes x1y1 title "path, adaptive" noenhanced, \
     $series3 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series4 using 1:2 with linespoints lc 5 lw 2 pt 7 ps 1 axes x1y1 title "whitted" noenhanced, \
     $series4 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series5 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.03" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
