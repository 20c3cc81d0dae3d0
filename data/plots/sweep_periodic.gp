# sweep_periodic.gp: the plot of `usm sweep --periodic --plot PREFIX`, a
# static script (share/usm/plots/sweep_periodic.gp).  usm writes PREFIX.gp:
# the values below, then this text; `gnuplot PREFIX.gp` re-plots.
#   prefix   output prefix: reads PREFIX.csv, writes PREFIX.png and PREFIX.svg
#   xcol     the swept parameter's column, e.g. 'phase_error [rad]' (the first)
#   events   the sweep's events, names as a word list ('stick_loss contact_open')
#   event_x  their values of the swept parameter, a word list of numbers
# Columns by name (docs/cli.md, "CSV files"; usm sweep --periodic); empty
# fields (no orbit) are left out.  Top: the mean rotor speed in the driving
# direction, -rotor_speed_mean, with the band of its ripple (peak to peak);
# middle: the smallest and largest normal force over the period (the contact
# opens where F_n_min reaches 0); bottom: the largest non-cyclic |lambda|.
# Each event is a dashed line labelled with its name.
if (!exists("csv")) csv = prefix.'.csv'
if (!exists("events")) events = ''
if (!exists("event_x")) event_x = ''
set datafile separator ','
# the display units of the CSV's columns (usm --units; SI when not given)
if (!exists("speed_unit")) speed_unit = '1/s'
set datafile columnheaders
set encoding utf8
set grid lc rgb '#dddddd'
x(c) = column(xcol)
speed(c) = -column('rotor_speed_mean ['.speed_unit.']')
ripple(c) = column('rotor_speed_ripple ['.speed_unit.']')
# full weight where the model describes the motor (column valid), thin grey elsewhere
ok(v) = strcol('valid') eq 'true' ? v : NaN
stats csv using (x(0)):(speed(0)) nooutput
xlo = STATS_min_x; xhi = STATS_max_x
xpad = xhi > xlo ? 0.02 * (xhi - xlo) : 1
set xrange [xlo - xpad:xhi + xpad]
do for [i = 1:words(events)] {
  ex = real(word(event_x, i)); en = word(events, i)
  set arrow (100 + i) from ex, graph 0 to ex, graph 1 nohead dt 2 lw 1.2 lc rgb '#555555' front
  set label (100 + i) en at ex, graph 0.97 rotate by 90 right offset -0.7, 0 font ',9' tc rgb '#555555' front
}
set xlabel xcol noenhanced
set format y '%g'
set key below horizontal Left reverse nobox height 1.5
set lmargin 12
set offsets 0, 0, graph 0.08, graph 0.08
do for [fmt in 'png svg'] {
  if (fmt eq 'png') {
    set terminal pngcairo size 900,1100 noenhanced font 'DejaVu Sans,11'
  } else {
    set terminal svg size 900,1100 dynamic noenhanced font 'DejaVu Sans,11'
  }
  set output prefix.'.'.fmt
  set multiplot layout 3,1 title 'usm sweep --periodic: '.csv
  set ylabel 'rotor speed w_R ['.speed_unit.']'
  plot csv using (x(0)):(speed(0) - ripple(0) / 2):(speed(0) + ripple(0) / 2) with filledcurves lc rgb '#cfe0f3' title 'ripple band (peak to peak)', \
       csv using (x(0)):(speed(0)) with linespoints lw 0.8 pt 7 ps 0.2 lc rgb '#aaaaaa' title 'not valid', \
       csv using (x(0)):(ok(speed(0))) with linespoints lw 2 pt 7 ps 0.4 lc rgb '#1f5fa8' title 'mean speed in the driving direction, -rotor_speed_mean'
  set ylabel 'normal force [N]'
  set arrow 99 from graph 0, first 0 to graph 1, first 0 nohead lc rgb '#555555' dt 3
  plot csv using (x(0)):(column('F_n_max [N]')) with lines lw 1.5 dt 4 lc rgb '#2e8b57' title 'F_n_max', \
       csv using (x(0)):(column('F_n_min [N]')) with linespoints lw 0.8 pt 7 ps 0.2 lc rgb '#aaaaaa' notitle, \
       csv using (x(0)):(ok(column('F_n_min [N]'))) with linespoints lw 2 pt 7 ps 0.4 lc rgb '#2e8b57' title 'F_n_min (the contact opens at 0)'
  unset arrow 99
  set ylabel 'largest |lambda| (non-cyclic)'
  plot csv using (x(0)):(column('max_modulus [1]')) with linespoints lw 0.8 pt 7 ps 0.2 lc rgb '#aaaaaa' notitle, \
       csv using (x(0)):(ok(column('max_modulus [1]'))) with linespoints lw 2 pt 7 ps 0.4 lc rgb '#c0392b' title 'max |lambda|'
  unset multiplot
  unset output
}
