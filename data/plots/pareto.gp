# pareto.gp: the figure of `usm pareto --plot PREFIX`, a static script
# (share/usm/plots/pareto.gp).  usm writes PREFIX.gp: the values below, then
# this text; `gnuplot PREFIX.gp` re-plots.
#   prefix   output prefix: reads PREFIX.csv, writes PREFIX.png and PREFIX.svg
#   xcol     the second objective's column, e.g. 'efficiency [1]' (the x axis)
#   ycol     the first objective's column, e.g. 'speed [1/s]' (the y axis)
# The non-dominated points of the front (the CSV holds no other), joined in
# order of the x axis.
if (!exists("csv")) csv = prefix.'.csv'
set datafile separator ','
set datafile columnheaders
set encoding utf8
set grid lc rgb '#dddddd'
set xlabel xcol noenhanced
set ylabel ycol noenhanced
set key top right noenhanced
do for [fmt in 'png svg'] {
  if (fmt eq 'png') {
    set terminal pngcairo size 800,560 noenhanced font 'DejaVu Sans,11'
  } else {
    set terminal svg size 800,560 dynamic noenhanced font 'DejaVu Sans,11'
  }
  set output prefix.'.'.fmt
  set title 'usm pareto: '.csv noenhanced
  plot csv using (column(xcol)):(column(ycol)) with linespoints pt 7 ps 0.8 lw 2 lc rgb '#1f5fa8' title 'Pareto front (epsilon-constraint)'
  unset output
}
