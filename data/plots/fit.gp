# fit.gp: the figure of `usm fit --plot PREFIX`, a static script
# (share/usm/plots/fit.gp).  usm writes PREFIX.gp: the values below, then
# this text; `gnuplot PREFIX.gp` re-plots.
#   prefix   output prefix: reads PREFIX.csv (the residuals' CSV of --out),
#            writes PREFIX.png and PREFIX.svg
#   xcol     the condition on the x axis, e.g. 'f [Hz]' (the one with the most
#            distinct values), or 'row' when the data have no condition
# Top: the measured values with their sigmas and the model's at the estimate
# (SI, every measured output in one panel); bottom: the residuals
# (model - measured) / sigma, a flagged point (no operating point, or the
# model not valid there) drawn as a red cross.
if (!exists("csv")) csv = prefix.'.csv'
set datafile separator ','
set datafile columnheaders
set encoding utf8
do for [fmt in 'png svg'] {
  if (fmt eq 'png') {
    set terminal pngcairo size 800,720 noenhanced font 'DejaVu Sans,11'
  } else {
    set terminal svg size 800,720 dynamic noenhanced font 'DejaVu Sans,11'
  }
  set output prefix.'.'.fmt
  set multiplot layout 2,1 title 'usm fit: '.csv noenhanced
  set grid lc rgb '#dddddd'
  set key top right noenhanced
  set xlabel xcol noenhanced
  set ylabel 'measured and model [SI]' noenhanced
  plot csv using (column(xcol)):'measured':'sigma' with yerrorbars pt 7 ps 0.7 lc rgb '#1f5fa8' title 'measured +- sigma', \
       csv using (column(xcol)):'model' with points pt 6 ps 1.2 lw 2 lc rgb '#d0641e' title 'model at the estimate'
  set ylabel 'residual (model - measured) / sigma' noenhanced
  set key off
  plot 0 with lines lc rgb '#888888', \
       csv using (column(xcol)):(column('flagged') == 0 ? column('residual') : 1/0) with points pt 7 ps 0.8 lc rgb '#1f5fa8', \
       csv using (column(xcol)):(column('flagged') == 1 ? column('residual') : 1/0) with points pt 2 ps 1.5 lw 2 lc rgb '#c0392b'
  unset multiplot
  unset output
}
