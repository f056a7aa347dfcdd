#!/usr/bin/env bash
# fibresim next to its peers on the same bed: LIGGGHTS (multisphere) and LAMMPS
# (fix rigid/small) on 10^4 fibres, plus LAMMPS's own chute benchmark to place
# the machine and fibresim on a settled bed of 10^4 Hertz spheres beside it
# (scenarios/bed_spheres_10k.toml). docs/peers.md says what is compared and how to read the table.
#
#   scripts/peers.sh                 8 alternated rounds on 1 and 2 cores
#   scripts/peers.sh --quick         2 rounds of 500 timed steps: checks that everything runs
#   scripts/peers.sh --spheres       only the 10^4-sphere bed and the chute
#   scripts/peers.sh --help          every option
#
# Steps: (1) install Debian's liggghts, lammps and time when missing (as root
# or with sudo); (2) settle the peers' bed once with LIGGGHTS and convert it for
# LAMMPS, kept in a cache folder (about 10 min on 2 cores the first time);
# (3) build fibresim in release; (4) R rounds, each running for every count n
# in the list LIGGGHTS on n processes, LAMMPS on n, fibresim on n threads, then
# the chute on one core, with the load average read before each job and the
# peak RSS from /usr/bin/time -v; (5) medians, ratios, parallel efficiency
# and memory per fibre printed and in OUT/summary.md, one CSV row per job in
# OUT/jobs.csv, and the figure OUT/peers.png drawn by `fibresim plot` from
# OUT/medians.csv.
# A failed job keeps its row (status column) and makes the exit status 1.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 2
repo=$PWD
peers=$repo/peers

usage() {
  cat <<'EOF'
usage: scripts/peers.sh [options]
  --rounds R        alternated rounds (default 8; 2 with --quick)
  --threads LIST    process/thread counts, comma-separated (default 1,2)
  --codes LIST      any of liggghts,lammps,fibresim,spheres,chute (default all five;
                    spheres: fibresim on the settled 10^4-sphere bed, beside the chute)
  --quick           2 rounds, 50 warm-up + 500 timed steps: a check that every job runs, not a measurement
  --steps N         timed steps of the bed (default 2000, at dt = 1e-6 s)
  --warmup N        the peers' untimed steps before them (default 200)
  --out DIR         a new folder for this run (default out/peers/<date-time>)
  --cache DIR       where the settled bed is kept (default $XDG_CACHE_HOME/fibresim/peers,
                    else ~/.cache/fibresim/peers)
  --chute-dir DIR   a folder holding LAMMPS's bench/in.chute and bench/data.chute
                    (default: looked for under /usr/share/lammps*; else the chute is skipped)
  --pause S         seconds of rest between jobs (default 3)
  --settle-only     install, settle and convert the bed, then stop
  --no-install      never call apt-get; fail if a tool is missing
  --spheres         the same as --codes spheres,chute
EOF
}

die() { # code message
  echo "peers.sh: $2" >&2
  exit "$1"
}

rounds="" threads=1,2 codes=liggghts,lammps,fibresim,spheres,chute quick=0 steps="" warmup=""
out="" cache="${XDG_CACHE_HOME:-$HOME/.cache}/fibresim/peers" chute_dir="${PEERS_CHUTE_DIR:-}"
pause=3 settle_only=0 install=1
while [ $# -gt 0 ]; do
  case $1 in
    --rounds | --threads | --codes | --steps | --warmup | --out | --cache | --chute-dir | --pause)
      [ $# -ge 2 ] || die 2 "$1 needs a value (see --help)"
      v=$2
      case $1 in
        --rounds) rounds=$v ;; --threads) threads=$v ;; --codes) codes=$v ;;
        --steps) steps=$v ;; --warmup) warmup=$v ;; --out) out=$v ;;
        --cache) cache=$v ;; --chute-dir) chute_dir=$v ;; --pause) pause=$v ;;
      esac
      shift 2 ;;
    --quick) quick=1; shift ;;
    --settle-only) settle_only=1; shift ;;
    --no-install) install=0; shift ;;
    --spheres) codes=spheres,chute; shift ;;
    -h | --help) usage; exit 0 ;;
    *) usage >&2; die 2 "unknown option '$1' (see the list above)" ;;
  esac
done
if [ $quick = 1 ]; then
  rounds=${rounds:-2} steps=${steps:-500} warmup=${warmup:-50}
fi
rounds=${rounds:-8} steps=${steps:-2000} warmup=${warmup:-200}
for pair in "rounds:$rounds" "steps:$steps" "warmup:$warmup" "pause:$pause"; do
  [[ ${pair#*:} =~ ^[0-9]+$ ]] || die 2 "--${pair%%:*} '${pair#*:}': give a whole number"
done
if [ "$rounds" -lt 1 ] || [ "$steps" -lt 1 ]; then die 2 "--rounds and --steps must be at least 1"; fi
IFS=, read -r -a ns <<<"$threads"
for n in "${ns[@]}"; do
  [[ $n =~ ^[1-9][0-9]*$ ]] || die 2 "--threads '$threads': give counts like 1,2"
done
IFS=, read -r -a want <<<"$codes"
has() { [[ ,$codes, == *,$1,* ]]; }
for c in "${want[@]}"; do
  case $c in liggghts | lammps | fibresim | spheres | chute) ;; *) die 2 "--codes: unknown code '$c' (liggghts, lammps, fibresim, spheres, chute)" ;; esac
done
[[ $cache != *" "* && $repo != *" "* ]] || die 2 "LIGGGHTS and LAMMPS read paths with spaces as two words: use a --cache and a checkout without spaces"

# The cache is keyed by what makes each file (comment lines aside): editing the
# settling input settles a new bed; editing the conversion only converts again.
key() { grep -hv '^[[:space:]]*#' "$@" | sha256sum | cut -c1-12; }
fibre_inc=$peers/liggghts/fibre_4spheres.inc
bed=$cache/bed-$(key "$peers/liggghts/in.settle" "$fibre_inc")
data=$bed/bed-$(key "$peers/liggghts/in.dump" "$peers/dump2data.py").data

# ---- 1. tools ---------------------------------------------------------------
need_pkgs=()
command -v python3 >/dev/null || die 2 "python3 is needed (for the bed's conversion and the report)"
[ -x /usr/bin/time ] || need_pkgs+=(time)
if has liggghts || [ $settle_only = 1 ] || { has lammps && [ ! -f "$data" ]; }; then
  command -v liggghts >/dev/null || need_pkgs+=(liggghts)
fi
if has lammps || has chute; then command -v lmp >/dev/null || need_pkgs+=(lammps); fi
if [ ${#need_pkgs[@]} -gt 0 ]; then
  [ $install = 1 ] || die 2 "missing: ${need_pkgs[*]}; install them with 'apt-get install -y ${need_pkgs[*]}' (or drop --no-install)"
  if [ "$(id -u)" = 0 ]; then sudo=""; elif command -v sudo >/dev/null; then sudo=sudo; else
    die 2 "missing: ${need_pkgs[*]}; run as root, or install them with 'apt-get install -y ${need_pkgs[*]}'"
  fi
  echo "installing ${need_pkgs[*]} (Debian packages; OpenMPI comes with them)"
  if ! { $sudo apt-get update -q && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q "${need_pkgs[@]}"; }; then
    die 1 "apt-get install ${need_pkgs[*]} failed"
  fi
fi
mpi=(mpirun)
[ "$(id -u)" = 0 ] && mpi+=(--allow-run-as-root)
cores=$(nproc)

# ---- 2. the peers' settled bed, once -----------------------------------------
settle_bed() {
  mkdir -p "$bed" || die 2 "--cache $cache: cannot create $bed"
  if [ -f "$data" ] && [ -f "$bed/bed.restart" ]; then
    echo "settled bed: $bed (cached)"
    return
  fi
  if [ ! -f "$bed/bed.restart" ]; then
    local over=()
    [ "$cores" -lt 2 ] && over=(--oversubscribe)
    echo "settling the peers' bed with LIGGGHTS on 2 processes at nice 10 (about 10 min on 2 idle cores; log: $bed/settle.log)"
    (cd "$bed" && nice -n 10 "${mpi[@]}" "${over[@]}" -np 2 liggghts -in "$peers/liggghts/in.settle" \
      -var FIBRE "$fibre_inc" -var RESTART "$bed/bed.restart.part" -log "$bed/settle.log" >"$bed/settle.out" 2>&1) ||
      die 1 "settling failed (exit $?): see $bed/settle.log and $bed/settle.out"
    grep -h "SETTLED" "$bed/settle.log" | tail -1
    mv "$bed/bed.restart.part" "$bed/bed.restart"
  fi
  echo "converting the bed for LAMMPS"
  (cd "$bed" && liggghts -in "$peers/liggghts/in.dump" -var FIBRE "$fibre_inc" -var RESTART "$bed/bed.restart" \
    -var OUTF "$bed/bed.dump" -log "$bed/dump.log" >"$bed/dump.out" 2>&1) ||
    die 1 "writing the bed's dump failed: see $bed/dump.log"
  python3 "$peers/dump2data.py" "$bed/bed.dump" "$data" || die 1 "converting $bed/bed.dump failed"
}
if has liggghts || has lammps || [ $settle_only = 1 ]; then settle_bed; fi
[ $settle_only = 1 ] && exit 0

# ---- chute inputs: LAMMPS's bench/ files, used where they are, never shipped --
if has chute; then
  if [ -z "$chute_dir" ]; then
    for d in /usr/share/lammps/bench /usr/share/lammps*/bench /usr/share/doc/lammps*/bench /usr/share/doc/lammps*/examples/bench; do
      [ -f "$d/in.chute" ] && [ -f "$d/data.chute" ] && chute_dir=$d && break
    done
  fi
  if [ -n "$chute_dir" ] && [ -f "$chute_dir/in.chute" ] && { [ -f "$chute_dir/data.chute" ] || [ -f "$chute_dir/data.chute.gz" ]; }; then
    mkdir -p "$cache/chute" || die 2 "--cache $cache: cannot create $cache/chute"
    cp "$chute_dir/in.chute" "$cache/chute/" || die 2 "cannot copy the chute inputs to $cache/chute"
    if [ -f "$chute_dir/data.chute" ]; then cp "$chute_dir/data.chute" "$cache/chute/"; else gunzip -c "$chute_dir/data.chute.gz" >"$cache/chute/data.chute"; fi
  else
    [ -n "$chute_dir" ] && echo "peers.sh: --chute-dir $chute_dir: no in.chute and data.chute there" >&2
    echo "peers.sh: skipping the chute: Debian's lammps packages do not ship LAMMPS's bench/ folder. Take in.chute and data.chute from bench/ of the LAMMPS source (a release tarball from lammps.org, or the lammps/lammps repository) and pass --chute-dir DIR" >&2
    codes=${codes//chute/}
  fi
fi
has liggghts || has lammps || has fibresim || has spheres || has chute || die 2 "nothing left to run (--codes $codes)"

# ---- 3. fibresim ---------------------------------------------------------------
fibresim=$repo/target/release/fibresim
if has fibresim || has spheres; then
  cargo build --release -q || die 1 "cargo build --release failed"
fi

# ---- the run's folder ----------------------------------------------------------
out=${out:-out/peers/$(date +%Y%m%d-%H%M%S)}
if [ -e "$out" ] && [ -n "$(ls -A "$out" 2>/dev/null)" ]; then
  die 2 "--out $out: the folder is not empty; give a new one, so that two runs never mix"
fi
mkdir -p "$out" || die 2 "--out $out: cannot create it"
out=$(cd "$out" && pwd)
csv=$out/jobs.csv
dt=1e-6
t_end=$(python3 -c "print(repr($steps * $dt))")
every=$((steps < 500 ? steps : 500)) # the peers' thermo cadence
{
  echo "Peer comparison, $(date '+%Y-%m-%d %H:%M %Z'), $cores cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'))"
  echo "fibresim $(git rev-parse --short HEAD 2>/dev/null)$(git diff --quiet HEAD -- src Cargo.toml Cargo.lock 2>/dev/null || echo ' (modified)'), $(dpkg-query -W -f='liggghts ${Version}, ' liggghts 2>/dev/null)$(dpkg-query -W -f='lammps ${Version}' lammps 2>/dev/null)"
  echo "beds: 10^4 fibres (and 10^4 spheres), dt = $dt s, $warmup warm-up steps (peers) + $steps timed steps; $rounds rounds; counts ${ns[*]}$([ $quick = 1 ] && echo '; QUICK MODE: a check, not a measurement')"
} >"$out/meta.txt"
cat "$out/meta.txt"

# ---- 4. the rounds ---------------------------------------------------------------
# job ROUND CODE N COMMAND...: run one job in its own folder, then append its row.
job() {
  local r=$1 code=$2 n=$3
  shift 3
  local d=$out/r$r/$code-$n
  mkdir -p "$d"
  read -r l1 l5 l15 _ </proc/loadavg
  printf '%s\n' "$*" >"$d/command.txt"
  (cd "$d" && "$@") >"$d/stdout.txt" 2>&1
  local rc=$?
  python3 "$repo/scripts/peers_report.py" row "$csv" "$r" "$code" "$n" "$d" "$rc" "$l1" "$l5" "$l15"
  sleep "$pause"
}
# The functions below are called through `job`.
# shellcheck disable=SC2317,SC2016
# The MPI launch of a peer: each rank under its own /usr/bin/time (per-rank RSS).
peer() { # n binary args...
  local n=$1
  shift
  if [ "$n" = 1 ]; then
    /usr/bin/time -v -o time.txt "$@" -log log.txt
  else
    local over=()
    [ "$n" -gt "$cores" ] && over=(--oversubscribe)
    "${mpi[@]}" "${over[@]}" -np "$n" sh -c 'exec /usr/bin/time -v -o time.rank$OMPI_COMM_WORLD_RANK "$@"' sh "$@" -log log.txt
  fi
}
# The chute reads data.chute from the folder it runs in.
# shellcheck disable=SC2317
chute() {
  ln -sf "$cache/chute/data.chute" data.chute && peer 1 lmp -in "$cache/chute/in.chute"
}
trap 'echo "interrupted: rows so far are in $csv" >&2; exit 130' INT TERM
for r in $(seq 1 "$rounds"); do
  echo "round $r/$rounds"
  for n in "${ns[@]}"; do
    has liggghts && job "$r" liggghts "$n" peer "$n" liggghts -in "$peers/liggghts/in.timed" -var FIBRE "$fibre_inc" \
      -var RESTART "$bed/bed.restart" -var NWARM "$warmup" -var NTIME "$steps"
    has lammps && job "$r" lammps "$n" peer "$n" lmp -in "$peers/lammps/in.timed" -var DATA "$data" \
      -var NWARM "$warmup" -var NTIME "$steps"
    has fibresim && job "$r" fibresim "$n" env RAYON_NUM_THREADS="$n" /usr/bin/time -v -o time.txt "$fibresim" run \
      "$repo/scenarios/bed_10k.toml" --dt "$dt" --t-end "$t_end" --every "$every" --threads "$n" -q --out out
  done
  for n in "${ns[@]}"; do
    has spheres && job "$r" spheres "$n" env RAYON_NUM_THREADS="$n" /usr/bin/time -v -o time.txt "$fibresim" run \
      "$repo/scenarios/bed_spheres_10k.toml" --dt "$dt" --t-end "$t_end" --every "$every" --threads "$n" -q --out out
  done
  has chute && job "$r" chute 1 chute
done
trap - INT TERM

# ---- 5. report and figure ----------------------------------------------------------
python3 "$repo/scripts/peers_report.py" report "$csv" "$out"
status=$?
if [ "$(wc -l <"$out/medians.csv" 2>/dev/null || echo 0)" -gt 1 ] && [ -x "$fibresim" ]; then
  "$fibresim" plot "$out/medians.csv" --column M_fibre_steps_per_s --x threads -o "$out/peers.png" >/dev/null &&
    echo "figure: $out/peers.png" || echo "peers.sh: the figure could not be drawn (fibresim plot failed)" >&2
fi
echo "jobs: $csv; summary: $out/summary.md"
exit $status
