# gnuplot -e "data='pv.dat'; outdir='DIR'; period=800" cases/heart/plots.gp
#   optional: scar='pv_scar.dat' also writes pv_loop_scar.png (healthy and scarred loops).
# pv*.dat columns: t (ms), V (ml), P (kPa) -- written by cases/heart/run.sh from globals.csv.
if (!exists("period")) period = 800
set terminal pngcairo size 900,650 enhanced font ",12"
set grid
set key top right
set output outdir.'/pv_loop.png'
set title 'LV pressure-volume loops (healthy), beats 1 and 2'
set xlabel 'LV cavity volume (ml)'
set ylabel 'LV pressure (kPa)'
plot data using ($1 < period ? $2 : 1/0):3 with linespoints pt 7 ps 0.4 lw 2 title 'beat 1', \
     data using ($1 >= period ? $2 : 1/0):3 with linespoints pt 6 ps 0.6 lw 1 dt 2 title 'beat 2'
set output outdir.'/pressure_volume_time.png'
set title 'LV pressure and volume over two beats (healthy)'
set xlabel 'time (ms)'
set ylabel 'LV pressure (kPa)'
set y2label 'LV cavity volume (ml)'
set ytics nomirror
set y2tics
plot data using 1:3 axes x1y1 with lines lw 2 title 'pressure (kPa)', \
     data using 1:2 axes x1y2 with lines lw 2 dt 2 title 'volume (ml)'
if (exists("scar")) {
  unset y2label
  unset y2tics
  set ytics mirror
  set output outdir.'/pv_loop_scar.png'
  set title 'LV pressure-volume loops: healthy vs apical-anterior scar (beat 2)'
  set xlabel 'LV cavity volume (ml)'
  set ylabel 'LV pressure (kPa)'
  plot data using ($1 >= period ? $2 : 1/0):3 with linespoints pt 7 ps 0.4 lw 2 title 'healthy', \
       scar using ($1 >= period ? $2 : 1/0):3 with linespoints pt 5 ps 0.4 lw 2 title 'scar'
}
