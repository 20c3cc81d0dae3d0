# nonideal_curves.gp: a static script of usm report (share/usm/plots/).
# Re-plot: cd into the report's directory and run  gnuplot nonideal_curves.gp
# Reads nonideal_curves_{phase_error,mode_split}_{3dof,4dof}.csv (periodic
# orbits of the variant imperfect, one imperfection at a time) and
# nonideal_curves_values.csv (the located values: the contact opens,
# stability is lost, the tolerable value), columns by name (docs/cli.md, "CSV
# files"); writes nonideal_curves.png and .svg.  Rows: rotor-speed ripple,
# smallest normal force over the period, largest non-cyclic |lambda|, mean
# rotor speed, largest impact velocity; columns: phase error, mode split.
# Past contact loss the orbits with separation of the unilateral model
# (columns *_separating, impact_velocity_max) are drawn dashed in their own
# colours.  Every axis range comes from the data.
reset session
set datafile separator ","
set encoding utf8
set grid lc rgb "#dddddd"
# the key above each panel, where it covers no curve
set key tmargin center horizontal Left reverse nobox spacing 1.05 font ",9" maxrows 2
vals = "nonideal_curves_values.csv"
# the located values (NaN where not found in the range)
val(name) = 0
array tol[4]; array con[4]; array sta[4]
do for [i = 1:4] { tol[i] = NaN; con[i] = NaN; sta[i] = NaN }
imps = "phase_error mode_split"; units = "deg %"; mods = "3dof 4dof"
do for [j = 1:2] {
  do for [k = 1:2] {
    suf = word(imps, j)."_".word(mods, k)." [".word(units, j)."]"
    i = 2 * (j - 1) + k
    stats vals using (tol[i] = column("tolerable_".suf), con[i] = column("contact_".suf), sta[i] = column("stability_".suf), 0) nooutput
  }
}
xcol(j) = j == 1 ? "phase_error_deg [deg]" : "mode_split_percent [%]"
xlab(j) = j == 1 ? "phase error δ [deg]" : "mode split s [%]"
ycol(r) = r == 1 ? "rotor_speed_ripple [1/s]" : (r == 2 ? "F_n_min [N]" : (r == 3 ? "max_modulus [1]" : (r == 4 ? "rotor_speed_mean [1/s]" : "impact_velocity_max [m/s]")))
ysep(r) = r == 1 ? "rotor_speed_ripple_separating [1/s]" : (r == 3 ? "max_modulus_separating [1]" : (r == 4 ? "rotor_speed_mean_separating [1/s]" : "impact_velocity_max [m/s]"))
yscale(r) = r == 5 ? 1e3 : 1
ylab(r) = r == 1 ? "rotor-speed ripple (peak to peak) [1/s]" : (r == 2 ? "smallest normal force F_{n,min} [N]" : (r == 3 ? "largest |λ| (non-cyclic)" : (r == 4 ? "mean rotor speed [1/s]" : "largest impact velocity [mm/s]")))
color(k) = k == 1 ? "#1f5fa8" : "#c0392b"
scolor(k) = k == 1 ? "#e67e22" : "#27ae60"
# a row's value with the orbit with separation where there is one (for the ranges)
yany(r) = (r == 2 ? column(ycol(r)) : (column(ysep(r)) == column(ysep(r)) ? column(ysep(r)) * yscale(r) : (r == 5 ? 0 : column(ycol(r)))))
file(j, k) = "nonideal_curves_".word(imps, j)."_".word(mods, k).".csv"
# full weight where the model describes the motor (column valid: the contact
# closed over the whole orbit, the 3-DOF stick admissible), thin grey elsewhere
ok(v) = strcol("valid") eq "true" ? v : NaN
do for [fmt in "png svg"] {
  if (fmt eq "png") {
    set terminal pngcairo size 1200,2000 enhanced font "DejaVu Sans,10"
  } else {
    set terminal svg size 1200,2000 dynamic enhanced font "DejaVu Sans,10"
  }
  set output "nonideal_curves.".fmt
  set multiplot layout 5,2 title "The non-ideal motor: each imperfection alone (periodic orbits by shooting, variant imperfect; past contact loss with separation, variant imperfect\\_unilateral)\n"
  do for [r = 1:5] {
    do for [j = 1:2] {
      set autoscale
      stats file(j, 1) using (column(xcol(j))):(yany(r)) nooutput
      x0 = STATS_min_x; x1 = STATS_max_x; y0 = STATS_min_y; y1 = STATS_max_y
      stats file(j, 2) using (column(xcol(j))):(yany(r)) nooutput
      x0 = STATS_min_x < x0 ? STATS_min_x : x0; x1 = STATS_max_x > x1 ? STATS_max_x : x1
      y0 = STATS_min_y < y0 ? STATS_min_y : y0; y1 = STATS_max_y > y1 ? STATS_max_y : y1
      if (r == 2 || r == 5) { y0 = y0 > 0 ? 0 : y0 }
      pad = (y1 - y0) > 0 ? 0.08 * (y1 - y0) : (abs(y1) > 0 ? 1e-3 * abs(y1) : 1)
      set xrange [x0:x1]
      set yrange [y0 - pad:y1 + pad]
      set xlabel xlab(j)
      set ylabel ylab(r)
      unset arrow
      if (r == 2) { set arrow 10 from x0, 0 to x1, 0 nohead lc rgb "#555555" dt 3 }
      do for [k = 1:2] {
        t = tol[2 * (j - 1) + k]
        if (t == t) { set arrow k from t, graph 0 to t, graph 1 nohead lc rgb color(k) dt 2 lw 1.5 }
      }
      plot for [k = 1:2] file(j, k) using (column(xcol(j))):(r == 5 ? NaN : column(ycol(r))) \
             with linespoints lw 0.8 pt 7 ps 0.3 lc rgb "#aaaaaa" \
             title (k == 1 ? "bilateral, not valid (contact open, stick lost)" : ""), \
           for [k = 1:2] file(j, k) using (column(xcol(j))):(r == 5 ? NaN : ok(column(ycol(r)))) \
             with linespoints lw 2 pt 7 ps 0.5 lc rgb color(k) \
             title (word(mods, k) eq "3dof" ? "3-DOF (stick)" : "4-DOF (slip)") . \
               (tol[2 * (j - 1) + k] == tol[2 * (j - 1) + k] ? sprintf(": tolerable %.3g %s", tol[2 * (j - 1) + k], word(units, j)) : ": tolerable beyond the range"), \
           for [k = 1:2] file(j, k) using (column(xcol(j))):(r == 2 ? NaN : column(ysep(r)) * yscale(r)) \
             with linespoints lw 2 dt 2 pt 5 ps 0.5 lc rgb scolor(k) \
             title (word(mods, k) eq "3dof" ? "3-DOF" : "4-DOF") . " with separation (unilateral)"
    }
  }
  unset multiplot
  unset output
}
