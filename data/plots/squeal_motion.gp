# squeal_motion.gp: the report's figure of what the unilateral 4-DOF motor
# does over the mode split past its last periodic orbit (usm report, section
# "The squeal"; share/usm/plots/squeal_motion.gp).  Reads squeal_motion.csv
# (usm_squeal_write_plot_csv: each row either a stroboscopic sample, k,
# rotor speed and tilt, or an audible line, frequency and level) and writes
# squeal_motion.png and .svg.  Top: the rotor speed once a period in the
# driving direction (a periodic orbit: one dot a value, k for period k;
# irregular motion: a band); middle: the tilt once a period; bottom: the
# audible lines of the stator rim's axial velocity, coloured by level.
reset session
prefix = 'squeal_motion'
csv = prefix.'.csv'
set datafile separator ','
set datafile columnheaders
set encoding utf8
set grid lc rgb '#dddddd'
x(c) = 100 * column(1)
set xlabel 'mode split [%] (4-DOF, unilateral contact)' noenhanced
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
  set multiplot layout 3,1 title 'The motor past its last periodic orbit: the motion once a period, and its audible lines'
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
