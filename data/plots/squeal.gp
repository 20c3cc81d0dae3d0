# squeal.gp: a static script of usm report (share/usm/plots/).
# Re-plot: cd into the report's directory and run  gnuplot squeal.gp
# Reads squeal_spectrum.csv (the amplitude spectrum of rotor speed, tilt and
# F_n just past the 4-DOF Neimark-Sacker point, a simulation from rest, Hann
# window over its second half), squeal_amplitude.csv (one row per mode split:
# the RMS of what does not repeat with the excitation period) and
# squeal_values.csv (the Neimark-Sacker point, its squeal frequency, f);
# columns by name (docs/cli.md, "CSV files"); writes squeal.png and .svg.
reset session
set datafile separator ","
set encoding utf8
set grid lc rgb "#dddddd"
vals = "squeal_values.csv"
stats vals using (ns = column("ns_percent [%]"), fs = column("squeal_frequency_kHz [kHz]"), f = column("f_kHz [kHz]"), sp = column("spectrum_percent [%]"), nsbad = strcol("invalid_reason"), 0) nooutput
# a squeal frequency of an orbit the model does not describe is labelled so
flag = strlen(nsbad) > 0 ? sprintf(" (model invalid: %s)", nsbad) : ""
pos(v) = v > 0 ? v : NaN
do for [fmt in "png svg"] {
  if (fmt eq "png") {
    set terminal pngcairo size 1100,1000 enhanced font "DejaVu Sans,10"
  } else {
    set terminal svg size 1100,1000 enhanced font "DejaVu Sans,10"
  }
  set output "squeal.".fmt
  set multiplot layout 2,1
  # the spectrum: harmonics of f dotted, the squeal's sidebands f -+ f_s dashed
  set title sprintf("Amplitude spectrum at mode split %.3g %% (Neimark-Sacker point %.4g %%)", sp, ns)
  set xlabel "frequency [kHz]"
  set ylabel "amplitude (Hann window)"
  set logscale y
  set format y "10^{%L}"
  set xrange [0:5 * f]
  set key top right font ",9"
  unset arrow
  do for [h = 1:5] {
    set arrow h from h * f, graph 0 to h * f, graph 1 nohead dt 3 lc rgb "#999999"
  }
  set arrow 11 from f - fs, graph 0 to f - fs, graph 1 nohead dt 2 lc rgb "#c0392b"
  set arrow 12 from f + fs, graph 0 to f + fs, graph 1 nohead dt 2 lc rgb "#c0392b"
  set label 1 sprintf("f - f_s = %.4g kHz%s", f - fs, flag) at f - fs, graph 0.95 right offset -0.5, 0 tc rgb "#c0392b" font ",9" noenhanced
  set label 2 sprintf("f + f_s = %.4g kHz%s", f + fs, flag) at f + fs, graph 0.95 left offset 0.5, 0 tc rgb "#c0392b" font ",9" noenhanced
  plot "squeal_spectrum.csv" using (column("frequency_kHz [kHz]")):(pos(column("F_n [N]"))) with lines lw 1.2 lc rgb "#1f5fa8" title "F_n [N]", \
       "" using (column("frequency_kHz [kHz]")):(pos(column("rotor_speed [1/s]"))) with lines lw 1 lc rgb "#e08214" title "rotor speed [1/s]"
  unset label
  unset arrow
  # the vibration that does not repeat with the excitation period, against the mode split
  set title "The parasitic vibration: RMS of the motion minus its synchronous average (second half of a 10 ms run from rest)"
  set xlabel "mode split s [%]"
  set ylabel "RMS of the tilt [rad]"
  set y2label "RMS of the rotor speed [1/s]"
  set logscale y2
  set format y2 "10^{%L}"
  set ytics nomirror
  set y2tics
  set autoscale x
  set key top left font ",9"
  set arrow 1 from ns, graph 0 to ns, graph 1 nohead dt 2 lc rgb "#c0392b"
  set label 1 sprintf(" Neimark-Sacker %.4g %%%s", ns, flag) at ns, graph 0.08 left tc rgb "#c0392b" font ",9" noenhanced
  plot "squeal_amplitude.csv" using (column("mode_split_percent [%]")):(pos(column("rms_theta [rad]"))) with linespoints pt 7 lw 1.5 lc rgb "#1f5fa8" title "tilt θ", \
       "" using (column("mode_split_percent [%]")):(pos(column("rms_rotor_speed [1/s]"))) axes x1y2 with linespoints pt 5 lw 1.5 lc rgb "#e08214" title "rotor speed"
  unset multiplot
  set output
}
