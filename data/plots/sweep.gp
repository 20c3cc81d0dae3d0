# sweep.gp: the plot of `usm sweep --plot PREFIX`, a static script
# (share/usm/plots/sweep.gp).  usm writes PREFIX.gp: the values below, then
# this text; `gnuplot PREFIX.gp` re-plots.
#   prefix   output prefix: reads PREFIX.csv, writes PREFIX.png and PREFIX.svg
#   xcol     the swept parameter's column, e.g. 'T [N m]' (the first column)
# Columns by name (docs/cli.md, "CSV files"); empty fields (no solution) are
# left out; the event lines ("# fold at ...") are comments to gnuplot.
# Top: the rotor speed (the torque-speed curve when xcol is T), circles where
# the solution is unstable; bottom: the tilt.  Axis ranges from the data.
if (!exists("csv")) csv = prefix.'.csv'
set datafile separator ','
# the first line names the columns (columns are read by name, through variables)
set datafile columnheaders
set encoding utf8
set grid lc rgb '#dddddd'
w = 'rotor_speed [1/s]'
x(c) = column(xcol)
unstable(c) = column('max_modulus [1]') > 1 ? column(w) : NaN
# full weight where the model describes the motor (column valid: the stick
# model up to the stick limit, the contact closed), thin grey elsewhere
ok(v) = strcol('valid') eq 'true' ? v : NaN
set xlabel xcol noenhanced
set format y '%g'
do for [fmt in 'png svg'] {
  if (fmt eq 'png') {
    set terminal pngcairo size 900,800 noenhanced font 'DejaVu Sans,11'
  } else {
    set terminal svg size 900,800 dynamic noenhanced font 'DejaVu Sans,11'
  }
  set output prefix.'.'.fmt
  set multiplot layout 2,1 title 'usm sweep: '.csv
  set ylabel 'rotor speed phi_Rdot [1/s]'
  set key top right box opaque
  plot csv using (x(0)):(column(w)) with linespoints lw 0.8 pt 7 ps 0.2 lc rgb '#aaaaaa' title 'not valid (stick not admissible, contact open)', \
       csv using (x(0)):(ok(column(w))) with linespoints lw 2 pt 7 ps 0.4 lc rgb '#1f5fa8' title 'rotor speed', \
       csv using (x(0)):(unstable(0)) with points pt 6 ps 1 lc rgb '#ff8c00' title 'unstable (max |lambda| > 1)'
  set ylabel 'tilt theta [rad]'
  plot csv using (x(0)):(column('theta [rad]')) with linespoints lw 0.8 pt 7 ps 0.2 lc rgb '#aaaaaa' notitle, \
       csv using (x(0)):(ok(column('theta [rad]'))) with linespoints lw 2 pt 7 ps 0.4 lc rgb '#2e8b57' title 'theta'
  unset multiplot
  unset output
}
