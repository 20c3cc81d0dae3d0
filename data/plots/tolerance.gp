# tolerance.gp: the histograms of `usm tolerance --out DIR`, a static script
# (share/usm/plots/tolerance.gp).  usm writes DIR/histograms.gp: the values
# below, then this text; `gnuplot DIR/histograms.gp` (from where usm ran)
# re-plots.
#   prefix   output prefix: writes PREFIX.png and PREFIX.svg
#   csv      the samples, DIR/samples.csv (named in the title only)
#   bins     the histograms, DIR/histograms.csv: 40 bins of rotor_speed and
#            max_modulus counted by usm over every sample that has the output
#            (columns by name, docs/tolerance.md); gnuplot reads these 40
#            rows, never the samples, so the figure costs the same at 10^8
#   speed_lo, speed_hi    the --spec bounds on rotor_speed (absent: none)
#   modulus_hi            the bound on max_modulus: 1 (stability), or a
#                         tighter --spec max_modulus<=X
# Top: the rotor speed of the samples; bottom: the largest non-cyclic
# |lambda|.  A bound is drawn (dashed) where
# it lies within one data span of the data, the axis widened to show it;
# a bound farther away is named in the key as off the axis, with the side
# the samples are on, so the key never names a line the reader cannot see.
set datafile separator ','
set datafile columnheaders
set encoding utf8
set grid lc rgb '#dddddd'
slo = 'rotor_speed_lo [1/s]'; shi = 'rotor_speed_hi [1/s]'; scnt = 'rotor_speed_count'
mlo = 'max_modulus_lo [1]'; mhi = 'max_modulus_hi [1]'; mcnt = 'max_modulus_count'
# how many samples have each output, and the range of the bins
stats bins using (column(scnt)) nooutput name 'SC'
stats bins using (column(mcnt)) nooutput name 'MC'
ns = SC_sum; nm = MC_sum
S_min = 0; S_max = 1; M_min = 0; M_max = 1
if (ns > 0) { stats bins using (column(slo)):(column(shi)) nooutput name 'SB'; S_min = SB_min_x; S_max = SB_max_y }
if (nm > 0) { stats bins using (column(mlo)):(column(mhi)) nooutput name 'MB'; M_min = MB_min_x; M_max = MB_max_y }
sw = (S_max - S_min) / SC_records
mw = (M_max - M_min) / MC_records
# bound_text(b, lo, hi, what): the key's words for bound b against data
# [lo, hi]; near(b, lo, hi): whether b is drawn
near(b, lo, hi) = b >= lo - (hi - lo) && b <= hi + (hi - lo)
bound_text(b, lo, hi, what) = near(b, lo, hi) ? sprintf('dashed: %s %g', what, b) \
    : sprintf('%s %g off the axis, %s every sample', what, b, b > hi ? 'above' : 'below')
widen_lo(lo, b, hi) = near(b, lo, hi) && b < lo ? b : lo
widen_hi(hi, b, lo) = near(b, lo, hi) && b > hi ? b : hi
if (!exists('modulus_hi')) { modulus_hi = 1 }
S_lo = S_min; S_hi = S_max
stitle = 'rotor speed'
if (exists('speed_lo')) {
  stitle = stitle.' ('.bound_text(speed_lo, S_min, S_max, 'spec >=').')'
  S_lo = widen_lo(S_lo, speed_lo, S_max); S_hi = widen_hi(S_hi, speed_lo, S_min)
}
if (exists('speed_hi')) {
  stitle = stitle.' ('.bound_text(speed_hi, S_min, S_max, 'spec <=').')'
  S_lo = widen_lo(S_lo, speed_hi, S_max); S_hi = widen_hi(S_hi, speed_hi, S_min)
}
mb = modulus_hi
mtitle = 'max_modulus ('.bound_text(mb, M_min, M_max, mb == 1 ? 'stability limit' : 'spec <=').')'
M_lo = widen_lo(M_min, mb, M_max); M_hi = widen_hi(M_max, mb, M_min)
spad = (S_hi > S_lo ? S_hi - S_lo : abs(S_lo) + 1) * 0.03
mpad = (M_hi > M_lo ? M_hi - M_lo : abs(M_lo) + 1e-9) * 0.03
set style fill solid 0.6 border lc rgb '#333333'
set yrange [0:*]
set ylabel 'samples'
set key top right
do for [fmt in 'png svg'] {
  if (fmt eq 'png') {
    set terminal pngcairo size 900,800 noenhanced font 'DejaVu Sans,11'
  } else {
    set terminal svg size 900,800 dynamic noenhanced font 'DejaVu Sans,11'
  }
  set output prefix.'.'.fmt
  set multiplot layout 2,1 title 'usm tolerance: '.csv
  set xlabel 'rotor speed phi_Rdot [1/s]'
  unset arrow
  if (exists('speed_lo') && near(speed_lo, S_min, S_max)) {
    set arrow 2 from speed_lo, graph 0 to speed_lo, graph 1 nohead front lw 2 dt 2 lc rgb '#a50026'
  }
  if (exists('speed_hi') && near(speed_hi, S_min, S_max)) {
    set arrow 3 from speed_hi, graph 0 to speed_hi, graph 1 nohead front lw 2 dt 2 lc rgb '#a50026'
  }
  set boxwidth sw
  if (ns > 0) {
    plot [S_lo - spad : S_hi + spad] bins using ((column(slo) + column(shi)) / 2):(column(scnt)) with boxes lc rgb '#1f5fa8' title stitle
  } else {
    set label 1 'no sample has a stationary solution' at graph 0.5, 0.5 center
    plot [0:1] [0:1] 2 notitle
    unset label 1
  }
  set xlabel 'largest non-cyclic |lambda|'
  unset arrow
  if (near(mb, M_min, M_max)) {
    set arrow 1 from mb, graph 0 to mb, graph 1 nohead front lw 2 dt 2 lc rgb '#a50026'
  }
  set boxwidth mw
  if (nm > 0) {
    plot [M_lo - mpad : M_hi + mpad] bins using ((column(mlo) + column(mhi)) / 2):(column(mcnt)) with boxes lc rgb '#ff8c00' title mtitle
  } else {
    set label 1 'no sample has Floquet multipliers' at graph 0.5, 0.5 center
    plot [0:1] [0:1] 2 notitle
    unset label 1
  }
  unset multiplot
  unset output
}
