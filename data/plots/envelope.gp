# envelope.gp: the plot of `usm envelope --plot PREFIX`, a static script
# (share/usm/plots/envelope.gp).  usm writes PREFIX.gp: the values below,
# then this text; `gnuplot PREFIX.gp` re-plots.
#   prefix       output prefix: reads PREFIX.csv, writes PREFIX.png and .svg
#   xcol, ycol   the box's columns, e.g. 'f [Hz]' and 'F0 [N]' (as in the
#                CSV header, docs/cli.md "CSV files")
#   cells        the raster's cells a side (usm envelope --raster)
# The regions coloured by their class (the raster's cells, rows of kind
# region:CLASS; rgb_of below), each region's class written at its sample point, the curves
# as lines coloured and named by kind, the codimension-two points as
# diamonds (docs/envelope.md).
if (!exists("csv")) csv = prefix.'.csv'
set datafile separator ','
set datafile columnheaders
set encoding utf8
is(k) = strcol('kind') eq k
starts(p) = strstrt(strcol('kind'), p) == 1
# Only the kinds the box has go into the key (n_KIND: its rows).
kinds = 'tilt_zero fold stick_limit stall stability friction_saturation contact_loss stick_loss separation_fold separation_stability separation_grazing'
do for [k in kinds] {
  stats csv using (is(k) ? 1 : 0) nooutput
  eval sprintf('n_%s = STATS_sum', k)
}
stats csv using (starts('codim2:') ? 1 : 0) nooutput
n_codim2 = STATS_sum
stats csv using (column(xcol)):(column(ycol)) nooutput
set xrange [STATS_min_x:STATS_max_x]
set yrange [STATS_min_y:STATS_max_y]
if (!exists("cells")) cells = 120
hx = (STATS_max_x - STATS_min_x) / cells / 2
hy = (STATS_max_y - STATS_min_y) / cells / 2
set xlabel xcol noenhanced
set ylabel ycol noenhanced
# A region's colour by its class: greens where the motor runs (stably, the
# stick admissible, the contact closed; paler with separation), oranges and
# reds where it does not run as designed, greys where there is no solution.
rgb_of(c) = (c eq 'operating_point' || c eq 'stick_admissible' || c eq 'contact_closed') ? 0xc7e9c0 : \
            c eq 'separating' ? 0xe5f5e0 : \
            c eq 'does_not_start' ? 0x9e9ac8 : \
            (c eq 'no_stable_root' || c eq 'unstable' || c eq 'separating_unstable') ? 0xfcae91 : \
            c eq 'squeal' ? 0xfb6a4a : \
            (c eq 'stick_lost' || c eq 'contact_open') ? 0xfee391 : \
            c eq 'unknown' ? 0xf0f0f0 : 0xbdbdbd
line(k) = is(k) ? column(ycol) : NaN
label_of(c) = strcol('kind')[8:*]
do for [fmt in 'png svg'] {
  if (fmt eq 'png') {
    set terminal pngcairo size 900,720 noenhanced font 'DejaVu Sans,11'
  } else {
    set terminal svg size 900,720 dynamic noenhanced font 'DejaVu Sans,11'
  }
  set output prefix.'.'.fmt
  set title 'usm envelope: '.csv
  set key outside bottom center horizontal maxrows 3
  plot csv using (column(xcol)):(starts('region:') ? column(ycol) : NaN):(hx):(hy):(rgb_of(strcol('kind')[8:*])) with boxxyerror fillstyle solid 1.0 noborder lc rgb variable notitle, \
       csv using (column(xcol)):(line('tilt_zero')) with lines lw 2 lc rgb '#08519c' title (n_tilt_zero > 0 ? 'tilt_zero' : ''), \
       csv using (column(xcol)):(line('fold')) with lines lw 2 lc rgb '#a50f15' title (n_fold > 0 ? 'fold' : ''), \
       csv using (column(xcol)):(line('stick_limit')) with lines lw 2 dt 2 lc rgb '#006d2c' title (n_stick_limit > 0 ? 'stick_limit' : ''), \
       csv using (column(xcol)):(line('stall')) with lines lw 2 dt 3 lc rgb '#54278f' title (n_stall > 0 ? 'stall' : ''), \
       csv using (column(xcol)):(line('stability')) with lines lw 2 lc rgb '#e6550d' title (n_stability > 0 ? 'stability' : ''), \
       csv using (column(xcol)):(line('friction_saturation')) with lines lw 2 dt 3 lc rgb '#636363' title (n_friction_saturation > 0 ? 'friction_saturation' : ''), \
       csv using (column(xcol)):(line('contact_loss')) with lines lw 2 lc rgb '#3182bd' title (n_contact_loss > 0 ? 'contact_loss' : ''), \
       csv using (column(xcol)):(line('stick_loss')) with lines lw 2 dt 2 lc rgb '#31a354' title (n_stick_loss > 0 ? 'stick_loss' : ''), \
       csv using (column(xcol)):(line('separation_fold')) with lines lw 2 dt 4 lc rgb '#a50f15' title (n_separation_fold > 0 ? 'separation_fold' : ''), \
       csv using (column(xcol)):(line('separation_stability')) with lines lw 2 dt 4 lc rgb '#e6550d' title (n_separation_stability > 0 ? 'separation_stability' : ''), \
       csv using (column(xcol)):(line('separation_grazing')) with lines lw 2 dt 5 lc rgb '#31a354' title (n_separation_grazing > 0 ? 'separation_grazing' : ''), \
       csv using (column(xcol)):(starts('codim2:') ? column(ycol) : NaN) with points pt 13 ps 1.6 lc rgb '#000000' title (n_codim2 > 0 ? 'codimension two' : ''), \
       csv using (column(xcol)):(starts('sample:') ? column(ycol) : NaN):(label_of(0)) with labels font ',9' notitle
  unset output
}
