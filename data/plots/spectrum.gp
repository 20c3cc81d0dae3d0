# spectrum.gp: the figure of `usm simulate --spectrum PREFIX`, a static script
# (share/usm/plots/spectrum.gp).  usm writes PREFIX.gp: the values below, then
# this text; `gnuplot PREFIX.gp` re-plots.
#   prefix, csv, title          output prefix, the spectrum (PREFIX.csv), the title
#   f [Hz]                      the excitation frequency: its harmonics are dotted
#   nh_rotor_speed, nh_theta, nh_F_n [Hz]   the strongest line of each channel that
#                               is not a harmonic of f (0: none), marked
#   nh_*_amp                    its amplitude
#   fmax [Hz]                   the last bin (half the sampling rate)
#   peak_rotor_speed, peak_theta, peak_F_n   each channel's largest amplitude; 0: the
#                               channel is constant over the window, its panel says
#                               so (a log scale has nothing to draw)
# Columns by name (docs/simulate.md, "The spectrum").  Amplitudes on a log
# scale: a sinusoid A sin(2 pi f t) shows as a line of height A.
set datafile separator ','
k(c) = column("frequency [Hz]") * 1e-3
pos(v) = v > 0 ? v : NaN
set grid
set key top right
set logscale y
set format y '%.0e'
set xrange [0:fmax * 1e-3]
set xlabel 'frequency [kHz]'
nh = 'nh_rotor_speed nh_theta nh_F_n'
if (!exists("peak_rotor_speed")) peak_rotor_speed = 1
if (!exists("peak_theta")) peak_theta = 1
if (!exists("peak_F_n")) peak_F_n = 1
do for [fmt in 'png svg'] {
  if (fmt eq 'png') {
    if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {
      set terminal pngcairo size 1000,1100 noenhanced
    } else {
      set terminal png size 1000,1100 noenhanced
    }
  } else {
    set terminal svg size 1000,1100 noenhanced
  }
  set output prefix.'.'.fmt
  set multiplot layout 3,1 title title
  do for [c = 1:3] {
    unset arrow
    unset label
    do for [h = 1:int(fmax / f)] {
      set arrow h from h * f * 1e-3, graph 0 to h * f * 1e-3, graph 1 nohead dt 3 lc rgb '#bbbbbb'
    }
    fr = c == 1 ? nh_rotor_speed : c == 2 ? nh_theta : nh_F_n
    am = c == 1 ? nh_rotor_speed_amp : c == 2 ? nh_theta_amp : nh_F_n_amp
    if (fr > 0) {
      set label 1 sprintf(' %.4g kHz (not a harmonic of f)', fr * 1e-3) at fr * 1e-3, am point pt 7 ps 1.2 lc rgb '#d62728' tc rgb '#d62728' offset 0.5, 0.5
    }
    col = c == 1 ? 'rotor_speed [1/s]' : c == 2 ? 'theta [rad]' : 'F_n [N]'
    pk = c == 1 ? peak_rotor_speed : c == 2 ? peak_theta : peak_F_n
    set ylabel 'amplitude of '.col
    if (pk > 0) {
      set autoscale y
      plot csv using (k(0)):(pos(column(col))) with lines lc rgb '#08306b' notitle
    } else {
      set yrange [1e-3:1]
      set label 2 col.': constant over the window: an empty spectrum' at graph 0.5, 0.5 center
      plot 1e-9 notitle
    }
  }
  unset multiplot
  set output
}
