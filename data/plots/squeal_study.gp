# squeal_study.gp: the plot of `usm squeal --plot PREFIX`, a static script
# (share/usm/plots/squeal_study.gp).  usm writes PREFIX.gp: the values below,
# then this text; `gnuplot PREFIX.gp` re-plots.
#   prefix   output prefix: reads PREFIX.csv, writes PREFIX.png and PREFIX.svg
#   xcol     the varied parameter's column, e.g. 'mode_split [1]' (the first)
# PREFIX.csv (usm_squeal_write_plot_csv): the stroboscopic samples (k, rotor
# speed, tilt) and the audible lines (frequency, level) of every value, each
# row one or the other (the other's fields empty).  Top: the bifurcation
# diagram, the rotor speed once a period in the driving direction; middle: the
# tilt once a period; bottom: the audible lines of the stator rim's axial
# velocity, frequency over the parameter, coloured by level (dB re 1 nm/s).
if (!exists("csv")) csv = prefix.'.csv'
set datafile separator ','
set datafile columnheaders
set encoding utf8
set grid lc rgb '#dddddd'
x(c) = column(1)
set xlabel xcol noenhanced
set format y '%g'
set lmargin 12
set offsets graph 0.03, graph 0.03, 0, 0
do for [fmt in 'png svg'] {
  if (fmt eq 'png') {
    if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {
      set terminal pngcairo size 1000,1100 noenhanced
    } else {
      set terminal png size 1000,1100 noenhanced
    }
  } else {
    set terminal svg size 1000,1100 noenhanced
  }
  set output prefix.'.'.fmt
  set multiplot layout 3,1 title 'usm squeal: the motion once a period, and its audible lines'
  set ylabel 'rotor speed (driving) [1/s]'
  plot csv using (x(0)):(-column('rotor_speed [1/s]')) with points pt 7 ps 0.3 lc rgb '#08306b' notitle
  set ylabel 'tilt [rad]'
  plot csv using (x(0)):(column('theta [rad]')) with points pt 7 ps 0.3 lc rgb '#08306b' notitle
  set ylabel 'audible line [kHz]'
  set cblabel 'level [dB re 1 nm/s]'
  set yrange [0:20]
  plot csv using (x(0)):(column('frequency [Hz]') * 1e-3):(column('level_db [dB]')) with points pt 5 ps 1.2 lc palette notitle
  unset yrange
  unset multiplot
  set output
}
