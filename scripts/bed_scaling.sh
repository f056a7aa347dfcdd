#!/usr/bin/env bash
# Fibre-steps per second of settled beds from 10^3 to 10^6 fibres, aspect
# ratios 3 and 10, on 1 and 2 threads, and the figure of docs/performance.md.
#
#   scripts/bed_scaling.sh OUT_DIR           # ~15 min on an idle 2-core machine
#   scripts/bed_scaling.sh OUT_DIR --memory  # the memory table only (~5 min)
#
# The beds: the shipped bed_1k, bed_1k_column (10^3 fibres in a 0.1 x 0.1 m
# column, as deep as bed_10k), bed_10k and bed_ar10 (10^3, AR 10), and
# copies of them side by side made by `fibresim replicate` (10^5 and 10^6
# fibres from bed_10k; 10^4 to 10^6 from bed_ar10). Each is timed by the bed
# bench (medians of --repeats runs; its memory counts come with it), with
# fewer steps for the larger beds so each sample takes seconds. Writes
# OUT_DIR/bed_scaling.csv (a `series` column: one per aspect ratio and thread
# count, plus the peers' measurements at 10^4 fibres) and
# docs/figures/bed_scaling.png from it with `fibresim plot`.
#
# With --memory it runs only the AR-3 beds of 10^4, 10^5 and 10^6 fibres,
# with the steps below, and prints the heap bytes per fibre of
# docs/performance.md "Memory", leaving the figure as it is.
set -euo pipefail
out=${1:?give an output folder}
mode=${2:-}
bin=${FIBRESIM:-target/release/fibresim}
mkdir -p "$out/beds"
cargo build --release -q
rm -f "$out"/raw_*.csv

bed() { # name source times -> path
  local f="$out/beds/$1.toml"
  [ -f "$f" ] || "$bin" replicate "scenarios/$2.toml" --times "$3" -o "$f" -q
  echo "$f"
}

bench() { # raw-csv scene steps repeats
  cargo bench -q --bench bed -- "$2" --steps "$3" --repeats "$4" --threads 1,2 --csv "$out/raw_$1.csv"
}

if [ "$mode" = --memory ]; then
  memory() { # scene steps (as below, one run each)
    cargo bench -q --bench bed -- "$1" --steps "$2" --repeats 1 --threads 1,2 --csv "$out/raw_memory.csv" |
      grep -E "loaded|world heap|heap while stepping"
  }
  memory scenarios/bed_10k.toml 100
  memory "$(bed ar3_100k bed_10k 5,2,1)" 10
  memory "$(bed ar3_1m bed_10k 10,10,1)" 2
  python3 - "$out" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(f"{sys.argv[1]}/raw_memory.csv")))
print("fibres | 1 thread | 2 threads (heap bytes per fibre, the scene included)")
for n in dict.fromkeys(r["fibres"] for r in rows):
    h = {r["threads"]: r["heap_bytes_per_fibre"] for r in rows if r["fibres"] == n}
    print(f"{n} | {h.get('1', '')} | {h.get('2', '')}")
EOF
  exit
fi

bench ar3 scenarios/bed_1k.toml 1000 5
bench ar3_column scenarios/bed_1k_column.toml 1000 5
bench ar3 scenarios/bed_10k.toml 100 5
bench ar3 "$(bed ar3_100k bed_10k 5,2,1)" 10 3
bench ar3 "$(bed ar3_1m bed_10k 10,10,1)" 2 3
bench ar10 scenarios/bed_ar10.toml 1000 5
bench ar10 "$(bed ar10_10k bed_ar10 5,2,1)" 100 5
bench ar10 "$(bed ar10_100k bed_ar10 10,10,1)" 10 3
bench ar10 "$(bed ar10_1m bed_ar10 40,25,1)" 2 3

python3 - "$out" <<'EOF'
import csv, sys
out = sys.argv[1]
rows = [("series", "fibres", "threads", "fibre_steps_per_s", "ns_per_fibre_step",
         "parallel_efficiency", "touching_per_fibre", "heap_bytes_per_fibre")]
# The 10^3 column is as deep as the 10^4 bed (the shipped 10^3 bed is a
# layer two or three fibres deep).
for raw, label in (("ar3", "AR 3"), ("ar10", "AR 10"), ("ar3_column", "AR 3, 10^3 column")):
    for r in csv.DictReader(open(f"{out}/raw_{raw}.csv")):
        t = int(r["threads"])
        name = f"fibresim {label}, {t} thread{'s' if t > 1 else ''}"
        rows.append((name, r["fibres"], t, r["fibre_steps_per_s"], r["ns_per_fibre_step"],
                     r["parallel_efficiency"], r["touching_per_fibre"], r["heap_bytes_per_fibre"]))
# The peers on their settled beds of the AR-3 fibres, this machine (the
# medians of docs/peers.md "One run"; scripts/peers.sh measures them afresh).
peers = (("LIGGGHTS 3.8 multisphere", 1, 1.607e6), ("LIGGGHTS 3.8 multisphere", 2, 2.958e6),
         ("LAMMPS rigid/small", 1, 1.781e6), ("LAMMPS rigid/small", 2, 3.259e6))
for name, t, rate in peers:
    rows.append((f"{name}, {t} process{'es' if t > 1 else ''}", 10000, t, rate, 1e9 / rate, "", "", ""))
# The speed target for the 10^4 bed, 2x LAMMPS, drawn across the range.
for t, rate in ((t, 2 * rate) for name, t, rate in peers if name.startswith("LAMMPS")):
    for n in (1000, 1000000):
        rows.append((f"target, {t} thread{'s' if t > 1 else ''}", n, t, rate, 1e9 / rate, "", "", ""))
with open(f"{out}/bed_scaling.csv", "w", newline="") as f:
    csv.writer(f).writerows(rows)
EOF
cp "$out/bed_scaling.csv" docs/figures/bed_scaling.csv
"$bin" plot docs/figures/bed_scaling.csv --x fibres --column fibre_steps_per_s --log-x --log-y \
  -o docs/figures/bed_scaling.png
column -s, -t docs/figures/bed_scaling.csv
