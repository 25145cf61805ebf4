# docs/seed002_scene.png from docs/seed002_scene.csv (written by docs/seed002_scene.sh):
# gnuplot -e "csv='docs/seed002_scene.csv'" docs/seed002_scene.gp
set terminal pngcairo size 1200,480 font "sans,11" noenhanced
set output "docs/seed002_scene.png"
set datafile separator ","
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set boxwidth 0.9
set grid ytics
set key top left
set multiplot layout 1,2 title "Seed 002's scene (line-arc-line, R 3 m, 0.5 m/s, w_max 10 deg/s, pose input): DWA against improved DWA"
set ylabel "max abs lateral error e_d (mm)"
set yrange [0:*]
plot "< awk -F, 'NR>1 && $2==\"dwa\"' ".csv using 3:xtic(1) title "DWA" lc rgb "#1f77b4", \
     "< awk -F, 'NR>1 && $2==\"improved_dwa\"' ".csv using 3 title "improved DWA" lc rgb "#d62728"
set ylabel "coverage area of the front and rear wheel tracks (m^2)"
plot "< awk -F, 'NR>1 && $2==\"dwa\"' ".csv using 4:xtic(1) title "DWA" lc rgb "#1f77b4", \
     "< awk -F, 'NR>1 && $2==\"improved_dwa\"' ".csv using 4 title "improved DWA" lc rgb "#d62728"
unset multiplot
