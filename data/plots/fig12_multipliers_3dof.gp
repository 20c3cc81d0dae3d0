# fig12_multipliers_3dof.gp: a static script of usm report (share/usm/plots/).
# Re-plot: cd into the report's directory and run  gnuplot fig12_multipliers_3dof.gp
# Reads fig12_multipliers_3dof.csv, columns by name (docs/cli.md, "CSV files"); writes fig12_multipliers_3dof.png
# and .svg.  Column "series": 0-5 computed from the start times t0 = 0, T/4,
# T/2, 10 T, 100 T, 1000 T; 8 the twist_integrated variant; 9 the paper's Table 3.
# The axes hold the unit circle and every multiplier (their largest modulus
# comes from the data).
reset session
set datafile separator ","
set encoding utf8
set title "Floquet multipliers, 3-DOF stick model (paper Fig. 12, Table 3)"
set grid lc rgb "#dddddd"
rmax = 1; n8 = 0
stats "fig12_multipliers_3dof.csv" using (rmax = column("modulus [1]") > rmax ? column("modulus [1]") : rmax, \
    n8 = n8 + (column("series") == 8), 0) nooutput
r = 1.3 * rmax
set xlabel "Re λ"
set ylabel "Im λ"
set size ratio -1
set xrange [-r:r]
set yrange [-r:r]
set key outside right top box opaque
set object 1 circle at 0,0 size 1 fillstyle empty border lc rgb "black" lw 1
sel(s) = (column("series") == s) ? column("im [1]") : NaN
re = "re [1]"
do for [fmt in "png svg"] {
  if (fmt eq "png") {
    set terminal pngcairo size 900,640 enhanced font "DejaVu Sans,11"
  } else {
    set terminal svg size 900,640 dynamic enhanced font "DejaVu Sans,11"
  }
  set output "fig12_multipliers_3dof.".fmt
  plot \
    "fig12_multipliers_3dof.csv" using (column(re)):(sel(2)) with points pt 8 ps 1.2 lw 1.5 lc rgb "#76d7c4" title "computed, t0 = T/2", \
    "fig12_multipliers_3dof.csv" using (column(re)):(sel(4)) with points pt 4 ps 1.2 lw 1.5 lc rgb "#f0b27a" title "computed, t0 = 100 T", \
    "fig12_multipliers_3dof.csv" using (column(re)):(sel(5)) with points pt 10 ps 1.2 lw 1.5 lc rgb "#e74c3c" title "computed, t0 = 1000 T", \
    "fig12_multipliers_3dof.csv" using (column(re)):(sel(8)) with points pt 12 ps 1.8 lc rgb "#888888" title (n8 > 0 ? "twist integrated (any t0)" : ""), \
    "fig12_multipliers_3dof.csv" using (column(re)):(sel(0)) with points pt 7 ps 1.2 lc rgb "#1f5fa8" title "computed, t0 = 0", \
    "fig12_multipliers_3dof.csv" using (column(re)):(sel(9)) with points pt 2 ps 2.0 lw 2 lc rgb "black" title "paper, Table 3"
  unset output
}
