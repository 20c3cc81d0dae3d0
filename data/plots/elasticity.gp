# elasticity.gp: a static script of usm report (share/usm/plots/).
# Re-plot: cd into the report's directory and run  gnuplot elasticity.gp
# Reads elasticity_{rotor_speed,max_modulus}_{3dof,4dof}.csv (the nonzero
# elasticities (p/y) dy/dp at the paper's point, sorted by magnitude), columns
# by name (docs/cli.md, "CSV files"); writes elasticity.png and .svg.
# One panel per output and model; bars right of zero raise the output.
reset session
set datafile separator ","
set encoding utf8
set grid ytics lc rgb "#dddddd"
set style fill solid 0.8 border -1
set boxwidth 0.7
set xtics rotate by -45 nomirror
set ylabel "elasticity (p/y) dy/dp"
set xzeroaxis lt -1
e = "elasticity [1]"
pos(c) = column(e) > 0 ? column(e) : NaN
neg(c) = column(e) < 0 ? column(e) : NaN
do for [fmt in "png svg"] {
  if (fmt eq "png") {
    set terminal pngcairo size 1200,820 enhanced font "DejaVu Sans,11"
  } else {
    set terminal svg size 1200,820 dynamic enhanced font "DejaVu Sans,11"
  }
  set output "elasticity.".fmt
  set multiplot layout 2,2 title "Elasticities at the paper's point, sorted by magnitude"
  do for [out in "rotor_speed max_modulus"] {
    do for [m in "3dof 4dof"] {
      file = "elasticity_".out."_".m.".csv"
      set title sprintf("%s, %s model", out eq "rotor_speed" ? "rotor speed" : "largest Floquet modulus", m)
      # a header alone: the derivative does not exist here (report.md says why)
      rows = int(system("awk 'END { print NR - 1 }' ".file))
      if (rows < 1) {
        set xrange [0:1]; set yrange [0:1]
        set label 1 "undefined (see report.md)" at 0.5, 0.5 center
        plot NaN notitle
        unset label 1
      } else {
        set autoscale  # stats reads only what lies in the current ranges
        stats file using (column("rank")):(column(e)) nooutput
        n = STATS_records
        emin = STATS_min_y < 0 ? STATS_min_y : 0
        emax = STATS_max_y > 0 ? STATS_max_y : 0
        span = emax - emin > 0 ? emax - emin : 1
        set xrange [0.3:n + 0.7]
        set yrange [emin - 0.08 * span:emax + 0.08 * span]
        plot \
          file using (column("rank")):(pos(0)):xticlabels(strcol("parameter")) with boxes lc rgb "#1f5fa8" notitle, \
          file using (column("rank")):(neg(0)) with boxes lc rgb "#c0392b" notitle
      }
    }
  }
  unset multiplot
  unset output
}
