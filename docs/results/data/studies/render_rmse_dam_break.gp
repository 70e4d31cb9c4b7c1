# kurage figure: `gnuplot THIS_FILE` redraws the PNG, SVG and PDF beside it.
set encoding utf8
reset
set title "render_rmse_dam_break: RMSE vs reference (sRGB)" noenhanced
set xlabel "seconds (rendering)" noenhanced
set logscale x
set ylabel "RMSE (sRGB)" noenhanced
set offsets graph 0.03, graph 0.12, graph 0.06, graph 0.06
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 1, lc rgb "#f0f0f0" lw 1
set key below noenhanced
$series0 << EOD
0.0247208 0.150446 "1 spp"
0.051965 0.0767352 "4 spp"
0.170559 0.0428717 "16 spp"
0.631049 0.0295135 "64 spp"
EOD
$series1 << EOD
0.0300615 0.123231 "1 spp"
0.0823328 0.0605292 "4 spp"
0.293382 0.0313199 "16 spp"
1.13217 0.018256 "64 spp"
EOD
$series2 << EOD
0.0927099 0.0325903 "4 spp"
0.317283 0.0166124 "16 spp"
EOD
$series3 << EOD
0.432653 0.0359291 "0.1 (4-64)"
2.19493 0.0183859 "0.05 (8-256)"
EOD
$series4 << EOD
0.0262612 0.0962304 "1 spp, 4 sky"
0.0646064 0.0772228 "4 spp, 4 sky"
0.160739 0.0764342 "4 spp, 16 sky"
EOD
$series5 << EOD
0.0247208 0.03 ""
2.19493 0.03 ""
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
