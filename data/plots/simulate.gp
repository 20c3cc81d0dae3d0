# simulate.gp: the plots of `usm simulate --out FILE.csv --plot PREFIX`, a
# static script (share/usm/plots/simulate.gp).  usm writes PREFIX.gp: the
# values below, then this text; `gnuplot PREFIX.gp` re-plots.
#   prefix, csv, title          output prefix, the time history, the title
#   stick, mu0                  stick model: draw mu0 F_n
#   have_steady, theta_bar, speed_bar   the stationary solution (dashed)
#   settled, t_settle [s]       where the period means settled
# Columns by name (docs/cli.md, "CSV files").  Thin lines: sampled values
# (aliased if the sampling rate is below about 10 f); thick lines: means over
# one excitation period; dashed: the stationary solution.
set datafile separator ','
# the display units of the CSV's columns (usm --units; SI when not given):
# theta_bar and speed_bar are in them too
if (!exists("rate_unit")) rate_unit = 'rad/s'
if (!exists("angle_unit")) angle_unit = 'rad'
# every point of an SVG is an element: keep the files reasonable
stats csv using (column("t [s]")) nooutput
stride = STATS_records > 20000 ? int(ceil(STATS_records / 20000.0)) : 1
t(c) = column("t [s]") * 1e3
set grid
set key top right
set xlabel 't [ms]'
if (settled) {
  set arrow 1 from t_settle * 1e3, graph 0 to t_settle * 1e3, graph 1 nohead dt 2 lw 2 lc rgb '#2ca02c'
  set label 1 'settled' at t_settle * 1e3, graph 0.92 offset 0.5, 0 tc rgb '#2ca02c'
}
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
  set multiplot layout 3,1 title title
  set ylabel 'tilt theta ['.angle_unit.']'
  plot csv using (t(0)):(column('theta ['.angle_unit.']')) every stride with lines lc rgb '#9ab8d8' title 'theta', \
       csv using (t(0)):(column('theta_avg ['.angle_unit.']')) with lines lw 2 lc rgb '#08306b' title 'mean over one period', \
       (have_steady ? theta_bar : NaN) with lines dt 2 lw 2 lc rgb '#d62728' title (have_steady ? 'stationary' : '')
  set ylabel 'rotor speed phi_Rdot ['.rate_unit.']'
  plot csv using (t(0)):(column('phi_Rdot ['.rate_unit.']')) every stride with lines lc rgb '#9ab8d8' title 'phi_Rdot', \
       csv using (t(0)):(column('phi_Rdot_avg ['.rate_unit.']')) with lines lw 2 lc rgb '#08306b' title 'mean over one period', \
       (have_steady ? speed_bar : NaN) with lines dt 2 lw 2 lc rgb '#d62728' title (have_steady ? 'stationary' : '')
  set ylabel 'contact force [N]'
  plot csv using (t(0)):(column("F_n [N]")) every stride with lines lc rgb '#1f77b4' title 'F_n', \
       csv using (t(0)):(column("F_t [N]")) every stride with lines lc rgb '#ff7f0e' title 'F_t', \
       csv using (t(0)):(stick ? mu0 * column("F_n [N]") : NaN) every stride with lines dt 2 lc rgb '#7f7f7f' title (stick ? 'mu0 F_n (stick limit)' : ''), \
       0 with lines lc rgb 'black' notitle
  unset multiplot
  set output
}
