# tolerance.gp: the histograms of `usm tolerance --out DIR`, a static script
# (share/usm/plots/tolerance.gp).  usm writes DIR/histograms.gp: the values
# below, then this text; `gnuplot DIR/histograms.gp` (from where usm ran)
# re-plots.
#   prefix   output prefix: writes PREFIX.png and PREFIX.svg
#   csv      the samples, DIR/samples.csv (columns by name, docs/cli.md
#            "CSV files"; empty fields, where an output does not exist, are
#            left out)
#   speed_lo, speed_hi    the --spec bounds on rotor_speed (absent: none)
#   modulus_hi            the bound on max_modulus: 1 (stability), or a
#                         tighter --spec max_modulus<=X
# Top: the rotor speed of the samples; bottom: the largest non-cyclic
# |lambda|.  40 bins over the data's range.  A bound is drawn (dashed) where
# it lies within one data span of the data, the axis widened to show it;
# a bound farther away is named in the key as off the axis, with the side
# the samples are on, so the key never names a line the reader cannot see.
set datafile separator ','
set datafile columnheaders
set encoding utf8
set grid lc rgb '#dddddd'
nbins = 40
scol = 'rotor_speed [1/s]'
mcol = 'max_modulus [1]'
# how many samples have each output (an empty field: none), then the range
# of each column; a constant column gets a small bin
ns = 0; nm = 0
stats csv using (ns = ns + (strlen(strcol(scol)) > 0), nm = nm + (strlen(strcol(mcol)) > 0), 0) nooutput
S_min = 0; S_max = 1; M_min = 0; M_max = 1
if (ns > 0) { stats csv using (column(scol)) nooutput name 'S' }
if (nm > 0) { stats csv using (column(mcol)) nooutput name 'M' }
sw = S_max > S_min ? (S_max - S_min) / nbins : (abs(S_min) + 1e-300) * 1e-9
mw = M_max > M_min ? (M_max - M_min) / nbins : (abs(M_min) + 1e-300) * 1e-9
sbin(x) = S_min + sw * (floor((x - S_min) / sw) + 0.5)
mbin(x) = M_min + mw * (floor((x - M_min) / mw) + 0.5)
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
    plot [S_lo - spad : S_hi + spad] csv using (sbin(column(scol))):(1.0) smooth frequency with boxes lc rgb '#1f5fa8' title stitle
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
    plot [M_lo - mpad : M_hi + mpad] csv using (mbin(column(mcol))):(1.0) smooth frequency with boxes lc rgb '#ff8c00' title mtitle
  } else {
    set label 1 'no sample has Floquet multipliers' at graph 0.5, 0.5 center
    plot [0:1] [0:1] 2 notitle
    unset label 1
  }
  unset multiplot
  unset output
}
