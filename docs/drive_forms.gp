# docs/drive_forms.png, drawn by docs/seed002_scene.sh: the runs of improved DWA in the three drive
# forms of scenarios/dual_steer_improved_dwa_pose.yaml in DIR/improved_dwa_{both_steer,rear_drive,
# front_drive} and one with path.csv in DIR/path: gnuplot -e "dir='DIR'" docs/drive_forms.gp
set terminal pngcairo size 1500,520 font "sans,10" noenhanced
set output "docs/drive_forms.png"
set datafile separator ","
set multiplot layout 1,3 title "Seed 002 drive forms, improved DWA, line-arc-line path (R 3 m), 0.5 m/s: wheel-centre tracks on the arc"
set xlabel "x (m)"; set ylabel "y (m)"
set size ratio -1
set xrange [2.8:6.4]; set yrange [-0.2:3.4]
set grid
do for [f in "both_steer rear_drive front_drive"] {
  set title sprintf("%s", f)
  plot dir."/path/path.csv" using 2:3 skip 1 with lines lw 3 lc rgb "#999999" title "path", \
       sprintf("%s/improved_dwa_%s/trace.csv", dir, f) using 24:25 skip 1 with lines lw 1.5 lc rgb "#1f77b4" title "front wheel", \
       sprintf("%s/improved_dwa_%s/trace.csv", dir, f) using 26:27 skip 1 with lines lw 1.5 lc rgb "#d62728" title "rear wheel", \
       sprintf("%s/improved_dwa_%s/trace.csv", dir, f) using 2:3 skip 1 with lines dt 2 lc rgb "black" title "reference point"
}
unset multiplot
