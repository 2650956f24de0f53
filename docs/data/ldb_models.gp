# Lac du Bonnet in 2D: flat joint vs rigid vs flexible Voronoi grains
# (docs/voronoi.md, "Lac du Bonnet: flat joint vs rigid vs flexible Voronoi").
# Reads the UCS histories and the property table of this directory:
#   cd docs/data && gnuplot ldb_models.gp   (writes ../img/ldb_models.svg)
set terminal svg size 1000,420 font "sans,12" background rgb "white"
set output "../img/ldb_models.svg"
set datafile separator ","
set multiplot layout 1,2

# (a) UCS stress-strain curves (compression positive).
set title "Unconfined compression, Lac du Bonnet calibrations (2D)"
set xlabel "axial strain [%]"
set ylabel "axial stress [MPa]"
set key bottom right
set grid
plot "ldb_ucs_flat_joint.csv" using (-100*$1):(-$2/1e6) with lines lw 2 lc rgb "#1f77b4" title "flat joint (1002 disks)", \
     "ldb_ucs_rigid_voronoi.csv" using (-100*$1):(-$2/1e6) with lines lw 2 lc rgb "#999999" title "rigid Voronoi (200 grains)", \
     "ldb_ucs_flexible_voronoi.csv" using (-100*$1):(-$2/1e6) with lines lw 2 lc rgb "#d62728" title "flexible Voronoi (200 grains)"

# (b) Each property over its Lac du Bonnet target (1 = on target; the band
# is the 10 % tolerance).
set title "Property / Lac du Bonnet target"
set xlabel ""
set ylabel "measured / target"
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set boxwidth 0.9
set yrange [0:1.8]
set key top left
set xtics nomirror
set object 1 rect from graph 0, first 0.9 to graph 1, first 1.1 fc rgb "#dddddd" behind fs solid 0.5 noborder
plot "ldb_models.csv" using 2:xtic(1) title "flat joint" lc rgb "#1f77b4", \
     "" using 3 title "rigid Voronoi" lc rgb "#999999", \
     "" using 4 title "flexible Voronoi" lc rgb "#d62728"
unset multiplot
