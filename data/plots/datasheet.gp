# datasheet.gp: a static script of usm report (share/usm/plots/).
# Re-plot: cd into the report's directory and run  gnuplot datasheet.gp
# Reads datasheet_{3dof,4dof}.csv (the load curves, a sweep over T) and
# report_values.csv (the stick limit), columns by name (docs/cli.md, "CSV files"); writes datasheet.png and .svg.
# The motor datasheet: rotor speed (left axis) and output power in mW and
# efficiency in per cent (right axis: both of order 1 to 100 here) against the
# load torque, one panel per model (their loads differ sevenfold).  Every
# axis range comes from the data; where the slip model's rotor is driven
# backwards (speed < 0: power and efficiency negative) the speed axis is
# clipped at -0.5 times the no-load speed and the right axis at 0.
# Every curve is drawn thin over its whole range and at full weight where the
# model describes the motor (column valid: the 3-DOF stick model up to the
# stick limit, both models while the contact is closed); the right axis
# spans the valid parts.
reset session
set datafile separator ","
set encoding utf8
set grid lc rgb "#dddddd"
x(c) = column("T [N m]") * 1e3
w = "speed [1/s]"; pw = "power_out [W]"; eta = "efficiency [1]"
ok(v) = strcol("valid") eq "true" ? v : NaN
set xlabel "load torque T [N mm]"
set ylabel "rotor speed w_R = -dφ_R/dt [1/s]"
set y2label "output power P_{out} [mW], efficiency η [%]"
set ytics nomirror
set y2tics
# the key below the plot, clear of the curves and of the axis label
set key below left Left reverse nobox spacing 1.1 height 1.5
stick = NaN
stats "report_values.csv" using (stick = column("stick_limit [N m]") * 1e3, 0) nooutput
do for [fmt in "png svg"] {
  if (fmt eq "png") {
    set terminal pngcairo size 1200,680 enhanced font "DejaVu Sans,11"
  } else {
    set terminal svg size 1200,680 dynamic enhanced font "DejaVu Sans,11"
  }
  set output "datasheet.".fmt
  set multiplot layout 1,2 title "Motor datasheet: rotor speed, output power and efficiency vs load torque"
  do for [m in "3dof 4dof"] {
    file = "datasheet_".m.".csv"
    set autoscale  # stats reads only what lies in the current ranges
    stats file using (x(0)):(column(w)) nooutput
    xmax = STATS_max_x; wmin = STATS_min_y; wmax = STATS_max_y
    stats file using (column(pw) * 1e3) nooutput
    pmax = STATS_max
    stats file using (column(eta) * 100) nooutput
    emax = STATS_max
    # the maxima where the model describes the motor (valid: for the stick
    # model F_t <= mu0 F_n; the contact closed)
    stats file using (ok(column(eta) * 100)) nooutput
    emax_stick = STATS_max
    stats file using (ok(column(pw) * 1e3)) nooutput
    pmax_stick = STATS_max
    y2max = pmax_stick > emax_stick ? pmax_stick : emax_stick
    set xrange [0:xmax]
    set yrange [(wmin < -0.5 * wmax ? -0.5 * wmax : (wmin < 0 ? 1.1 * wmin : 0)):1.15 * wmax]
    set y2range [0:1.15 * y2max]
    set title (m eq "3dof" ? "3-DOF (stick) model" : "4-DOF (slip) model")
    unset arrow
    if (m eq "3dof") {
      if (stick == stick) { set arrow 1 from stick, graph 0 to stick, graph 1 nohead lc rgb "#555555" dt 3 lw 1.5 }
      plot \
        file using (x(0)):(column(w)) with lines lw 0.8 lc rgb "#8fa9c9" notitle, \
        file using (x(0)):(ok(column(w))) with lines lw 2.5 lc rgb "#1f5fa8" title "speed w_R (thin grey: past the stick limit, not valid)", \
        file using (x(0)):(column(pw) * 1e3) axes x1y2 with lines lw 0.8 dt 2 lc rgb "#aaaaaa" notitle, \
        file using (x(0)):(ok(column(pw) * 1e3)) axes x1y2 with lines lw 2 dt 2 lc rgb "#c0392b" title sprintf("output power P_{out} [mW] (max %.3g with stick)", pmax_stick), \
        file using (x(0)):(column(eta) * 100) axes x1y2 with lines lw 0.8 dt 4 lc rgb "#aaaaaa" notitle, \
        file using (x(0)):(ok(column(eta) * 100)) axes x1y2 with lines lw 2 dt 4 lc rgb "#2e8b57" title sprintf("efficiency η [%%] (max %.3g with stick)", emax_stick), \
        keyentry with lines dt 3 lw 1.5 lc rgb "#555555" title sprintf("stick limit F_t = μ_0 F_n: %.3g N mm (3-DOF valid below)", stick)
    } else {
      plot \
        file using (x(0)):(column(w)) with lines lw 0.8 lc rgb "#aaaaaa" notitle, \
        file using (x(0)):(ok(column(w))) with lines lw 2.5 lc rgb "#1f5fa8" title "speed w_R (thin grey where not valid: contact open)", \
        file using (x(0)):(column(pw) * 1e3) axes x1y2 with lines lw 0.8 dt 2 lc rgb "#aaaaaa" notitle, \
        file using (x(0)):(ok(column(pw) * 1e3)) axes x1y2 with lines lw 2 dt 2 lc rgb "#c0392b" title sprintf("output power P_{out} [mW] (max %.3g)", pmax_stick), \
        file using (x(0)):(column(eta) * 100) axes x1y2 with lines lw 0.8 dt 4 lc rgb "#aaaaaa" notitle, \
        file using (x(0)):(ok(column(eta) * 100)) axes x1y2 with lines lw 2 dt 4 lc rgb "#2e8b57" title sprintf("efficiency η [%%] (max %.3g)", emax_stick)
    }
  }
  unset multiplot
  unset output
}
