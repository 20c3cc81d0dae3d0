# sweep.gp: the plot of `usm sweep --plot PREFIX`, a static script
# (share/usm/plots/sweep.gp).  usm writes PREFIX.gp: the values below, then
# this text; `gnuplot PREFIX.gp` re-plots.
#   prefix   output prefix: reads PREFIX.csv, writes PREFIX.png and PREFIX.svg
#   xcol     the swept parameter's column, e.g. 'T [N m]' (the first column)
#   events   the sweep's events, names as a word list ('stall friction_saturation')
#   event_x  their values of the swept parameter, a word list of numbers
# Columns by name (docs/cli.md, "CSV files"); empty fields (no solution) are
# left out.  Top: the rotor speed in the driving direction, w_R = -phidot_R
# (the torque-speed curve when xcol is T), circles where the solution is
# unstable; bottom: the tilt.  Each event is a dashed line labelled with its
# name.  The speed axis is clipped to the part of the branch before a
# friction saturation, where the slip model's speed diverges: the divergence
# is marked by its event line, not drawn to its end.
if (!exists("csv")) csv = prefix.'.csv'
if (!exists("events")) events = ''
if (!exists("event_x")) event_x = ''
# the display units of the CSV's columns (usm --units; SI when not given)
if (!exists("speed_unit")) speed_unit = '1/s'
if (!exists("angle_unit")) angle_unit = 'rad'
set datafile separator ','
# the first line names the columns (columns are read by name, through variables)
set datafile columnheaders
set encoding utf8
set grid lc rgb '#dddddd'
w = 'rotor_speed ['.speed_unit.']'
x(c) = column(xcol)
speed(c) = -column(w)
unstable(c) = column('max_modulus [1]') > 1 ? speed(0) : NaN
# full weight where the model describes the motor (column valid: the stick
# model up to the stick limit, the contact closed), thin grey elsewhere
ok(v) = strcol('valid') eq 'true' ? v : NaN
# the range of the solutions; the friction saturation, where the speed diverges
stats csv using (x(0)):(speed(0)) nooutput
xlo = STATS_min_x; xhi = STATS_max_x; dlo = STATS_min_y; dhi = STATS_max_y
sat = NaN
do for [i = 1:words(events)] { if (word(events, i) eq 'friction_saturation') { sat = real(word(event_x, i)) } }
# the speed axis from the first 80 % of the branch before the saturation,
# with room on either side; never beyond the data
core = sat == sat ? xlo + 0.8 * (sat - xlo) : xhi
stats csv using (x(0) <= core ? x(0) : NaN):(speed(0)) nooutput
ylo = STATS_min_y; yhi = STATS_max_y
span = yhi - ylo > 0 ? yhi - ylo : (abs(yhi) > 0 ? abs(yhi) : 1)
ymin = dlo - 0.05 * span > ylo - 0.6 * span ? dlo - 0.05 * span : ylo - 0.6 * span
ymax = dhi + 0.05 * span < yhi + 0.6 * span ? dhi + 0.05 * span : yhi + 0.6 * span
if (sat == sat && sat > xhi) { xhi = sat }
xpad = xhi > xlo ? 0.02 * (xhi - xlo) : 1
set xrange [xlo:xhi + xpad]
# the events: dashed lines, labelled with their names at the top
do for [i = 1:words(events)] {
  ex = real(word(event_x, i)); en = word(events, i)
  ecol = en eq 'friction_saturation' ? '#c0392b' : '#555555'
  etext = en eq 'friction_saturation' ? 'friction_saturation: speed diverges' : en
  set arrow (100 + i) from ex, graph 0 to ex, graph 1 nohead dt 2 lw 1.2 lc rgb ecol front
  set label (100 + i) etext at ex, graph 0.98 rotate by 90 right offset -0.7, 0 font ',9' tc rgb ecol front
}
set xlabel xcol noenhanced
set format y '%g'
set key below horizontal Left reverse nobox height 1.5
set lmargin 12
do for [fmt in 'png svg'] {
  if (fmt eq 'png') {
    set terminal pngcairo size 900,860 noenhanced font 'DejaVu Sans,11'
  } else {
    set terminal svg size 900,860 dynamic noenhanced font 'DejaVu Sans,11'
  }
  set output prefix.'.'.fmt
  set multiplot layout 2,1 title 'usm sweep: '.csv
  set ylabel 'rotor speed w_R ['.speed_unit.']'
  set yrange [ymin:ymax]
  plot csv using (x(0)):(speed(0)) with linespoints lw 0.8 pt 7 ps 0.2 lc rgb '#aaaaaa' title 'not valid (stick not admissible, contact open)', \
       csv using (x(0)):(ok(speed(0))) with linespoints lw 2 pt 7 ps 0.4 lc rgb '#1f5fa8' title 'rotor speed in the driving direction, w_R = -phidot_R', \
       csv using (x(0)):(unstable(0)) with points pt 6 ps 1 lc rgb '#ff8c00' title 'unstable (max |lambda| > 1)'
  set ylabel 'tilt theta ['.angle_unit.']'
  set autoscale y
  plot csv using (x(0)):(column('theta ['.angle_unit.']')) with linespoints lw 0.8 pt 7 ps 0.2 lc rgb '#aaaaaa' notitle, \
       csv using (x(0)):(ok(column('theta ['.angle_unit.']'))) with linespoints lw 2 pt 7 ps 0.4 lc rgb '#2e8b57' title 'theta'
  unset multiplot
  unset output
}
