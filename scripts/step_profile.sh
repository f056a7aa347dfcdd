#!/usr/bin/env bash
# Where a bed's step spends its instructions: callgrind on one thread for
# STEPS and for 2·STEPS steps, each function's inclusive count differenced
# over STEPS and divided by the bodies, so loading, the first force
# computation and the start-up checks drop out. Instruction counts do not
# depend on the machine's load.
#
# Usage: scripts/step_profile.sh [SCENE] [STEPS] [DIR]
#   defaults: scenarios/bed_10k.toml 40 /tmp/step_profile
# Prints instructions per body-step: the whole step and its parts.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenarios/bed_10k.toml}
steps=${2:-40}
dir=${3:-/tmp/step_profile}
mkdir -p "$dir"
cargo build --release -q
bin=target/release/fibresim
dt=$(python3 -c 'import sys, tomllib; print(tomllib.load(open(sys.argv[1], "rb"))["simulation"]["dt"])' "$scene")
for k in 1 2; do
    valgrind --tool=callgrind --callgrind-out-file="$dir/cg.$k" \
        "$bin" run "$scene" --t-end "$(python3 -c "print($k*$steps*$dt)")" \
        --threads 1 -q --out "$dir/run.$k" --force 2>"$dir/valgrind.$k.log"
done
python3 - "$dir" "$steps" "$bin" "$scene" <<'PY'
import json, re, subprocess, sys
d, steps, binary, scene = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
bodies = json.load(open(f"{d}/run.1/summary.json"))["bodies"]
def functions(path):
    # Inclusive counts of whole functions (the lines callgrind_annotate
    # tags with the binary; the others are inlined code by source file).
    # Run from "/": from the source tree it names some files relatively
    # and splits a function's count between the two names.
    out = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", "--auto=no", path],
                         capture_output=True, text=True, check=True, cwd="/").stdout
    f = {}
    for line in out.splitlines():
        m = re.match(r"\s*([\d,]+) \([^)]*\)\s+(\S.*?)(?: \[(.*)\])?$", line)
        if not m:
            continue
        name = m.group(2).split(":", 1)[-1]
        if m.group(2) == "PROGRAM TOTALS" or m.group(3):
            f[name] = max(f.get(name, 0), int(m.group(1).replace(",", "")))
    return f
one, two = functions(f"{d}/cg.1"), functions(f"{d}/cg.2")
def per(name):
    return (two.get(name, 0) - one.get(name, 0)) / steps / bodies
total = per("PROGRAM TOTALS")
ff = "fibresim::contact::fibre_fibre::"
# The dispatch, or, where it is inlined into the pair loop, its kernels'
# functions (the fibre kernels; the sphere kernels are inlined too).
kernels = per("fibresim::contact::dispatch::contacts_remembering") or (
    per(ff + "contact_fibre_fibre_remembering") + per("fibresim::contact::fibre_wall::contact_fibre_wall"))
rows = [
    ("the whole step", total),
    ("forces (the contact stage)", per("fibresim::contact::stage::ContactStage::compute")),
    ("  neighbour-list builds", per("fibresim::contact::broad::NeighbourList::build")),
    ("  the pair loop", per("fibresim::contact::blocks::Blocks::lists")),
    ("    the kernels' dispatch and kernels", kernels),
    ("      fibre–fibre", per(ff + "contact_fibre_fibre_remembering")),
    ("        kept in their regime (one kernel)", per(ff + "end_involved::remembered_in_regime")),
    ("        end-involved through the dispatch", per(ff + "end_involved::penetration_smoothed")),
    ("        of which rim–rim", per(ff + "features::rim_rim::rim_rim")),
]
forces = per("fibresim::contact::stage::ContactStage::compute")
loop = per("fibresim::contact::blocks::Blocks::lists")
rows[2] = ("  neighbour-list builds (in the window)", rows[2][1])
rows.insert(4, ("    the pair loop less the kernels (candidates, laws, sums)", loop - kernels))
rows.append(("integration and the rest (the step less the forces)", total - forces))
rows.append(("not the kernels (the step less dispatch and kernels)", total - kernels))
print(f"{scene}: {bodies} bodies, steps {steps} → {2 * steps}, instructions per body-step")
for name, v in rows:
    print(f"{v:9.0f}  {name}")
PY
