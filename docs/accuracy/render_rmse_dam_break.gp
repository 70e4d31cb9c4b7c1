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
0.067635 0.159778 "today: sky by BSDF, no split, 1 spp"
0.200846 0.0814271 "today: sky by BSDF, no split, 4 spp"
0.666879 0.0448731 "today: sky by BSDF, no split, 16 spp"
2.04616 0.0305391 "today: sky by BSDF, no split, 64 spp"
0.0801988 0.126421 "path MIS + split, 1 spp"
0.250404 0.0617256 "path MIS + split, 4 spp"
0.929906 0.0322056 "path MIS + split, 16 spp"
3.71027 0.0189638 "path MIS + split, 64 spp"
0.320669 0.0397912 "path MIS + split + denoiser, 4 spp"
1.08243 0.0220901 "path MIS + split + denoiser, 16 spp"
1.48752 0.036178 "path, adaptive 0.1 (4-64)"
6.33166 0.0199149 "path, adaptive 0.05 (8-256)"
0.0705603 0.0978885 "whitted, 1 spp, 4 sky"
0.189391 0.0780198 "whitted, 4 spp, 4 sky"
0.505295 0.0777242 "whitted, 4 spp, 16 sky"
EOD
$series1 << EOD
0.067635 0.03 ""
6.33166 0.03 ""
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
