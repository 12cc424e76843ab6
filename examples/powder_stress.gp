# SPDX-License-Identifier: MIT
# docs/images/powder_cohesive_stress.png: the stress in the core of scenes/powder-cohesive.toml's
# pile, coarse-grained along z over the last 10 frames (docs/fields.md):
#   tumble run scenes/powder-cohesive.toml --record powder.bin --record-contacts
#   tumble fields powder.bin -o powder.csv --width 0.01 --axis z --grid 45 --box=-0.03,-0.03,0,0.03,0.03,0.09 --from -10
#   gnuplot examples/powder_stress.gp          # reads powder.csv, writes powder_cohesive_stress.png
# The core is the 6 cm square about the pile's axis. The weight above each point, g times the
# integral of the density from the top down, is summed by awk over the 45 slices of 2 mm: the
# vertical stress at the axis of a pile carries it, minus what the flanks' arching and the
# cohesion hold (columns of the CSV: z $3, density $4, packing fraction $5, contact sigma_xx $6,
# sigma_yy $7, sigma_zz $8). Within a few kernel widths of the ground the fields fall off: the
# kernel reaches below the ground, where there are no grains (and the ground's forces are not
# contacts between grains).
set terminal pngcairo size 1000,640 font ",12"
set output "powder_cohesive_stress.png"
set datafile separator whitespace
data = "< tail -n +2 powder.csv | tac | awk -F, '{w += 9.81 * 0.002 * $4; print $3, $4, $5, $8, w - 0.5 * 9.81 * 0.002 * $4, 0.5 * ($6 + $7)}'"
set multiplot layout 1,2 title "Cohesive polydisperse pile, 1500 grains (sjkr, k_c = 7e5 J/m^3): its core coarse-grained along z, w = 10 mm"
set xlabel "stress [Pa]"; set ylabel "z [m]"; set key top right
set yrange [0:0.08]
plot data u 4:1 w l lw 3 lc rgb "#c03020" t "contact stress {/Symbol s}_{zz}", \
     data u 6:1 w l lw 2 lc rgb "#2060c0" t "contact stress ({/Symbol s}_{xx} + {/Symbol s}_{yy}) / 2", \
     data u 5:1 w l lw 1 dt 2 lc rgb "black" t "weight above, g {/Symbol \362}_z^{/Symbol \245} {/Symbol r} dz'"
set xlabel "packing fraction"; set xrange [0:0.7]; unset ylabel
plot data u 3:1 w l lw 3 lc rgb "#208040" t "{/Symbol n}(z)"
unset multiplot
