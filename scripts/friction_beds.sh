#!/usr/bin/env bash
# Settled beds of aspect ratio 3 and 10, frictionless and with friction
# μ = 0.3 and 0.5 (walls the same μ): packing fraction and coordination
# number (docs/beds.md, "Frictional beds: packing fraction and coordination").
#
#   scripts/friction_beds.sh OUT_DIR [N_AR3 [N_AR10 [CASES [generate]]]]
#
# CASES (default "3:0 3:0.3 3:0.5 10:0 10:0.3 10:0.5") is a list of AR:μ.
# The sizes of docs/beds.md: N_AR3 = 2000, N_AR10 = 1000 (the default). The
# 10⁴-fibre beds of scenarios/ are the same with 10⁴ fibres:
# `scripts/friction_beds.sh out/beds10k 10000 10000 "3:0.5 10:0.5"`.
#
# Each case: `generate` pours N fibres (D = 0.01 m, ρ = 1100 kg/m³,
# E = 5e7 Pa, ν = 0.35) at random into a tall box; `settle` (e = 0.3,
# δt = 2e-5 s, as the shipped beds) runs until the kinetic energy per fibre is
# below 1e-6 J × (L / 0.03 m) (the same energy per unit mass for both aspect
# ratios) and every fibre touches something; the written bed (which keeps its
# friction) is run for 10 steps at δt = 1e-6 s with a VTK frame, whose
# `contacts` array gives the coordination; scripts/bed_packing.py measures.
set -euo pipefail
out=${1:?give an output folder}
n3=${2:-2000}
n10=${3:-1000}
cases=${4:-"3:0 3:0.3 3:0.5 10:0 10:0.3 10:0.5"}
mode=${5:-settle} # "generate": write the poured scenarios only
bin=${FIBRESIM:-target/release/fibresim}
nice=(nice -n 5)
cargo build --release -q
mkdir -p "$out"

for c in $cases; do
  ar=${c%%:*}
  mu=${c##*:}
  name="ar${ar}_mu${mu/./}"
  # The box: AR 3 0.15 m wide (0.25 m for AR 10), wider from 2000 (1000)
  # fibres on at equal depth; the fibres placed at φ = 0.15 (0.06: long
  # fibres jam earlier) in a box as tall as that needs.
  if [ "$ar" = 3 ]; then
    n=$n3; len=0.03; ke=1e-6; t_end=2; side0=0.15; n0=2000; phi0=0.15
  else
    n=$n10; len=0.1; ke=3.3e-6; t_end=3; side0=0.25; n0=1000; phi0=0.06
  fi
  read -r side height < <(python3 -c "
from math import pi, sqrt
side = round($side0 * max(1, sqrt($n / $n0)), 4)
print(side, round($n * pi / 4 * 0.01**2 * $len / (side**2 * $phi0), 3))")
  "$bin" generate --n "$n" --diameter 0.01 --length "$len" --density 1100 \
    --young 5e7 --poisson 0.35 --box "$side,$side,$height" --seed 1 \
    --restitution 0.3 --dt 2e-5 --t-end "$t_end" --max-attempts 1000000 \
    -o "$out/loose_$name.toml" -q
  if [ "$mu" != 0 ]; then
    sed -i "s/^wall_restitution = 0.3\$/wall_restitution = 0.3\nfriction = $mu/" "$out/loose_$name.toml"
  fi
  [ "$mode" = generate ] && continue
  # A bed that does not settle by t_end is still written (exit 2): measured
  # and reported as such.
  time "${nice[@]}" "$bin" settle "$out/loose_$name.toml" --threads 1 --check-every 500 \
    --ke-per-body "$ke" --every 1000 -o "$out/settle_$name" --force -q \
    --write "$out/bed_$name.toml" --write-dt 1e-6 --write-t-end 0.002 || true
  "${nice[@]}" "$bin" run "$out/bed_$name.toml" --threads 1 --t-end 1e-5 --vtk-every 10 \
    -o "$out/frame_$name" --force -q
done
[ "$mode" = generate ] || python3 scripts/bed_packing.py "$out" | tee "$out/packing.md"
