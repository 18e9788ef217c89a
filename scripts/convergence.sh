#!/bin/sh
# Runout under grid refinement (issue 12; Thesis §5.1 and §5.2, fig. 5.18): the soil column
# of examples/soil_column.toml (h = 0.5, 0.25, 0.125 m; time step 2 ms per metre of cell, the
# example's c dt / h = 0.45) and the slope of examples/slope_collapse.toml (phi = 18 deg,
# c = 5 kPa; h = 1, 0.5, 0.25 m, its cfl), for each velocity transfer given, 3 x 3 points per
# cell throughout. Prints one table row per run: problem, transfer, cell size, points, the
# last stage's runout (summary.json: continuous, from the points and their half-sizes, along the
# connected deposit), how the stage ended, simulated and wall seconds. Takes tens of minutes
# (the finest slope is 70,000 points for 13 s); run it beside other work with nice.
# With three sizes or more, per problem and transfer, Richardson's extrapolation of the runout
# and of the gravity work over the three finest (`skred extrapolate`, Celik et al. 2008).
# Then, per problem, scripts/deposit_front.py: the front at thicknesses fixed in metres
# (2, 4, 10 and 20 % of the initial height), the gravity work and the transfer's share of it.
# For a scenario of your own, `skred refine SCENARIO.toml -o OUTDIR --transfers auto,apic` runs the
# same kind of study (h, h/2, h/4, a fixed time step halved with the cell) and prints the verdict.
# PROBLEMS=slope50 runs examples/slope_50m.toml instead (the slope at the thesis's scale, 50 m
# high; h = 5, 2.5, 1.25 m: 60, 120, 240 cells across its grid, and by the count of the soil's
# cells the thesis's 39, 77, 154 across; SIZES="3.3333333333333335 1.6666666666666667
# 0.8333333333333334" starts at the thesis's 58: docs/studies/2026-11-29-slope-50m-at-the-thesis-discretisation.md).
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
#   SHIFTS="0 1 2 3 4" ...   (each size run once per k, with the column, or the slope's face,
#                               moved k h / 5 along +x against the grid: where the material's
#                               edges fall in their cells; the rows read h+k, and a line per size
#                               gives the mean runout, its half-range and the mean's change)
#   HALF=1 PROBLEMS=column ...   (the column's symmetric half: the grid from its axis, x = 0 to
#                               20 m, with the roller side at the axis; half the points and time,
#                               the same tips to 0.3 % at h/4: docs/studies/2026-11-29-column-at-h16.md;
#                               deposit_front.py's gravity work is then the half's)
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
shifts=${SHIFTS:-0}
half=${HALF:-0}
if [ "$half" = 1 ] && { [ "$shifts" != 0 ] || [ "$problems" != column ]; }; then
  echo "HALF=1 takes PROBLEMS=column and no SHIFTS (a shifted column is not symmetric about the axis)" >&2
  exit 4
fi
tag=$volumetric
splitexpr='s/^$//'  # (nothing)
if [ "$split" = 1 ]; then
  tag=${volumetric}_split
  splitexpr='s/^shape = /split = true\nshape = /'
fi
tag=$tag${period:+_p$period}
[ "$dtf" = 1 ] || tag=${tag}_dt$dtf
tag=$tag${interp:+_$interp}${thick:+_t$thick}${ppc:+_ppc$ppc}${order:+_m$order}${restm:+_r$restm}
[ "$half" = 1 ] && tag=${tag}_half
# moved PROBLEM H K > sed expression: the column's sides, or the slope's toe and crest vertices,
# moved by K H / 5 along +x (K = 0: unchanged).
moved() {
  awk -v p="$1" -v h="$2" -v k="$3" 'BEGIN {
    d = k * h / 5
    if (p == "column") printf "s/^min = \\[15.0,/min = [%.9g,/;s/^max = \\[25.0,/max = [%.9g,/", 15 + d, 25 + d
    else if (p == "slope") printf "s/\\[30.28, 4.0\\], \\[16.0, 14.0\\]/[%.9g, 4.0], [%.9g, 14.0]/", 30.28 + d, 16 + d
    else printf "s/\\[151.4, 20.0\\], \\[80.0, 70.0\\]/[%.9g, 20.0], [%.9g, 70.0]/", 151.4 + d, 80 + d }'
}
# mean_of FORMAT VALUES... > their mean, printed with FORMAT.
mean_of() {
  f=$1
  shift
  echo "$@" | awk -v f="$f" '{ s = 0; for (i = 1; i <= NF; i++) s += $i; printf f, s / NF }'
}
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
    before=
    tips=
    works=
    for h in $sizes; do
      dt=
      [ "$problem" = column ] && dt=$(awk -v h="$h" -v f="$dtf" 'BEGIN { printf "%g", 0.002 * h * f }')
      extra=
      [ -n "$period" ] && [ "$tr" = xpic ] && extra="\\nxpic_period = $period"
      [ -n "$order" ] && [ "$tr" = xpic ] && extra="$extra\\nxpic_order = $order"
      runouts=
      gws=
      for k in $shifts; do
        dir=$out/${problem}_${tr}_${tag}_$h
        [ "$shifts" = 0 ] || dir=${dir}_s$k
        dirs="$dirs $dir"
        scenario "$file" "$h" "$dt" "$tr" "$extra" > "$dir.toml"
        if [ "$half" = 1 ]; then
          sed -i -e 's/^size = \[40.0, 7.5\]/size = [20.0, 7.5]/' -e 's/^min = \[15.0, 0.0\]/min = [0.0, 0.0]/' \
            -e 's/^max = \[25.0, 5.0\]/max = [5.0, 5.0]/' "$dir.toml"
          if [ "$(scenario "$file" "$h" "$dt" "$tr" "$extra" | diff - "$dir.toml" | grep -c '^>' || true)" != 3 ]; then
            echo "HALF: $file's grid and column are not where the script looks for them" >&2
            exit 4
          fi
        fi
        if [ "$k" != 0 ]; then
          # A pattern that no longer matches the example would run another body: the column's
          # min and max lines, or the slope's vertices line, must each have changed.
          sed -i -e "$(moved "$problem" "$h" "$k")" "$dir.toml"
          changed=$(scenario "$file" "$h" "$dt" "$tr" "$extra" | diff - "$dir.toml" | grep -c '^>' || true)
          if [ "$changed" != "$([ "$problem" = column ] && echo 2 || echo 1)" ]; then
            echo "SHIFTS: $file's edges are not where moved() looks for them" >&2
            exit 4
          fi
        fi
        "$skred" run "$dir.toml" -o "$dir" --overwrite --threads "$threads" \
          > "$dir.log" 2>&1 || true
        row=$(/usr/bin/python3 - "$dir/summary.json" "$problem" "$tr" "$h" "$k" << 'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
st = s["stages"][-1]
h = sys.argv[4][:6] + ("" if sys.argv[5] == "0" else "+" + sys.argv[5])
print("%-7s %-6s %6s %8d %9.3f %-9s %7.2f %7.0f" % (sys.argv[2], sys.argv[3], h, s["particles"],
      st["runout"], st.get("ended_by", s["status"]), st["end_time"] - st["start_time"], s.get("wall_seconds", 0)))
EOF
)
        echo "$row"
        runouts="$runouts $(echo "$row" | awk '{ print $5 }')"
        gws="$gws $(/usr/bin/python3 -c 'import json, sys
print(json.load(open(sys.argv[1]))["stages"][-1]["gravity_work"])' "$dir/summary.json" 2> /dev/null || echo nan)"
      done
      # The size's values for Richardson's extrapolation below (the means over the shifts).
      tips="$tips $h=$(mean_of %.9g $runouts)"
      works="$works $h=$(mean_of %.9g $gws)"
      # Several shifts: the mean runout at this size, its half-range, the mean's change per size.
      if [ "$shifts" != 0 ]; then
        mean=$(mean_of %.6g $runouts)
        echo $runouts | awk -v p="$problem" -v t="$tr" -v h="$h" -v m="$mean" -v b="$before" '{
          lo = $1; hi = $1
          for (i = 2; i <= NF; i++) { if ($i < lo) lo = $i; if ($i > hi) hi = $i }
          pct = m > 0 ? 50 * (hi - lo) / m : 0
          printf "%-7s %-6s %6s the mean of %d shifts %.3f m, half-range %.3f m (%.1f %%)", p, t,
            substr(h, 1, 6), NF, m, (hi - lo) / 2, pct
          if (b != "" && b > 0) printf "; %+.1f %% from the size before", 100 * (m / b - 1)
          printf "\n" }'
        before=$mean
      fi
    done
    # Three sizes or more: Richardson's extrapolation of the runout (the mean over the shifts) and
    # of the gravity work over the three finest (skred extrapolate; Celik et al. 2008).
    if [ "$(echo $sizes | wc -w)" -ge 3 ]; then
      "$skred" extrapolate $tips --name "$problem $tr runout" --unit m 2>&1 | head -n 1 || true
      "$skred" extrapolate $works --name "$problem $tr gravity work" --unit J/m 2>&1 | head -n 1 || true
    fi
    fronts="$fronts
$(/usr/bin/python3 "$here/scripts/deposit_front.py" "$height" $dirs)"
  done
done
echo "$fronts"
