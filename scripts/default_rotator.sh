#!/usr/bin/env bash
# Work–precision of every rotator on two contact scenes: the data behind the
# default rotator (docs/studies.md, "The default rotator").
#
#   scripts/default_rotator.sh OUT_DIR     # ~5 min of CPU, 20 min on a loaded machine
#
# Scenes: a drop of 50 fibres (D = 0.01 m, L = 0.03 m) into a 0.1 m box,
# made by `fibresim generate` (recommended dt 4.9e-6 s), and the shipped
# settled bed of 10^3 fibres, scenarios/bed_1k.toml (2 ms window).
#   1. the whole drop (0.3 s): full-budget energy error, dt = 4e-6, 2e-6, 1e-6 s;
#   2. its first 0.06 s (the first impacts, before the motion turns chaotic):
#      the same, plus the trajectory error at T against nosquish at 2.5e-7 s;
#   3. bed_1k over its 2 ms: the same as 2;
#   4. the CPU time per body-step of the rotators on both scenes, alternated
#      rounds (cargo bench --bench contact_rotators), one thread;
# then prints the markdown table of docs/studies.md from OUT_DIR.
set -euo pipefail
out=${1:?give an output folder}
bin=${FIBRESIM:-target/release/fibresim}
cargo build --release -q
mkdir -p "$out"
"$bin" generate --n 50 --diameter 0.01 --length 0.03 --box 0.1,0.1,0.1 \
  --t-end 0.3 -o "$out/drop50.toml" -q
grid=(--rotators all --dt-max 4e-6 --dt-min 1e-6 --points 3 -q --threads 2)
time "$bin" converge "$out/drop50.toml" "${grid[@]}" --out "$out/drop_energy"
time "$bin" converge "$out/drop50.toml" "${grid[@]}" --t-end 0.06 \
  --ref-factor 4 --trajectory nosquish --out "$out/drop_trajectory"
time "$bin" converge scenarios/bed_1k.toml "${grid[@]}" \
  --ref-factor 4 --trajectory nosquish --out "$out/bed_trajectory"
# The paper's pcdm and euler, and every scheme that closes the step with the
# torque of the new configuration (the others are first order with contacts).
timed=pcdm,euler,leapfrog,nosquish,richardson,omelyan,fincham,fincham-mid,spiral-vv,split
cargo bench -q --bench contact_rotators -- "$out/drop50.toml" --rotators "$timed" \
  --dt 4e-6 --steps 75000 --rounds 5 | tee "$out/cost_drop.txt"
cargo bench -q --bench contact_rotators -- scenarios/bed_1k.toml --rotators "$timed" \
  --dt 4e-6 --steps 500 --rounds 5 | tee "$out/cost_bed.txt"
python3 scripts/default_rotator_table.py "$out"
