# fig11_speed_amplitude.gp: a static script of usm report (share/usm/plots/).
# Re-plot: cd into the report's directory and run  gnuplot fig11_speed_amplitude.gp
# Reads fig11_speed_amplitude_{3dof,4dof}.csv and report_values.csv, columns
# by name (docs/cli.md, "CSV files"); writes fig11_speed_amplitude.png and .svg.
reset session
set datafile separator ","
set encoding utf8
set title "Rotor speed vs excitation amplitude m0 (paper Fig. 11)"
set grid lc rgb "#dddddd"
ex3 = NaN; ex4 = NaN; m0 = NaN; w0 = NaN
stats "report_values.csv" using (ex3 = column("existence_m0_3dof [N m]") * 1e3, \
    ex4 = column("existence_m0_4dof [N m]") * 1e3, m0 = column("m0 [N m]") * 1e3, \
    w0 = column("speed_3dof [1/s]"), 0) nooutput
# full weight where the model describes the motor (column valid), thin grey elsewhere
ok(v) = strcol("valid") eq "true" ? v : NaN
set xlabel "excitation torque amplitude m_0 [mN m]"
set ylabel "rotor speed w_R = -dφ_R/dt [1/s]"
# the key below the plot, where it covers neither the curves nor the limits
set key below left Left reverse nobox horizontal maxrows 3 spacing 1.1
# room above the curves and beside the limits: nothing sits on the frame
set offsets 0, graph 0.03, graph 0.12, 0
set xrange [0:*]
set autoscale xfixmax
set yrange [0:*]
# the existence limits: labelled dashed lines inside the frame (3-DOF to the
# left of its label, 4-DOF below it when the two coincide)
if (ex3 == ex3) { set arrow 1 from ex3, graph 0.02 to ex3, graph 0.9 nohead lc rgb "#1f5fa8" dt 2 lw 1.5 front
  set label 1 sprintf(" 3-DOF: a solution from %.5g mN m", ex3) at ex3, graph 0.95 left tc rgb "#1f5fa8" font ",10" front }
if (ex4 == ex4) { set arrow 2 from ex4, graph 0.02 to ex4, graph 0.9 nohead lc rgb "#c0392b" dt 4 lw 1.5 front
  set label 2 sprintf(" 4-DOF: a solution from %.5g mN m", ex4) at ex4, graph 0.91 left tc rgb "#c0392b" font ",10" front }
do for [fmt in "png svg"] {
  if (fmt eq "png") {
    set terminal pngcairo size 900,560 enhanced font "DejaVu Sans,11"
  } else {
    set terminal svg size 900,560 dynamic enhanced font "DejaVu Sans,11"
  }
  set output "fig11_speed_amplitude.".fmt
  plot \
    "fig11_speed_amplitude_3dof.csv" using (column("m0 [N m]") * 1e3):(column("speed [1/s]")) \
      with lines lw 0.8 lc rgb "#aaaaaa" title "not valid (stick not admissible, contact open)", \
    "fig11_speed_amplitude_3dof.csv" using (column("m0 [N m]") * 1e3):(ok(column("speed [1/s]"))) \
      with lines lw 2 lc rgb "#1f5fa8" title "3-DOF (stick)", \
    keyentry with lines dt 2 lw 1.5 lc rgb "#1f5fa8" title (ex3 == ex3 ? sprintf("3dof: a solution exists from m_0 = %.5g mN m", ex3) : ""), \
    "fig11_speed_amplitude_4dof.csv" using (column("m0 [N m]") * 1e3):(column("speed [1/s]")) \
      with lines lw 0.8 lc rgb "#aaaaaa" notitle, \
    "fig11_speed_amplitude_4dof.csv" using (column("m0 [N m]") * 1e3):(ok(column("speed [1/s]"))) \
      with lines lw 2 lc rgb "#c0392b" title "4-DOF (slip)", \
    keyentry with lines dt 4 lw 1.5 lc rgb "#c0392b" title (ex4 == ex4 ? sprintf("4dof: a solution exists from m_0 = %.5g mN m", ex4) : ""), \
    "+" using (m0):(w0) every ::0::0 with points pt 3 ps 2 lc rgb "black" title sprintf("Appendix A: m_0 = %g mN m", m0)
  unset output
}
