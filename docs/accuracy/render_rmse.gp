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
0.115393 0.221593 "today: sky by BSDF, no split, 1 spp"
0.365172 0.149435 "today: sky by BSDF, no split, 4 spp"
1.22589 0.08579 "today: sky by BSDF, no split, 16 spp"
4.58399 0.0528001 "today: sky by BSDF, no split, 64 spp"
0.187297 0.128829 "path MIS + split, 1 spp"
0.582262 0.0756934 "path MIS + split, 4 spp"
1.96582 0.0429598 "path MIS + split, 16 spp"
7.09575 0.023214 "path MIS + split, 64 spp"
0.612934 0.0648504 "path MIS + split + denoiser, 4 spp"
1.73226 0.0296221 "path MIS + split + denoiser, 16 spp"
3.08424 0.0462038 "path, adaptive 0.1 (4-64)"
18.4021 0.0242495 "path, adaptive 0.05 (8-256)"
0.157735 0.081595 "whitted, 1 spp, 4 sky"
0.318606 0.059741 "whitted, 4 spp, 4 sky"
0.506056 0.0554834 "whitted, 4 spp, 16 sky"
EOD
$series1 << EOD
0.115393 0.03 ""
18.4021 0.03 ""
EOD
set terminal pngcairo size 900,560 font "sans,11"
set output "study.png"
plot $series0 using 1:2 with linespoints lc 1 lw 2 pt 7 ps 1 axes x1y1 title "integrator" noenhanced, \
     $series0 using 1:2:3 with labels left offset 0.8,0.4 font ",9" tc rgb "#333333" axes x1y1 notitle noenhanced, \
     $series1 using 1:2 with lines lc rgb "#808080" lw 1 pt 7 ps 1 axes x1y1 title "accepted error 0.03" noenhanced
set terminal svg size 900,560 font "sans,11"
set output "study.svg"
replot
set terminal pdfcairo size 9in,5.6in font "sans,8"
set output "study.pdf"
replot
unset output
