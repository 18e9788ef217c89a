#!/bin/sh
# Runout under grid refinement (issue 12; Thesis §5.1 and §5.2, fig. 5.18): the soil column
# of examples/soil_column.toml (h = 0.5, 0.25, 0.125 m; time step 2 ms per metre of cell, the
# example's c dt / h = 0.45) and the slope of examples/slope_collapse.toml (phi = 18 deg,
# c = 5 kPa; h = 1, 0.5, 0.25 m, its cfl), for each velocity transfer given, 3 x 3 points per
# cell throughout. Prints one table row per run: problem, transfer, cell size, points, the
# last stage's runout (summary.json: continuous, from the points and their half-sizes, along the
# connected deposit), how the stage ended, simulated and wall seconds. Takes tens of minutes
# (the finest slope is 70,000 points for 13 s); run it beside other work with nice.
# Then, per problem, scripts/deposit_front.py: the front at thicknesses fixed in metres
# (2, 4, 10 and 20 % of the initial height), the gravity work and the transfer's share of it.
# For a scenario of your own, `skred refine SCENARIO.toml -o OUTDIR --transfers auto,apic` runs the
# same kind of study (h, h/2, h/4, a fixed time step halved with the cell) and prints the verdict.
# PROBLEMS=slope50 runs examples/slope_50m.toml instead (the slope at the thesis's scale, 50 m
# high; h = 5, 2.5, 1.25 m: 60, 120, 240 cells across its grid, and by the count of the soil's
# cells the thesis's 39, 77, 154 across; SIZES="3.3333333333333335 1.6666666666666667
# 0.8333333333333334" starts at the thesis's 58: docs/method.md, "At the thesis's own discretisation").
#   scripts/convergence.sh [build/skred] [transfers...]     e.g.  scripts/convergence.sh build/skred xpic apic
#   PROBLEMS="column" THREADS=2 OUT=out/convergence scripts/convergence.sh
#   PROBLEMS=column SIZES="0.125 0.0625" scripts/convergence.sh build/skred apic   (other sizes)
#   VOLUMETRIC=cell-average scripts/convergence.sh build/skred apic   (solver.volumetric_strain)
#   SPLIT=1 VOLUMETRIC=cell-average scripts/convergence.sh build/skred apic   (split = true on the
#                                                  body: material-point splitting, Thesis §3.4)
#   XPIC_PERIOD=2 scripts/convergence.sh build/skred xpic   (solver.xpic_period: XPIC once per 2 h/c)
#   DT_FACTOR=0.5 PROBLEMS=column ...   (the column's time step times 0.5)
#   INTERPOLATION=bspline ...   (solver.interpolation; the examples use gimp)
#   RUNOUT_THICKNESS=1.0 ...   (runout_thickness [m] of the stages with a rest criterion: the
#                               runout where the deposit is that thick, not half a cell)
#   REST_MEASURE=displacement ...   (rest_measure of the stages with a rest criterion: what the
#                               rest test reads, docs/method.md "The rest test")
#   XPIC_ORDER=4 ... xpic   (solver.xpic_order: the m of XPIC(m))
#   PPC=2 ...   (particles_per_cell: n x n points per cell instead of the examples' 3 x 3)
#   scripts/convergence.sh build/skred auto   (the engine's defaults: for these slides XPIC once
#                               per 2 h/c; with VOLUMETRIC=auto also the cell-averaged strain)
set -e
skred=${1:-build/skred}
[ $# -gt 0 ] && shift
transfers=${*:-flip}
problems=${PROBLEMS:-column slope}
threads=${THREADS:-1}
out=${OUT:-out/convergence}
volumetric=${VOLUMETRIC:-point}
split=${SPLIT:-0}
period=${XPIC_PERIOD:-}
dtf=${DT_FACTOR:-1}
interp=${INTERPOLATION:-}
thick=${RUNOUT_THICKNESS:-}
restm=${REST_MEASURE:-}
ppc=${PPC:-}
order=${XPIC_ORDER:-}
tag=$volumetric
splitexpr='s/^$//'  # (nothing)
if [ "$split" = 1 ]; then
  tag=${volumetric}_split
  splitexpr='s/^shape = /split = true\nshape = /'
fi
tag=$tag${period:+_p$period}
[ "$dtf" = 1 ] || tag=${tag}_dt$dtf
tag=$tag${interp:+_$interp}${thick:+_t$thick}${ppc:+_ppc$ppc}${order:+_m$order}${restm:+_r$restm}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"

# scenario FILE H DT TRANSFER EXTRA > toml: the example at cell size H (DT: fixed time step, or
# empty to keep the example's cfl), with the velocity transfer, no PIC share and the [solver]
# lines EXTRA (sed's \n between lines).
scenario() {
  sed -e "s/^cell_size = .*/cell_size = $2/" \
    -e '/^pic_fraction/d' -e '/^velocity_transfer/d' -e '/^xpic_period/d' -e '/^volumetric_strain/d' \
    -e "s/^\[solver\]$/[solver]\nvelocity_transfer = \"$4\"\nvolumetric_strain = \"$volumetric\"$5/" \
    ${3:+-e "s/^time_step = .*/time_step = $3/"} \
    ${interp:+-e "s/^interpolation = .*/interpolation = \"$interp\"/"} \
    ${thick:+-e "s/^rest_time = \(.*\)$/rest_time = \1\nrunout_thickness = $thick/"} \
    ${restm:+-e "s/^rest_time = \(.*\)$/rest_time = \1\nrest_measure = \"$restm\"/"} \
    ${ppc:+-e "s/^particles_per_cell = .*/particles_per_cell = $ppc/"} \
    -e "$splitexpr" "$1"
}

fronts=
echo "solver.volumetric_strain = \"$volumetric\"$([ "$split" = 1 ] && echo ', split = true')${period:+, xpic_period = $period}${interp:+, interpolation = \"$interp\"}${thick:+, runout_thickness = $thick}${restm:+, rest_measure = \"$restm\"}${ppc:+, particles_per_cell = $ppc}"
printf '%-7s %-6s %6s %8s %9s %-9s %7s %7s\n' problem transf h points runout_m ended_by t_s wall_s
for tr in $transfers; do
  for problem in $problems; do
    case $problem in
      column) file=$here/examples/soil_column.toml; sizes="0.5 0.25 0.125"; height=5 ;;
      slope) file=$here/examples/slope_collapse.toml; sizes="1.0 0.5 0.25"; height=10 ;;
      slope50) file=$here/examples/slope_50m.toml; sizes="5 2.5 1.25"; height=50 ;;
      *) echo "unknown problem $problem" >&2; exit 4 ;;
    esac
    sizes=${SIZES:-$sizes}
    dirs=
    for h in $sizes; do
      dt=
      [ "$problem" = column ] && dt=$(awk -v h="$h" -v f="$dtf" 'BEGIN { printf "%g", 0.002 * h * f }')
      dir=$out/${problem}_${tr}_${tag}_$h
      dirs="$dirs $dir"
      extra=
      [ -n "$period" ] && [ "$tr" = xpic ] && extra="\\nxpic_period = $period"
      [ -n "$order" ] && [ "$tr" = xpic ] && extra="$extra\\nxpic_order = $order"
      scenario "$file" "$h" "$dt" "$tr" "$extra" > "$dir.toml"
      "$skred" run "$dir.toml" -o "$dir" --overwrite --threads "$threads" \
        > "$dir.log" 2>&1 || true
      /usr/bin/python3 - "$dir/summary.json" "$problem" "$tr" "$h" << 'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
st = s["stages"][-1]
print("%-7s %-6s %6s %8d %9.3f %-9s %7.2f %7.0f" % (sys.argv[2], sys.argv[3], sys.argv[4], s["particles"],
      st["runout"], st.get("ended_by", s["status"]), st["end_time"] - st["start_time"], s.get("wall_seconds", 0)))
EOF
    done
    fronts="$fronts
$(/usr/bin/python3 "$here/scripts/deposit_front.py" "$height" $dirs)"
  done
done
echo "$fronts"
