# fig09_speed_frequency.gp: a static script of usm report (share/usm/plots/).
# Re-plot: cd into the report's directory and run  gnuplot fig09_speed_frequency.gp
# Reads fig09_speed_frequency_{3dof,4dof}.csv and report_values.csv, columns by
# name (docs/cli.md, "CSV files"); writes fig09_speed_frequency.png and .svg.
reset session
set datafile separator ","
set encoding utf8
set title "Rotor speed vs excitation frequency (paper Fig. 9)"
set grid lc rgb "#dddddd"
fmax3 = NaN; fmax4 = NaN; fpaper = NaN
stats "report_values.csv" using (fmax3 = column("f_max_3dof [Hz]") / 1000, \
    fmax4 = column("f_max_4dof [Hz]") / 1000, fpaper = column("f_max_paper [Hz]") / 1000, 0) nooutput
# full weight where the model describes the motor (column valid), thin grey elsewhere
ok(v) = strcol("valid") eq "true" ? v : NaN
set xlabel "excitation frequency f [kHz]"
set ylabel "rotor speed w_R = -dφ_R/dt [1/s]"
set key top right box opaque
if (fmax3 == fmax3) { set arrow 1 from fmax3, graph 0 to fmax3, graph 1 nohead lc rgb "#1f5fa8" dt 2 lw 1.5 }
if (fmax4 == fmax4) { set arrow 2 from fmax4, graph 0 to fmax4, graph 1 nohead lc rgb "#c0392b" dt 2 lw 1.5 }
set arrow 3 from fpaper, graph 0 to fpaper, graph 1 nohead lc rgb "#555555" dt 3 lw 1.5
do for [fmt in "png svg"] {
  if (fmt eq "png") {
    set terminal pngcairo size 900,560 enhanced font "DejaVu Sans,11"
  } else {
    set terminal svg size 900,560 dynamic enhanced font "DejaVu Sans,11"
  }
  set output "fig09_speed_frequency.".fmt
  plot \
    "fig09_speed_frequency_3dof.csv" using (column("f [Hz]") / 1000):(column("speed [1/s]")) \
      with lines lw 0.8 lc rgb "#aaaaaa" title "not valid (stick not admissible, contact open)", \
    "fig09_speed_frequency_3dof.csv" using (column("f [Hz]") / 1000):(ok(column("speed [1/s]"))) \
      with lines lw 2 lc rgb "#1f5fa8" title "3-DOF (stick)", \
    "fig09_speed_frequency_4dof.csv" using (column("f [Hz]") / 1000):(column("speed [1/s]")) \
      with lines lw 0.8 lc rgb "#aaaaaa" notitle, \
    "fig09_speed_frequency_4dof.csv" using (column("f [Hz]") / 1000):(ok(column("speed [1/s]"))) \
      with lines lw 2 lc rgb "#c0392b" title "4-DOF (slip)", \
    keyentry with lines dt 2 lw 1.5 lc rgb "#1f5fa8" title (fmax3 == fmax3 ? sprintf("3dof maximum: %.4g kHz", fmax3) : ""), \
    keyentry with lines dt 2 lw 1.5 lc rgb "#c0392b" title (fmax4 == fmax4 ? sprintf("4dof maximum: %.4g kHz", fmax4) : ""), \
    keyentry with lines dt 3 lw 1.5 lc rgb "#555555" title sprintf("paper: near %.3g kHz", fpaper)
  unset output
}
