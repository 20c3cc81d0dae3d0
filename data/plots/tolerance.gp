# tolerance.gp: the histograms of `usm tolerance --out DIR`, a static script
# (share/usm/plots/tolerance.gp).  usm writes DIR/histograms.gp: the values
# below, then this text; `gnuplot DIR/histograms.gp` (from where usm ran)
# re-plots.
#   prefix   output prefix: writes PREFIX.png and PREFIX.svg
#   csv      the samples, DIR/samples.csv (columns by name, docs/cli.md
#            "CSV files"; empty fields, where an output does not exist, are
#            left out)
# Top: the rotor speed of the samples; bottom: the largest non-cyclic
# |lambda|, with the stability limit 1 marked.  40 bins over the data's range.
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
  set boxwidth sw
  if (ns > 0) {
    plot csv using (sbin(column(scol))):(1.0) smooth frequency with boxes lc rgb '#1f5fa8' title 'rotor speed'
  } else {
    set label 1 'no sample has a stationary solution' at graph 0.5, 0.5 center
    plot [0:1] [0:1] 2 notitle
    unset label 1
  }
  set xlabel 'largest non-cyclic |lambda|'
  set arrow 1 from 1, graph 0 to 1, graph 1 nohead front lw 2 dt 2 lc rgb '#a50026'
  set boxwidth mw
  if (nm > 0) {
    plot csv using (mbin(column(mcol))):(1.0) smooth frequency with boxes lc rgb '#ff8c00' title 'max_modulus (dashed: stability limit 1)'
  } else {
    set label 1 'no sample has Floquet multipliers' at graph 0.5, 0.5 center
    plot [0:1] [0:1] 2 notitle
    unset label 1
  }
  unset multiplot
  unset output
}
