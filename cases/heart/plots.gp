# gnuplot -e "data='pv.dat'; outdir='DIR'" cases/heart/plots.gp
# pv.dat columns: t (ms), V (ml), P (kPa) -- written by cases/heart/run.sh from globals.csv.
set terminal pngcairo size 900,650 enhanced font ",12"
set grid
set key top right
set output outdir.'/pv_loop.png'
set title 'LV pressure-volume loop'
set xlabel 'LV cavity volume (ml)'
set ylabel 'LV pressure (kPa)'
plot data using 2:3 with linespoints pt 7 ps 0.4 lw 2 title 'lv'
set output outdir.'/pressure_volume_time.png'
set title 'LV pressure and volume over the beat'
set xlabel 'time (ms)'
set ylabel 'LV pressure (kPa)'
set y2label 'LV cavity volume (ml)'
set ytics nomirror
set y2tics
plot data using 1:3 axes x1y1 with lines lw 2 title 'pressure (kPa)', \
     data using 1:2 axes x1y2 with lines lw 2 dt 2 title 'volume (ml)'
