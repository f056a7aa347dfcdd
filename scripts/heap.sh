#!/usr/bin/env bash
# A heap of fibres (aspect ratio 3, μ = 0.5, walls the same) and its angle of
# repose (docs/beds.md, "A heap"), by the lifted-cylinder method: a column
# settled in a narrow box is released onto a wide floor.
#
#   scripts/heap.sh OUT_DIR [N [MU]]     # docs/beds.md: N = 1000 and 3000, MU = 0.5
#
# 1. `generate` N fibres (D = 0.01 m, L = 0.03 m, as the beds) at random in a
#    column box W × W × H (W = 0.2 m for 1000 fibres, growing as N^(1/3)),
#    `settle` them (e = 0.3, δt = 2e-5 s): a settled column about 0.6 W tall;
# 2. the column's walls are taken away: the same bed in a box 3 W wide
#    (its floor and the column's position unchanged), settled again: the
#    column slumps into a heap whose flanks stand at the angle of repose;
# 3. scripts/heap_angle.py fits the flank.
set -euo pipefail
out=${1:?give an output folder}
n=${2:-1000}
mu=${3:-0.5}
bin=${FIBRESIM:-target/release/fibresim}
nice=(nice -n 5)
cargo build --release -q
mkdir -p "$out"
read -r w h < <(python3 -c "
from math import pi
w = round(0.2 * ($n / 1000) ** (1 / 3), 4)
print(w, round($n * pi / 4 * 0.01**2 * 0.03 / (w**2 * 0.12), 3))")
"$bin" generate --n "$n" --diameter 0.01 --length 0.03 --density 1100 --young 5e7 \
  --poisson 0.35 --box "$w,$w,$h" --seed 1 --restitution 0.3 --dt 2e-5 --t-end 3 \
  --max-attempts 1000000 -o "$out/column_loose.toml" -q
sed -i "s/^wall_restitution = 0.3\$/wall_restitution = 0.3\nfriction = $mu/" "$out/column_loose.toml"
time "${nice[@]}" "$bin" settle "$out/column_loose.toml" --threads 1 --check-every 500 \
  --ke-per-body 1e-6 --every 1000 -o "$out/settle_column" --force -q \
  --write "$out/column.toml" --write-dt 2e-5 --write-t-end 3 || true
# The released column: the box [−W, 2W]² around the column's [0, W]².
python3 - "$out/column.toml" "$out/released.toml" "$w" <<'PY'
import re, sys
src, dst, w = sys.argv[1], sys.argv[2], float(sys.argv[3])
t = open(src).read()
t = re.sub(r"\[box\]\nmin = \[[^\]]*\]\nmax = \[([^,\]]*), ([^,\]]*), ([^\]]*)\]",
           lambda m: f"[box]\nmin = [{-w}, {-w}, 0.0]\nmax = [{2 * w}, {2 * w}, {m.group(3)}]", t, count=1)
assert f"min = [{-w}, {-w}, 0.0]" in t, "the column scenario's [box] was not found"
open(dst, "w").write(t)
PY
time "${nice[@]}" "$bin" settle "$out/released.toml" --restitution 0.3 --threads 1 \
  --check-every 500 --ke-per-body 1e-6 --every 1000 -o "$out/settle_heap" --force -q \
  --write "$out/heap.toml" --write-dt 1e-6 --write-t-end 0.002 || true
python3 scripts/heap_angle.py "$out/heap.toml" --png "$out/heap_profile.png" | tee "$out/angle.txt"
