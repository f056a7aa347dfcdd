#!/usr/bin/env bash
# What share of a step the fibre–fibre kernels take, by class of call,
# measured by taking them away (src/contact/replay.rs): one recorded run of
# SCENE on one thread, then ROUNDS rounds of replays, each replaying one
# set of classes, alternated so that the host's drift hits every set alike.
# Every replay must give the recorded run's energy.csv byte for byte.
#
# Usage: scripts/kernel_share.sh [SCENE] [T_END] [ROUNDS] [DIR]
#   defaults: scenarios/bed_10k.toml 2e-4 3 /tmp/kernel_share
# Prints the median ns per fibre-step of each set and what each class costs.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenarios/bed_10k.toml}
t_end=${2:-2e-4}
rounds=${3:-3}
dir=${4:-/tmp/kernel_share}
mkdir -p "$dir"
CARGO_TARGET_DIR=target/replay cargo build --release --features replay -q
bin=target/replay/release/fibresim
run() { # $1 = out dir; env FIBRESIM_REPLAY set by the caller
    "$bin" run "$scene" --t-end "$t_end" --threads 1 -q --out "$1" --force
}
FIBRESIM_REPLAY="record:$dir/rec" run "$dir/record"
sets=("none:" "passed:passed" "kept:kept" "scan:scan" "dispatch:dispatch" "all:passed,kept,scan,dispatch")
for r in $(seq "$rounds"); do
    for s in "${sets[@]}"; do
        name=${s%%:*}
        FIBRESIM_REPLAY="replay:$dir/rec:${s#*:}" run "$dir/$name.$r"
        cmp -s "$dir/record/energy.csv" "$dir/$name.$r/energy.csv" ||
            { echo "replaying $name changed energy.csv" >&2; exit 1; }
    done
done
python3 - "$dir" "$rounds" "$dir/rec" <<'EOF'
import json, statistics, sys, collections, struct
d, rounds, rec_path = sys.argv[1], int(sys.argv[2]), sys.argv[3]
ns = {}
for name in ["none", "passed", "kept", "scan", "dispatch", "all"]:
    v = [json.load(open(f"{d}/{name}.{r}/summary.json"))["ns_per_body_step"] for r in range(1, rounds + 1)]
    ns[name] = statistics.median(v)
    print(f"replayed {name:9s} median {ns[name]:7.1f} ns per fibre-step  ({', '.join(f'{x:.1f}' for x in v)})")
# The timed steps' calls: from the second computation on (the first is the
# start's, before the clock).
marks = open(f"{rec_path}.computations", "rb").read()
first = struct.unpack_from("<Q", marks, 8)[0] if len(marks) >= 16 else 0
raw = open(f"{rec_path}.calls", "rb").read()
count = collections.Counter(raw[i] for i in range(8 * first, len(raw), 8))
rec = json.load(open(f"{d}/record/summary.json"))
fibre_steps = rec["bodies"] * rec["steps"]
for k, name in enumerate(["passed", "kept", "dispatch", "scan"]):
    saved = ns["none"] - ns[name]
    per = count[k] / fibre_steps
    each = saved / per if per else float("nan")
    print(f"{name:9s} {per:5.2f} calls per fibre-step, {saved:6.1f} ns per fibre-step ({each:5.1f} ns a call)")
print(f"every kernel: {ns['none'] - ns['all']:.1f} of {ns['none']:.1f} ns per fibre-step "
      f"({100 * (ns['none'] - ns['all']) / ns['none']:.0f} %); the rest {ns['all']:.1f} ns")
EOF
