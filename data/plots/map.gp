# map.gp: the plot of `usm map --plot PREFIX`, a static script
# (share/usm/plots/map.gp).  usm writes PREFIX.gp: the values below, then
# this text; `gnuplot PREFIX.gp` re-plots.
#   prefix       output prefix: reads PREFIX.csv, writes PREFIX.png and .svg
#   xcol, ycol   the grid's columns, e.g. 'f [Hz]' and 'T [N m]' (as in the
#                CSV header, docs/cli.md "CSV files")
#   mcol         the modulus column (default 'op_max_modulus [1]': the
#                operating point's)
# Each grid point by its operating point (column op_class): the
# largest non-cyclic |lambda| of the operating point where there is one
# (op_max_modulus), and as classes of their own: no stable root (dark red),
# does not start from rest (black), unknown -- several roots and no
# --from-rest (white) -- and grey where no stationary solution exists; the
# axes span the grid's cells (from the data).
if (!exists("csv")) csv = prefix.'.csv'
if (!exists("mcol")) mcol = 'op_max_modulus [1]'
set datafile separator ','
# the first line names the columns (columns are read by name, through variables)
set datafile columnheaders
set encoding utf8
stats csv using (column(xcol)):(column(ycol)) nooutput
xmin = STATS_min_x; xmax = STATS_max_x; ymin = STATS_min_y; ymax = STATS_max_y
nx = 0
stats csv using (nx = nx + (column(ycol) == ymin), 0) nooutput
ny = STATS_records / nx
dx = nx > 1 ? (xmax - xmin) / (nx - 1) : 1; dy = ny > 1 ? (ymax - ymin) / (ny - 1) : 1
set xrange [xmin - dx / 2:xmax + dx / 2]
set yrange [ymin - dy / 2:ymax + dy / 2]
set xlabel xcol noenhanced
set ylabel ycol noenhanced
set cblabel 'largest non-cyclic |lambda| (log scale)'
set logscale cb
set cbrange [0.8:1.25]
set cbtics (0.8, 0.9, 1, 1.1, 1.25)
set palette defined (0 '#313695', 0.25 '#74add1', 0.5 '#ffffbf', 0.75 '#f46d43', 1 '#a50026')
set object 1 rectangle from graph 0,0 to graph 1,1 behind fillcolor rgb '#bdbdbd' fillstyle solid 1.0 noborder
present(c) = strcol('exists') eq 'true'
# cells where the model does not describe the motor (column valid false:
# stick not admissible, contact open): a small grey dot
invalid(c) = strcol('valid') eq 'false' ? column(ycol) : NaN
# the operating point's class (column op_class)
opc(name) = strcol('op_class') eq name
opval(c) = opc('operating_point') ? column(mcol) : NaN
klass(name) = opc(name) ? 1 : NaN
do for [fmt in 'png svg'] {
  if (fmt eq 'png') {
    set terminal pngcairo size 900,720 noenhanced font 'DejaVu Sans,11'
  } else {
    set terminal svg size 900,720 dynamic noenhanced font 'DejaVu Sans,11'
  }
  set output prefix.'.'.fmt
  set title 'usm map: '.csv.' (operating point; grey: no stationary solution; dots: model not valid)'
  set key outside bottom center horizontal
  plot csv using (column(xcol)):(column(ycol)):(opval(0)) with image notitle, \
       csv using (column(xcol)):(column(ycol) * klass('no_stable_root')):(dx / 2):(dy / 2) with boxxyerror fillstyle solid 1.0 noborder lc rgb '#67001f' title 'no stable root', \
       csv using (column(xcol)):(column(ycol) * klass('does_not_start')):(dx / 2):(dy / 2) with boxxyerror fillstyle solid 1.0 noborder lc rgb '#000000' title 'does not start from rest', \
       csv using (column(xcol)):(column(ycol) * klass('unknown')):(dx / 2):(dy / 2) with boxxyerror fillstyle solid 1.0 border lc rgb '#969696' fillcolor rgb '#ffffff' title 'unknown (several roots; --from-rest decides)', \
       csv using (column(xcol)):(invalid(0)) with points pt 7 ps 0.3 lc rgb '#555555' title 'model not valid', \
       NaN with boxes fillstyle solid 1.0 lc rgb '#bdbdbd' title 'no stationary solution'
  unset output
}
