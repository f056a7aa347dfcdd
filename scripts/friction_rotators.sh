#!/usr/bin/env bash
# Work–precision of every rotator where friction drives spin: the data behind
# docs/studies.md, "Rotators with friction".
#
#   scripts/friction_rotators.sh OUT_DIR [drop|window|control|bed|cost|instructions|table ...]   # default: all
#
# Scenes:
#   drop: 50 fibres (D = 0.01 m, L = 0.03 m) dropped into a 0.1 m box with
#         restitution 0.5 and friction μ = 0.5 (body–body and walls), made by
#         `fibresim generate` (recommended δt 4.9e-6 s). Every landing twists
#         and spins the fibres through the tangential springs.
#         The whole drop (0.3 s): full-budget energy error, δt = 4, 2, 1 µs;
#   window: its first 0.03 s (the first landings; later windows converge
#        ever more slowly as landings multiply): full-budget energy error
#        and the distance at T to nosquish
#        at δt = 0.125 µs, whose own error converge reports (its distance to
#        its twin at 0.25 µs), at δt = 4, 2, 1, 0.5 µs;
#   control: the whole drop again for six rotators, damped but frictionless
#         and frictional but undamped, to say which part of the law sets the
#         energy error;
#   bed:  the settled frictional bed scenarios/bed_ar3_mu05.toml (2000 fibres,
#         μ = 0.5) run damped (e = 0.3, friction 0.5) over 2 ms, as the window;
#   cost: CPU time per body-step of the rotators on both scenes, alternated
#         rounds (cargo bench --bench contact_rotators), one thread;
#   instructions: instructions per body-step of six rotators on the whole
#         drop (valgrind callgrind);
#   table: the markdown table and the figure (scripts/friction_rotators_table.py).
# Sizes: the full sizes of docs/studies.md: about 17 min of CPU (drop 5,
# bed 4, controls 2, callgrind 3, benches 3), an hour of wall time at load 8.
set -euo pipefail
out=${1:?give an output folder}
shift
stages=${*:-drop window control bed cost instructions table}
bin=${FIBRESIM:-target/release/fibresim}
nice=(nice -n 5)
cargo build --release -q
mkdir -p "$out"

# Friction is a [contact] key: it goes after the restitution lines that
# `generate --restitution` writes.
add_friction() { # FILE MU
  sed -i "s/^wall_restitution = \(.*\)\$/wall_restitution = \1\nfriction = $2/" "$1"
  grep -q "^friction = $2\$" "$1" || { echo "no [contact] restitution in $1" >&2; exit 2; }
}

grid=(--rotators all --dt-max 4e-6 --dt-min 1e-6 --points 3 -q --threads 1)
control=leapfrog,omelyan,pcdm,pcdm-staggered,cayley-cd,split
counted=omelyan,cayley-cd,pcdm-staggered,leapfrog,pcdm,split
timed=pcdm,pcdm-staggered,euler,leapfrog,nosquish,richardson,omelyan,cayley-cd,fincham,fincham-mid,spiral-vv,split

for stage in $stages; do
  case $stage in
  drop)
    "$bin" generate --n 50 --diameter 0.01 --length 0.03 --box 0.1,0.1,0.1 \
      --restitution 0.5 --t-end 0.3 -o "$out/drop50.toml" -q
    add_friction "$out/drop50.toml" 0.5
    time "${nice[@]}" "$bin" converge "$out/drop50.toml" "${grid[@]}" --out "$out/drop_energy"
    ;;
  window)
    time "${nice[@]}" "$bin" converge "$out/drop50.toml" --rotators all --dt-max 4e-6 \
      --dt-min 5e-7 --points 4 -q --threads 1 --t-end 0.03 \
      --ref-factor 4 --trajectory nosquish --out "$out/drop_trajectory"
    ;;
  bed)
    cp scenarios/bed_ar3_mu05.toml scenarios/bed_ar3_mu05_bodies.csv "$out/"
    python3 - "$out/bed_ar3_mu05.toml" <<'PY'
import sys
p = sys.argv[1]
t = open(p).read().replace("friction = 0.5\n", "restitution = 0.3\nwall_restitution = 0.3\nfriction = 0.5\n", 1)
open(p, "w").write(t)
PY
    time "${nice[@]}" "$bin" converge "$out/bed_ar3_mu05.toml" "${grid[@]}" --t-end 0.002 \
      --ref-factor 4 --trajectory nosquish --out "$out/bed_trajectory"
    ;;
  control)
    # Which part of the contact law sets the energy error: the same drop
    # damped but frictionless, and frictional but undamped (no restitution,
    # so no tangential damping either).
    sed '/^friction = /d' "$out/drop50.toml" >"$out/drop50_damped.toml"
    grep -v -E '^(restitution|wall_restitution) = ' "$out/drop50.toml" >"$out/drop50_undamped.toml"
    for v in damped undamped; do
      time "${nice[@]}" "$bin" converge "$out/drop50_$v.toml" --rotators "$control" \
        --dt-max 4e-6 --dt-min 1e-6 --points 3 -q --threads 1 --out "$out/control_$v"
    done
    ;;
  cost)
    "${nice[@]}" cargo bench -q --bench contact_rotators -- "$out/drop50.toml" --rotators "$timed" \
      --dt 4e-6 --steps 75000 --rounds 5 --threads 1 | tee "$out/cost_drop.txt"
    "${nice[@]}" cargo bench -q --bench contact_rotators -- "$out/bed_ar3_mu05.toml" --rotators "$timed" \
      --dt 4e-6 --steps 500 --rounds 5 --threads 1 | tee "$out/cost_bed.txt"
    ;;
  instructions)
    # Instructions per body-step (valgrind callgrind: deterministic, so it
    # separates rotators closer than the bench's spread on a busy machine):
    # the whole drop at δt = 4 µs, start-up and all, over 75 000 × 50.
    for r in ${counted//,/ }; do
      ir=$(valgrind --tool=callgrind --callgrind-out-file="$out/callgrind.out" \
        "$bin" run "$out/drop50.toml" --rotator "$r" --dt 4e-6 --every 1000000 -q \
        --threads 1 --out "$out/instructions_run" --force 2>&1 |
        grep -o "Collected : [0-9]*" | grep -o "[0-9]*")
      echo "$r $ir $((ir / (75000 * 50)))"
    done | tee "$out/instructions_drop.txt"
    rm -rf "$out/callgrind.out" "$out/instructions_run"
    ;;
  table)
    python3 scripts/friction_rotators_table.py "$out" --png "$out/friction_work_precision.png" \
      | tee "$out/table.md"
    ;;
  *) echo "unknown stage $stage (drop, window, control, bed, cost, instructions, table)" >&2; exit 2 ;;
  esac
done
