# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "render_rmse: RMSE vs reference (sRGB)" noenhanced
set xlabel "seconds (rendering)" noenhanced
set logscale x
set ylabel "RMSE (sRGB)" noenhanced
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
0.0471919 0.188113 "1 spp"
0.104278 0.128909 "4 spp"
0.307685 0.0759482 "16 spp"
1.02225 0.0472399 "64 spp"
EOD
$series1 << EOD
0.0562748 0.11019 "1 spp"
0.135838 0.0649411 "4 spp"
0.440759 0.0362875 "16 spp"
1.83876 0.0189015 "64 spp"
EOD
$series2 << EOD
0.173425 0.0303098 "4 spp"
0.538009 0.020094 "16 spp"
EOD
$series3 << EOD
0.862671 0.0401768 "0.1 (4-64)"
4.17494 0.0208582 "0.05 (8-256)"
EOD
$series4 << EOD
0.0405253 0.0694632 "1 spp, 4 sky"
0.0941452 0.043244 "4 spp, 4 sky"
0.212354 0.0377942 "4 spp, 16 sky"
EOD
$series5 << EOD
0.0405253 0.03 ""
4.17494 0.03 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "render_rmse.png"
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
set output "render_rmse.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "render_rmse.pdf"
replot
unset output
