# map_3dof.gp: a static script of usm report (share/usm/plots/).
# Re-plot: cd into the report's directory and run  gnuplot map_3dof.gp
# Reads map_3dof.csv (the grid), map_3dof_{existence,stability,stick}.csv (the
# boundaries, located by bisection in T) and report_values.csv, columns by
# name; writes map_3dof.png and .svg.  The axes span the grid's cells, from the data.
reset session
set datafile separator ","
set encoding utf8
set title "Stability map f x T, 3-DOF stick model"
set grid lc rgb "#dddddd"
f0 = NaN; T0 = NaN; nb1 = 0; nb2 = 0; nb3 = 0
stats "report_values.csv" using (f0 = column("f [Hz]") / 1000, T0 = column("T [N m]") * 1e3, \
    nb1 = column("map_3dof_existence [1]"), nb2 = column("map_3dof_stability [1]"), \
    nb3 = column("map_3dof_stick [1]"), 0) nooutput
stats "map_3dof.csv" using (column("f [Hz]") / 1000):(column("T [N m]") * 1e3) nooutput
xmin = STATS_min_x; xmax = STATS_max_x; ymin = STATS_min_y; ymax = STATS_max_y
nx = 0
stats "map_3dof.csv" using (nx = nx + (column("T [N m]") * 1e3 == ymin), 0) nooutput
ny = STATS_records / nx
dx = (xmax - xmin) / (nx - 1); dy = (ymax - ymin) / (ny - 1)
set xlabel "excitation frequency f [kHz]"
set ylabel "load torque T [N mm]"
set cblabel "largest non-cyclic |λ| (log scale)"
set logscale cb
set cbrange [0.8:1.25]
set cbtics (0.8, 0.9, 1, 1.1, 1.25)
set palette defined (0 "#313695", 0.25 "#74add1", 0.5 "#ffffbf", 0.75 "#f46d43", 1 "#a50026")
set xrange [xmin - dx / 2:xmax + dx / 2]
set yrange [ymin - dy / 2:ymax + dy / 2]
# grey: no stationary solution
set object 1 rectangle from graph 0,0 to graph 1,1 behind fillcolor rgb "#bdbdbd" fillstyle solid 1.0 noborder
set key at screen 0.5, screen 0.01 center bottom horizontal box opaque maxrows 2 width 1
set bmargin 7
unset grid
bx(c) = column("f [Hz]") / 1000
# cells where the model does not describe the motor (column valid false:
# stick not admissible, contact open) get a small grey dot
invalid(c) = strcol("valid") eq "false" ? by(0) : NaN
by(c) = column("T [N m]") * 1e3
do for [fmt in "png svg"] {
  if (fmt eq "png") {
    set terminal pngcairo size 900,720 enhanced font "DejaVu Sans,11"
  } else {
    set terminal svg size 900,720 dynamic enhanced font "DejaVu Sans,11"
  }
  set output "map_3dof.".fmt
  plot \
    "map_3dof.csv" using (bx(0)):(by(0)):(strcol("exists") eq "true" ? column("max_modulus [1]") : NaN) with image notitle, \
    "map_3dof_existence.csv" using (bx(0)):(by(0)) with lines lw 3 lc rgb "black" title (nb1 > 0 ? "solution stops existing" : ""), \
    "map_3dof_stability.csv" using (bx(0)):(by(0)) with lines lw 2.5 dt 2 lc rgb "white" title (nb2 > 0 ? "|λ| = 1" : ""), \
    "map_3dof_stick.csv" using (bx(0)):(by(0)) with lines lw 2.5 dt 4 lc rgb "#1e8449" title (nb3 > 0 ? "F_t = μ_0 F_n" : ""), \
    "map_3dof.csv" using (bx(0)):(invalid(0)) with points pt 7 ps 0.3 lc rgb "#555555" title "model not valid here", \
    keyentry with boxes fillstyle solid 1.0 lc rgb "#bdbdbd" title "no stationary solution", \
    "+" using (f0):(T0) every ::0::0 with points pt 3 ps 2.5 lw 2 lc rgb "black" title sprintf("Appendix A (f = %g kHz, T = %g N mm)", f0, T0)
  unset output
}
