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
0.0272196 0.158712 "1 spp"
0.0599627 0.0788821 "4 spp"
0.193571 0.0424274 "16 spp"
0.722553 0.0284941 "64 spp"
EOD
$series1 << EOD
0.0382372 0.127274 "1 spp"
0.0965079 0.0617222 "4 spp"
0.333454 0.0316595 "16 spp"
1.28834 0.0181831 "64 spp"
EOD
$series2 << EOD
0.104903 0.0323709 "4 spp"
0.339004 0.016627 "16 spp"
EOD
$series3 << EOD
0.483478 0.0356672 "0.1 (4-64)"
2.19564 0.0183929 "0.05 (8-256)"
EOD
$series4 << EOD
0.030464 0.0977432 "1 spp, 4 sky"
0.0728884 0.078033 "4 spp, 4 sky"
0.189537 0.0774637 "4 spp, 16 sky"
EOD
$series5 << EOD
0.0272196 0.03 ""
2.19564 0.03 ""
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
