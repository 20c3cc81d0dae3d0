# nonideal_orbit.gp: a static script of usm report (share/usm/plots/).
# Re-plot: cd into the report's directory and run  gnuplot nonideal_orbit.gp
# Reads nonideal_orbit.csv (one period of the 3-DOF imperfect motor's
# periodic orbit, closed: its last row is the state one period after the
# first) and nonideal_orbit_circle.csv (the ideal motor's path, a circle of
# radius the stationary tilt), columns by name; writes nonideal_orbit.png and
# .svg.  Left: the tilt vector rho = theta (cos phi, sin phi) in the housing
# plane, true scale, over the ideal circle (centred at the origin, as the
# orbit: the two nearly coincide at this scale); right: the tilt relative to the ideal one, theta/theta_ideal - 1 in per
# cent, against the direction of the tilt: the deviation the left panel is
# too small to show.  Every range comes from the data.  The orbit is drawn
# thin and grey over the whole period and at full weight where the model
# describes the motor (column valid: the contact closed, |F_t| <= mu0 F_n).
reset session
set datafile separator ","
set encoding utf8
set grid lc rgb "#dddddd"
orb = "nonideal_orbit.csv"; circ = "nonideal_orbit_circle.csv"
ok(v) = strcol("valid") eq "true" ? v : NaN
stats circ using (column("radius [rad]") * 1e6) nooutput
r0 = STATS_max
stats orb using (column("theta [rad]") * 1e6) nooutput
rmax = STATS_max > r0 ? STATS_max : r0
stats orb using (column("radial [%]")) nooutput
d0 = STATS_min; d1 = STATS_max
dpad = (d1 - d0) > 0 ? 0.1 * (d1 - d0) : 0.1
do for [fmt in "png svg"] {
  if (fmt eq "png") {
    set terminal pngcairo size 1200,560 enhanced font "DejaVu Sans,11"
  } else {
    set terminal svg size 1200,560 dynamic enhanced font "DejaVu Sans,11"
  }
  set output "nonideal_orbit.".fmt
  set multiplot layout 1,2 title "One period of the non-ideal motor (3-DOF, variant imperfect): the tilt vector in the housing plane"
  set size ratio -1
  set xrange [-1.25 * rmax:1.25 * rmax]
  set yrange [-1.25 * rmax:1.25 * rmax]
  set xlabel "ρ_X [μrad]"
  set ylabel "ρ_Y [μrad]"
  set key below
  plot orb using (column("rho_X [rad]") * 1e6):(column("rho_Y [rad]") * 1e6) with lines lw 1.5 lc rgb "#aaaaaa" title "not valid (contact open or stick lost)", \
       orb using (column("rho_X [rad]") * 1e6):(ok(column("rho_Y [rad]") * 1e6)) with lines lw 2.5 lc rgb "#c0392b" title "periodic orbit (one period)", \
       circ using (column("rho_X [rad]") * 1e6):(column("rho_Y [rad]") * 1e6) with lines lw 1.2 dt 2 lc rgb "#1f5fa8" title sprintf("ideal motor: circle of radius θ = %.4g μrad", r0)
  set size noratio
  set xrange [0:360]
  set xtics 60
  set yrange [d0 - dpad:d1 + dpad]
  set xlabel "direction of the tilt φ mod 360 [deg]"
  set ylabel "θ / θ_{ideal} - 1 [%]"
  plot orb using (column("angle [deg]")):(column("radial [%]")) with points pt 7 ps 0.2 lc rgb "#aaaaaa" title "not valid", \
       orb using (column("angle [deg]")):(ok(column("radial [%]"))) with points pt 7 ps 0.4 lc rgb "#c0392b" title "periodic orbit", \
       0 with lines dt 2 lw 2 lc rgb "#1f5fa8" title "ideal motor"
  unset multiplot
  unset output
}
