# envelope.gp: the plot of `usm envelope --plot PREFIX`, a static script
# (share/usm/plots/envelope.gp).  usm writes PREFIX.gp: the values below,
# then this text; `gnuplot PREFIX.gp` re-plots.
#   prefix       output prefix: reads PREFIX.csv, writes PREFIX.png and .svg
#   xcol, ycol   the box's columns, e.g. 'f [Hz]' and 'F0 [N]' (as in the
#                CSV header, docs/cli.md "CSV files")
#   cells        the raster's cells a side (usm envelope --raster)
# The regions coloured by their class (the raster's cells, rows of kind
# region:CLASS), each region's class written at its sample point, the curves
# as lines coloured and named by kind, the codimension-two points as
# diamonds (docs/envelope.md).
if (!exists("csv")) csv = prefix.'.csv'
set datafile separator ','
set datafile columnheaders
set encoding utf8
stats csv using (column(xcol)):(column(ycol)) nooutput
set xrange [STATS_min_x:STATS_max_x]
set yrange [STATS_min_y:STATS_max_y]
if (!exists("cells")) cells = 120
hx = (STATS_max_x - STATS_min_x) / cells / 2
hy = (STATS_max_y - STATS_min_y) / cells / 2
set xlabel xcol noenhanced
set ylabel ycol noenhanced
is(k) = strcol('kind') eq k
starts(p) = strstrt(strcol('kind'), p) == 1
cell(k) = is('region:'.k) ? column(ycol) : NaN
line(k) = is(k) ? column(ycol) : NaN
label_of(c) = strcol('kind')[8:*]
do for [fmt in 'png svg'] {
  if (fmt eq 'png') {
    set terminal pngcairo size 900,720 noenhanced font 'DejaVu Sans,11'
  } else {
    set terminal svg size 900,720 dynamic noenhanced font 'DejaVu Sans,11'
  }
  set output prefix.'.'.fmt
  set title 'usm envelope: '.csv
  set key outside bottom center horizontal maxrows 3
  plot csv using (column(xcol)):(cell('operating_point')):(hx):(hy) with boxxyerror fillstyle solid 1.0 noborder lc rgb '#c7e9c0' title 'runs stably', \
       csv using (column(xcol)):(cell('does_not_start')):(hx):(hy) with boxxyerror fillstyle solid 1.0 noborder lc rgb '#9e9ac8' title 'does not start', \
       csv using (column(xcol)):(cell('no_stable_root')):(hx):(hy) with boxxyerror fillstyle solid 1.0 noborder lc rgb '#fcae91' title 'no stable root', \
       csv using (column(xcol)):(cell('unknown')):(hx):(hy) with boxxyerror fillstyle solid 1.0 noborder lc rgb '#f0f0f0' title 'unknown', \
       csv using (column(xcol)):(cell('no_solution')):(hx):(hy) with boxxyerror fillstyle solid 1.0 noborder lc rgb '#bdbdbd' title 'no solution', \
       csv using (column(xcol)):(line('tilt_zero')) with lines lw 2 lc rgb '#08519c' title 'tilt_zero', \
       csv using (column(xcol)):(line('fold')) with lines lw 2 lc rgb '#a50f15' title 'fold', \
       csv using (column(xcol)):(line('stick_limit')) with lines lw 2 dt 2 lc rgb '#006d2c' title 'stick_limit', \
       csv using (column(xcol)):(line('stall')) with lines lw 2 dt 3 lc rgb '#54278f' title 'stall', \
       csv using (column(xcol)):(line('stability')) with lines lw 2 lc rgb '#e6550d' title 'stability', \
       csv using (column(xcol)):(line('separation_fold')) with lines lw 2 dt 4 lc rgb '#a50f15' title 'separation_fold', \
       csv using (column(xcol)):(line('separation_stability')) with lines lw 2 dt 4 lc rgb '#e6550d' title 'separation_stability', \
       csv using (column(xcol)):(line('separation_grazing')) with lines lw 2 dt 5 lc rgb '#31a354' title 'separation_grazing', \
       csv using (column(xcol)):(starts('codim2:') ? column(ycol) : NaN) with points pt 13 ps 1.6 lc rgb '#000000' title 'codimension two', \
       csv using (column(xcol)):(starts('sample:') ? column(ycol) : NaN):(label_of(0)) with labels font ',9' notitle
  unset output
}
