#!/usr/bin/env bash
# Rubjerg Knude (examples/rubjerg_knude.toml) under each [[contact]] detection rule, "fill" and
# "traction" (docs/studies/2026-12-04-contact-detection-rules.md): runs a copy of the example
# per rule and prints, from each run's series.csv, when the slide came to rest, the runout, the
# peak mean speed and the energy of the rain stage (from the trigger at t = 6 s) with its
# balance against the gravity work. About a minute of wall time per run on one thread.
#   bash scripts/contact_detection.sh build/skred out/contact_detection
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 SKRED OUTDIR" >&2; exit 2; }
skred=$(realpath "$1")
out=$2
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
ln -sfn "$here/examples/rubjerg_knude" "$out/rubjerg_knude"  # the example's CSV profiles
for rule in fill traction; do
  sed "s/^friction = 0.6$/friction = 0.6\ndetection = \"$rule\"/" "$here/examples/rubjerg_knude.toml" \
    > "$out/rubjerg_knude_$rule.toml"
  grep -q "^detection = \"$rule\"" "$out/rubjerg_knude_$rule.toml"
  SECONDS=0
  "$skred" run "$out/rubjerg_knude_$rule.toml" -o "$out/$rule" --threads 1 --overwrite > "$out/$rule.log"
  echo "$rule: $SECONDS s wall"
done
python3 - "$out" <<'EOF'
import csv, sys
for rule in ("fill", "traction"):
    rows = list(csv.DictReader(open(f"{sys.argv[1]}/{rule}/series.csv")))
    v = lambda r, k: float(r[k])
    trigger = [r for r in rows if v(r, "time") <= 6.0 + 1e-9][-1]
    end = rows[-1]
    peak = max((r for r in rows if v(r, "time") > 6.0), key=lambda r: v(r, "mean_speed"))
    d = {k: v(end, k) - v(trigger, k) for k in ("gravity_work", "plastic_dissipation", "contact_work",
                                                "transfer_dissipation", "strain_energy", "kinetic_energy",
                                                "friction_work")}
    balance = (sum(d.values()) - 2 * d["gravity_work"]) / d["gravity_work"]
    print(f"{rule}: at rest at {v(end, 'time'):.2f} s ({v(end, 'time') - 6:.1f} s after the trigger), "
          f"runout {v(end, 'runout'):.2f} m, peak mean speed {v(peak, 'mean_speed'):.3f} m/s at "
          f"{v(peak, 'time'):.2f} s; rain stage: gravity work {d['gravity_work'] / 1e6:.1f} MJ, plastic "
          f"{d['plastic_dissipation'] / 1e6:.1f}, contact {d['contact_work'] / 1e6:.1f}, transfer "
          f"{d['transfer_dissipation'] / 1e6:.1f}, strain {d['strain_energy'] / 1e6:.2f}; balance "
          f"{100 * balance:+.2f} % of the gravity work")
EOF
