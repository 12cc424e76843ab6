# SPDX-License-Identifier: MIT
# docs/images/column_stress.png from the profile of scenes/column.toml (docs/fields.md):
#   tumble run scenes/column.toml
#   tumble fields column.bin -o column.csv --width 0.005 --axis z --grid 300 --box 0,0,0,0.1,0.1,0.15 --from -10
#   gnuplot examples/column_stress.gp          # reads column.csv, writes column_stress.png
# The weight above each point, g times the integral of the density from the top down, is summed
# by awk over the 300 slices of 0.5 mm (columns of the CSV: z $3, density $4, packing fraction $5,
# kinetic sigma_zz $15, contact sigma_zz $21).
set terminal pngcairo size 1000,640 font ",12"
set output "column_stress.png"
set datafile separator whitespace
data = "< tail -n +2 column.csv | tac | awk -F, '{w += 9.81 * 0.0005 * $4; print $3, $4, $5, $21, w - 0.5 * 9.81 * 0.0005 * $4, $15}'"
set multiplot layout 1,2 title "Settled column, 972 spheres (r = 5 mm), periodic in x and y: coarse-grained along z, w = 5 mm"
set xlabel "stress [Pa]"; set ylabel "z [m]"; set key top right
set yrange [0:0.11]
plot data u 4:1 w l lw 3 lc rgb "#c03020" t "contact stress {/Symbol s}_{zz}", \
     data u 5:1 w l lw 1 dt 2 lc rgb "black" t "weight above, g {/Symbol \362}_z^{/Symbol \245} {/Symbol r} dz'", \
     data u ($6*1e6):1 w l lw 2 lc rgb "#2060c0" t "kinetic {/Symbol s}^k_{zz} {/Symbol \264} 10^6"
set xlabel "packing fraction"; set xrange [0:0.7]; unset ylabel
plot data u 3:1 w l lw 3 lc rgb "#208040" t "{/Symbol n}(z)"
unset multiplot
