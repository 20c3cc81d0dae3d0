# fig10_speed_load.gp: a static script of usm report (share/usm/plots/).
# Re-plot: cd into the report's directory and run  gnuplot fig10_speed_load.gp
# Reads fig10_speed_load_{3dof,4dof}.csv and report_values.csv, columns by
# name (docs/cli.md, "CSV files"); writes fig10_speed_load.png and .svg.
# Axis ranges come from the data: the left panel spans the 3-DOF curve (and
# the paper's slip load), the right one the loads up to 1.25 times where the
# 4-DOF solution stops existing; the 4-DOF speed, which falls without bound
# there, is clipped.
reset session
set datafile separator ","
set encoding utf8
set grid lc rgb "#dddddd"
stick = NaN; sat = NaN; ex3 = NaN; ex4 = NaN; stab = NaN; paper = NaN
stats "report_values.csv" using (stick = column("stick_limit [N m]") * 1e3, \
    sat = column("stick_limit_sat [N m]") * 1e3, ex3 = column("existence_T_3dof [N m]") * 1e3, \
    ex4 = column("existence_T_4dof [N m]") * 1e3, stab = column("stability_T [N m]") * 1e3, \
    paper = column("slip_load_paper [N m]") * 1e3, 0) nooutput
zoom = ex4 == ex4 ? 1.25 * ex4 : (stick == stick ? 2 * stick : NaN)
x(c) = column("T [N m]") * 1e3
w = "speed [1/s]"
# full weight where the model describes the motor (column valid: the stick
# model up to the stick limit, the contact closed), thin where it does not
stuck(c) = strcol("valid") eq "true" ? column(w) : NaN
unstable(c) = column("max_modulus [1]") >= 1 ? column(w) : NaN
stats "fig10_speed_load_3dof.csv" using (x(0)):(column(w)) nooutput
xmax = STATS_max_x > 1.05 * paper ? STATS_max_x : 1.05 * paper
wmin = STATS_min_y; wmax = STATS_max_y
set xlabel "load torque T [N mm]"
set ylabel "rotor speed w_R = -dφ_R/dt [1/s]"
set key box opaque
do for [fmt in "png svg"] {
  if (fmt eq "png") {
    set terminal pngcairo size 1200,560 enhanced font "DejaVu Sans,11"
  } else {
    set terminal svg size 1200,560 dynamic enhanced font "DejaVu Sans,11"
  }
  set output "fig10_speed_load.".fmt
  set multiplot layout 1,2 title "Rotor speed vs load torque (paper Fig. 10)"
  # left: the full range (3-DOF solid where F_t <= mu0 F_n, circles where unstable)
  unset arrow
  set key top right
  set xrange [0:xmax]
  set yrange [wmin - 0.15 * abs(wmax):1.3 * abs(wmax)]
  if (stick == stick) { set arrow 1 from stick, graph 0 to stick, graph 1 nohead lc rgb "#2e8b57" dt 2 lw 1.5 }
  if (ex3 == ex3) { set arrow 2 from ex3, graph 0 to ex3, graph 1 nohead lc rgb "#1f5fa8" dt 4 lw 1.5 }
  if (stab == stab) { set arrow 3 from stab, graph 0 to stab, graph 1 nohead lc rgb "#ff8c00" dt 5 lw 1.5 }
  set arrow 4 from paper, graph 0 to paper, graph 1 nohead lc rgb "#555555" dt 3 lw 1.5
  plot \
    "fig10_speed_load_3dof.csv" using (x(0)):(stuck(0)) with lines lw 2.5 lc rgb "#1f5fa8" title "3-DOF (stick), F_t <= μ_0 F_n", \
    "fig10_speed_load_3dof.csv" using (x(0)):(column(w)) with lines lw 1 lc rgb "#1f5fa8" title "3-DOF, stick not admissible", \
    "fig10_speed_load_3dof.csv" using (x(0)):(unstable(0)) with points pt 6 ps 0.6 lc rgb "#ff8c00" title "3-DOF unstable (max |λ| > 1)", \
    "fig10_speed_load_4dof.csv" using (x(0)):(column(w)) with lines lw 1 lc rgb "#c0392b" notitle, \
    "fig10_speed_load_4dof.csv" using (x(0)):(stuck(0)) with lines lw 2.5 lc rgb "#c0392b" title "4-DOF (slip)", \
    keyentry with lines dt 2 lw 1.5 lc rgb "#2e8b57" title sprintf("stick limit F_t = μ_0 F_n: %.3g N mm", stick), \
    keyentry with lines dt 4 lw 1.5 lc rgb "#1f5fa8" title sprintf("3-DOF solution exists up to %.3g N mm", ex3), \
    keyentry with lines dt 5 lw 1.5 lc rgb "#ff8c00" title sprintf("3-DOF unstable above %.3g N mm", stab), \
    keyentry with lines dt 3 lw 1.5 lc rgb "#555555" title sprintf("paper: slip above %.2g N mm", paper)
  # right: the stick/slip region
  unset arrow
  set key bottom left
  if (zoom == zoom) { set xrange [0:zoom] }
  set yrange [-3.5 * abs(wmax):1.3 * abs(wmax)]
  if (stick == stick) { set arrow 1 from stick, graph 0 to stick, graph 1 nohead lc rgb "#2e8b57" dt 2 lw 1.5 }
  if (sat == sat) { set arrow 2 from sat, graph 0 to sat, graph 1 nohead lc rgb "#8e44ad" dt 2 lw 1.5 }
  if (ex4 == ex4) { set arrow 3 from ex4, graph 0 to ex4, graph 1 nohead lc rgb "#c0392b" dt 4 lw 1.5 }
  plot \
    "fig10_speed_load_3dof.csv" using (x(0)):(stuck(0)) with linespoints lw 2.5 pt 7 ps 0.4 lc rgb "#1f5fa8" title "3-DOF (stick), F_t <= μ_0 F_n", \
    "fig10_speed_load_3dof.csv" using (x(0)):(column(w)) with lines lw 1 lc rgb "#1f5fa8" notitle, \
    "fig10_speed_load_4dof.csv" using (x(0)):(column(w)) with lines lw 1 lc rgb "#c0392b" notitle, \
    "fig10_speed_load_4dof.csv" using (x(0)):(stuck(0)) with linespoints lw 2.5 pt 7 ps 0.4 lc rgb "#c0392b" title "4-DOF (slip)", \
    keyentry with lines dt 2 lw 1.5 lc rgb "#2e8b57" title sprintf("F_t = μ_0 F_n: %.3g N mm", stick), \
    keyentry with lines dt 2 lw 1.5 lc rgb "#8e44ad" title sprintf("F_t = μ_0 (π/2) F_n: %.3g N mm", sat), \
    keyentry with lines dt 4 lw 1.5 lc rgb "#c0392b" title sprintf("4-DOF solution exists up to %.3g N mm", ex4)
  unset multiplot
  unset output
}
