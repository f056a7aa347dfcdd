#!/bin/bash
# Instructions per step of every rotator (valgrind callgrind: deterministic,
# so it can be compared on a busy machine): the difference of a 2e4-step and
# a 1e4-step run, over 1e4, on test case 4 and on the torque-free asymmetric
# top. Usage: scripts/rotator_instructions.sh [BINARY] (default
# target/release/fibresim). Quoted in docs/performance.md, "One body step".
set -euo pipefail
B=${1:-target/release/fibresim}
OUT=$(mktemp -d)
ir() { valgrind --tool=callgrind --callgrind-out-file="$OUT/cg.out" "$@" 2>&1 | grep -o "Collected : [0-9]*" | grep -o "[0-9]*"; }
for r in $("$B" rotators | awk 'NR>1 && /^[a-z]/ {print $1}'); do
  case $r in frozen|order:) continue;; esac
  a=$(ir "$B" run scenarios/torque_fibre.toml --rotator "$r" --dt 1e-6 --t-end 0.01 --every 1000000 -q --out "$OUT/o")
  b=$(ir "$B" run scenarios/torque_fibre.toml --rotator "$r" --dt 1e-6 --t-end 0.02 --every 1000000 -q --out "$OUT/o")
  c=$(ir "$B" run scenarios/asymmetric_top.toml --rotator "$r" --dt 1e-4 --t-end 1 --every 1000000 -q --out "$OUT/o")
  d=$(ir "$B" run scenarios/asymmetric_top.toml --rotator "$r" --dt 1e-4 --t-end 2 --every 1000000 -q --out "$OUT/o")
  echo "$r tc4 $(( (b - a) / 10000 )) asym_free $(( (d - c) / 10000 ))"
done
rm -rf "$OUT"
