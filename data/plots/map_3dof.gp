# map_3dof.gp: a static script of usm report (share/usm/plots/).
# Re-plot: cd into the report's directory and run  gnuplot map_3dof.gp
# Reads map_3dof.csv (the grid), map_3dof_{existence,stability,stick}.csv (the
# boundaries, located by bisection in T) and report_values.csv, columns by
# name; writes map_3dof.png and .svg.  The axes span the grid's cells, from the data.
#
# Each cell by its operating point (column op_class), as `usm map
# --plot` draws it (map.gp): the colour is the largest non-cyclic |lambda| of
# the operating point where there is one; no stable root, does not start from
# rest and unknown (several roots, one of them stable: only a start-up from
# rest decides, and the report does not simulate one) are classes of their
# own; grey: no stationary solution; dots: the model does not describe the
# motor there (column valid false).  The legend names each class present with
# its number of cells (counted here from the CSV) and lists the absent ones.
reset session
set datafile separator ","
set encoding utf8
set title "Stability map f x T, 3-DOF stick model: the operating point of each cell"
f0 = NaN; T0 = NaN; nb1 = 0; nb2 = 0; nb3 = 0
stats "report_values.csv" using (f0 = column("f [Hz]") / 1000, T0 = column("T [N m]") * 1e3, \
    nb1 = column("map_3dof_existence [1]"), nb2 = column("map_3dof_stability [1]"), \
    nb3 = column("map_3dof_stick [1]"), 0) nooutput
stats "map_3dof.csv" using (column("f [Hz]") / 1000):(column("T [N m]") * 1e3) nooutput
xmin = STATS_min_x; xmax = STATS_max_x; ymin = STATS_min_y; ymax = STATS_max_y
nx = 0
stats "map_3dof.csv" using (nx = nx + (column("T [N m]") * 1e3 == ymin), 0) nooutput
ny = STATS_records / nx
dx = nx > 1 ? (xmax - xmin) / (nx - 1) : 1; dy = ny > 1 ? (ymax - ymin) / (ny - 1) : 1
# the cells of each class, and those outside the model's validity
is(name) = strcol("op_class") eq name
n_op = 0; n_nsr = 0; n_dns = 0; n_unk = 0; n_nos = 0; n_inv = 0
stats "map_3dof.csv" using (n_op = n_op + is("operating_point"), n_nsr = n_nsr + is("no_stable_root"), \
    n_dns = n_dns + is("does_not_start"), n_unk = n_unk + is("unknown"), \
    n_nos = n_nos + is("no_solution"), n_inv = n_inv + (strcol("valid") eq "false"), 0) nooutput
L_op = "operating point"
L_nsr = "no stable root"
L_dns = "does not start from rest"
L_unk = "unknown (several roots)"
L_nos = "no stationary solution"
L_inv = "model not valid here"
cells(n, label) = n > 0 ? sprintf("%s (%d cell%s)", label, n, n == 1 ? "" : "s") : ""
absent = ""
add(s, n, label) = n > 0 ? s : (s eq "" ? label : s.", ".label)
absent = add(absent, n_op, L_op); absent = add(absent, n_nsr, L_nsr)
absent = add(absent, n_dns, L_dns); absent = add(absent, n_unk, "unknown")
absent = add(absent, n_nos, L_nos)
# the classes absent from this map, stated under the legend
note = absent eq "" ? "" : "Classes not on this map: ".absent
if (n_inv == 0) note = note.(note eq "" ? "" : "; ")."the model is valid at every cell"
if (note ne "") set label 1 note at screen 0.5, screen 0.015 center noenhanced
set xlabel "excitation frequency f [kHz]"
set ylabel "load torque T [N mm]"
set cblabel "largest non-cyclic |λ| of the operating point (log scale)"
set logscale cb
set cbrange [0.8:1]
set cbtics (0.8, 0.85, 0.9, 0.95, 1)
set palette defined (0 "#313695", 0.5 "#74add1", 1 "#ffffbf")
set xrange [xmin - dx / 2:xmax + dx / 2]
set yrange [ymin - dy / 2:ymax + dy / 2]
# grey: no stationary solution
set object 1 rectangle from graph 0,0 to graph 1,1 behind fillcolor rgb "#bdbdbd" fillstyle solid 1.0 noborder
set key at screen 0.5, screen 0.045 center bottom horizontal box opaque fc rgb "#e5e5e5" maxrows 5 width 1
set bmargin 11
unset grid
bx(c) = column("f [Hz]") / 1000
by(c) = column("T [N m]") * 1e3
inclass(name) = is(name) ? by(0) : NaN
invalid(c) = strcol("valid") eq "false" ? by(0) : NaN
# (the image's value inline: gnuplot 5.4 refuses "with image" when it comes from a
# user function -- "image coordinates undefined")
do for [fmt in "png svg"] {
  if (fmt eq "png") {
    set terminal pngcairo size 900,820 enhanced font "DejaVu Sans,11"
  } else {
    set terminal svg size 900,820 dynamic enhanced font "DejaVu Sans,11"
  }
  set output "map_3dof.".fmt
  plot \
    "map_3dof.csv" using (bx(0)):(by(0)):(strcol("op_class") eq "operating_point" ? column("op_max_modulus [1]") : NaN) with image notitle, \
    keyentry with boxes fillstyle solid 1.0 lc rgb "#74add1" title cells(n_op, L_op), \
    "map_3dof.csv" using (bx(0)):(inclass("no_stable_root")):(0.51 * dx):(0.51 * dy) with boxxyerror fillstyle solid 1.0 border lc rgb "#67001f" lc rgb "#67001f" title cells(n_nsr, L_nsr), \
    "map_3dof.csv" using (bx(0)):(inclass("does_not_start")):(0.51 * dx):(0.51 * dy) with boxxyerror fillstyle solid 1.0 border lc rgb "#000000" lc rgb "#000000" title cells(n_dns, L_dns), \
    "map_3dof.csv" using (bx(0)):(inclass("unknown")):(0.51 * dx):(0.51 * dy) with boxxyerror fillstyle solid 1.0 border lc rgb "#ffffff" lc rgb "#ffffff" notitle, \
    "map_3dof.csv" using (bx(0)):(inclass("unknown")):(0.51 * dx):(0.51 * dy) with boxxyerror fillstyle pattern 4 noborder lc rgb "#525252" title cells(n_unk, L_unk), \
    "map_3dof_existence.csv" using (bx(0)):(by(0)) with lines lw 3 lc rgb "black" title (nb1 > 0 ? "solution stops existing" : ""), \
    "map_3dof_stability.csv" using (bx(0)):(by(0)) with lines lw 2.5 dt 2 lc rgb "white" title (nb2 > 0 ? "|λ| = 1 (smallest-tilt root)" : ""), \
    "map_3dof_stick.csv" using (bx(0)):(by(0)) with lines lw 2.5 dt 4 lc rgb "#1e8449" title (nb3 > 0 ? "F_t = μ_0 F_n" : ""), \
    "map_3dof.csv" using (bx(0)):(invalid(0)) with points pt 7 ps 0.55 lc rgb "#ffffff" notitle, \
    "map_3dof.csv" using (bx(0)):(invalid(0)) with points pt 7 ps 0.35 lc rgb "#525252" title cells(n_inv, L_inv), \
    keyentry with boxes fillstyle solid 1.0 lc rgb "#bdbdbd" title cells(n_nos, L_nos), \
    "+" using (f0):(T0) every ::0::0 with points pt 3 ps 2.5 lw 2 lc rgb "black" title sprintf("Appendix A (f = %g kHz, T = %g N mm)", f0, T0)
  unset output
}
