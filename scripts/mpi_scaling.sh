#!/usr/bin/env bash
# Strong and weak scaling over MPI ranks, one CSV row per run.
#
#   scripts/mpi_scaling.sh OUT_DIR [STEPS_10K] [STEPS_1M] [STEPS_WEAK]
#
# Makes the large beds with `fibresim replicate` from the shipped bed_10k
# (in OUT_DIR/beds), then runs, with the same flags for every run:
#   strong  bed_10k and a 10^6-fibre bed (10 x 10 copies): one process on
#           1 and 2 threads, mpirun -np 2 x 1 thread (ranks x threads =
#           cores), -np 4 x 1 thread (oversubscribed);
#   weak    10^5 fibres per rank: 5 x 2, 10 x 2, 10 x 4 copies on 1, 2, 4 ranks.
# Every multi-rank run's energy.csv is compared with the one-process run of
# the same bed (cmp): the bytes must be those of one process.
# Columns: case, fibres, ranks, threads, steps, wall_s (the stepping loop,
# summary.json), fibre_steps_per_s, bytes_per_fibre_step (mean over ranks),
# force_s_max, comm_s_max, wait_s_max, peak_rss_mb (the largest of the
# ranks' peak resident sets, loading included), same_bytes.
set -euo pipefail
out=${1:?give an output folder}
steps_10k=${2:-500}
steps_1m=${3:-10}
steps_weak=${4:-40}
bin=${FIBRESIM:-target/release/fibresim}
[ -n "${FIBRESIM:-}" ] || cargo build --release --features mpi -q
mkdir -p "$out/beds" "$out/runs"
mpi=(mpirun --allow-run-as-root --oversubscribe -x OMPI_MCA_mpi_yield_when_idle=1)
csv="$out/mpi_scaling.csv"
echo "case,fibres,ranks,threads,steps,wall_s,fibre_steps_per_s,bytes_per_fibre_step,force_s_max,comm_s_max,wait_s_max,peak_rss_mb,same_bytes" >"$csv"

bed() { # name times -> path of the replicated bed
  local f="$out/beds/$1.toml"
  [ -f "$f" ] || "$bin" replicate scenarios/bed_10k.toml --times "$2" -o "$f" -q
  echo "$f"
}

row() { # case scene ranks threads steps reference_dir
  local case=$1 scene=$2 k=$3 t=$4 n=$5 ref=${6:-}
  local dir="$out/runs/${case}_$(basename "$scene" .toml)_np${k}_t${t}"
  local t_end
  t_end=$(python3 -c "print(repr($n * 1e-6))")
  rm -f "$dir.rss"
  local cmd=(/usr/bin/time -a -o "$dir.rss" -f %M "$bin" run "$scene" --t-end "$t_end" --every "$n" --threads "$t" -q --out "$dir" --force)
  if [ "$k" -gt 1 ]; then "${mpi[@]}" -np "$k" "${cmd[@]}"; else "${cmd[@]}"; fi
  local same=na
  if [ -n "$ref" ]; then cmp -s "$ref/energy.csv" "$dir/energy.csv" && same=yes || same=NO; fi
  python3 - "$dir/summary.json" "$case" "$k" "$t" "$n" "$same" "$dir.rss" >>"$csv" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
case, k, t, n, same = sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), sys.argv[6]
bodies = s["bodies"]
r = s.get("ranks", [])
if k > 1 and not r:
    sys.exit(f"{sys.argv[1]}: no `ranks` report: this binary was built without `--features mpi`")
mean = lambda key: sum(x[key] for x in r) / len(r) if r else 0.0
peak = lambda key: max(x[key] for x in r) if r else 0.0
rss = max(int(l) for l in open(sys.argv[7]) if l.strip().isdigit()) / 1024
print(f"{case},{bodies},{k},{t},{n},{s['wall_s']:.3f},{bodies * n / s['wall_s']:.0f},"
      f"{mean('bytes_per_body_step'):.1f},{peak('force_s'):.3f},{peak('comm_s'):.3f},{peak('wait_s'):.3f},{rss:.0f},{same}")
EOF
  echo "$dir"
}

for scene in scenarios/bed_10k.toml "$(bed bed_1m 10,10,1)"; do
  n=$steps_10k
  [[ $scene == *bed_1m* ]] && n=$steps_1m
  ref=$(row strong "$scene" 1 1 "$n")
  row strong "$scene" 1 2 "$n" "$ref" >/dev/null
  row strong "$scene" 2 1 "$n" "$ref" >/dev/null
  row strong "$scene" 4 1 "$n" "$ref" >/dev/null
done
for spec in "1 bed_100k 5,2,1" "2 bed_200k 10,2,1" "4 bed_400k 10,4,1"; do
  set -- $spec
  row weak "$(bed "$2" "$3")" "$1" 1 "$steps_weak" >/dev/null
done
# The figure of docs/mpi.md: fibre-steps/s against ranks (1 thread each), one
# series per bed, and one process on 2 threads for comparison.
python3 - "$csv" <<'EOF'
import csv, sys
rows = [("series", "ranks", "fibre_steps_per_s", "wall_s", "bytes_per_fibre_step", "peak_rss_mb")]
for r in csv.DictReader(open(sys.argv[1])):
    n = int(r["fibres"])
    bed = {10000: "10⁴ fibres (bed_10k)", 1000000: "10⁶ fibres"}.get(n, "")
    if r["case"] == "weak":
        name = "weak: 10⁵ fibres per rank"
    elif r["threads"] == "2":
        name = f"{bed}, one process on 2 threads"
    else:
        name = f"{bed}, ranks x 1 thread"
    rows.append((name, r["ranks"] if r["threads"] == "1" else "2", r["fibre_steps_per_s"],
                 r["wall_s"], r["bytes_per_fibre_step"], r["peak_rss_mb"]))
with open("docs/figures/mpi_scaling.csv", "w", newline="") as f:
    csv.writer(f).writerows(rows)
EOF
"$bin" plot docs/figures/mpi_scaling.csv --x ranks --column fibre_steps_per_s --log-y \
  -o docs/figures/mpi_scaling.png
column -s, -t "$csv"
