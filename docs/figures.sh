#!/usr/bin/env bash
# Regenerate every figure in docs/figures/ and the tables that a command
# prints, with the exact commands the manual (docs/) shows beside them.
#
#   docs/figures.sh              everything (test cases 1-2 take minutes)
#   docs/figures.sh --skip-long  all but test cases 1 and 2
#
# Times are wall times on the shared 2-core machine (2026-12).
# The study commands write to their default folders under out/ and print
# their tables (the numbers in docs/validation.md and docs/studies.md); this
# script copies the figures into docs/figures/ under the names the pages use.
set -euo pipefail
cd "$(dirname "$0")/.."

long=1
case "${1:-}" in
  --skip-long) long=0 ;;
  "") ;;
  *) echo "usage: $0 [--skip-long]" >&2; exit 2 ;;
esac

cargo build --release # warm target/: seconds; cold: ~3 min
fibresim=target/release/fibresim
fig=docs/figures
mkdir -p "$fig"

# Replace the lines between '<!-- BEGIN name -->' and '<!-- END name -->'
# in FILE with the contents of TABLE (a generated markdown table).
splice() {
  local file=$1 name=$2 table=$3
  if ! grep -q "<!-- BEGIN $name -->" "$file"; then
    echo "note: $file has no '<!-- BEGIN $name -->' marker; paste $table by hand" >&2
    return
  fi
  awk -v name="$name" -v table="$table" '
    $0 == "<!-- BEGIN " name " -->" { print; while ((getline l < table) > 0) print l; skip = 1; next }
    $0 == "<!-- END " name " -->" { skip = 0 }
    !skip' "$file" >"$file.tmp"
  mv "$file.tmp" "$file"
}

# --- Generated reference tables: instant ----------------------------------
mkdir -p out
"$fibresim" rotators --markdown >out/rotators.md
splice docs/rotators.md rotators out/rotators.md
"$fibresim" keys --markdown >out/keys.md
splice docs/scenario.md keys out/keys.md

# --- Stress suite and stability map: ~1 s (616 runs) -----------------------
"$fibresim" stress --out out/stress -q
cp out/stress/stability_map.png "$fig/stability_map.png"
splice docs/stress.md stress_full out/stress/stress_full.md
splice docs/stress.md stress_table out/stress/stress_table.md

# --- Test case 3 (Table 2), closed form: ~0.3 s and ~1.5 s ------------------
"$fibresim" compare scenarios/torque_sphere.toml --rotators all
cp out/torque_sphere/compare/angle_error_closed_form.png "$fig/tc3_compare.png"
"$fibresim" converge scenarios/torque_sphere.toml --rotators all
cp out/torque_sphere/converge/convergence_x_error.png "$fig/tc3_convergence_x_error.png"

# --- Test case 4 (Fig. 7): ~0.5 s and ~10 s ---------------------------------
# converge: rk4 reference at 1e-8 s (1e7 steps, ~5 s), the 7 x 5 error runs
# in parallel, then the sequential timing pass for the work-precision
# figure (~4 s: each point timed alone, median of 3-5 repeats under 0.5 s).
"$fibresim" compare scenarios/torque_fibre.toml
cp out/torque_fibre/compare/angle_error_rk4.png "$fig/tc4_compare.png"
"$fibresim" converge scenarios/torque_fibre.toml # every scheme by default
cp out/torque_fibre/converge/convergence.png "$fig/tc4_convergence.png"
cp out/torque_fibre/converge/convergence_geodesic.png "$fig/tc4_convergence_geodesic.png"
cp out/torque_fibre/converge/work_precision.png "$fig/tc4_work_precision.png"

# --- Tables printed by tests: ~1 min each if the tests need a rebuild --------
# docs/validation.md "Test case 3": angle and x-errors of every rotator at dt = 1e-4.
cargo test --release --test suite -q rotators::test_case_3 -- --nocapture
# docs/validation.md "Orders of convergence".
cargo test --release --test suite -q rotator_order:: -- --include-ignored --nocapture

if [ "$long" = 1 ]; then
  # --- Test cases 1 and 2 (Figs. 2-4), dt = 1e-7, 2 s, 2e7 steps per run ------
  # Test case 1: ~20 s (5 single-fibre runs on 2 cores; 1/10 of it took 1.7 s).
  "$fibresim" compare scenarios/single_fibre.toml --rotators pcdm,scalar,euler,leapfrog,frozen
  cp out/single_fibre/compare/energy_error_full.png "$fig/tc1_compare.png"
  # Test case 2: ~1-2 min (4 nine-fibre runs of ~17 s of stepping each, on
  # 2 cores, more while contacts are live). The `frozen` baseline row of
  # docs/validation.md's table comes from a separate run, so it is not in
  # the figure.
  "$fibresim" compare scenarios/nine_fibres.toml --rotators pcdm,scalar,euler,leapfrog
  cp out/nine_fibres/compare/energy_error_full.png "$fig/tc2_compare.png"
  "$fibresim" compare scenarios/nine_fibres.toml --rotators frozen --out out/nine_fibres/frozen # ~20 s
fi
[ "$long" = 0 ] || scripts/friction_studies.sh # friction: rotators, beds, heap (~1 h)
echo "figures in $fig/"
