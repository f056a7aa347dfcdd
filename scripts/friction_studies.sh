#!/usr/bin/env bash
# Every friction study of the docs: the rotators where friction drives spin
# (docs/studies.md, "Rotators with friction"), the frictional beds and the
# heap (docs/beds.md). Copies the figures into docs/figures/ and puts the
# tables between the pages' <!-- BEGIN name --> / <!-- END name --> markers.
#
#   scripts/friction_studies.sh [OUT_DIR]      # default out/friction
#
# About 1 h of wall time on the shared 2-core machine at load 8 (one thread
# each; the beds and the 2000-fibre bed of the rotator study are the long
# parts).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/friction}
scripts/friction_beds.sh "$out/beds"
scripts/friction_rotators.sh "$out/rotators"
scripts/heap.sh "$out/heap" 3000

splice() { # FILE NAME TABLE
  awk -v name="$2" -v table="$3" '
    $0 == "<!-- BEGIN " name " -->" { print; while ((getline l < table) > 0) print l; skip = 1; next }
    $0 == "<!-- END " name " -->" { skip = 0 }
    !skip' "$1" >"$1.tmp"
  mv "$1.tmp" "$1"
}
splice docs/beds.md friction_beds "$out/beds/packing.md"
splice docs/studies.md friction_rotators "$out/rotators/table.md"
cp "$out/rotators/friction_work_precision.png" docs/figures/friction_work_precision.png
cp "$out/heap/heap_profile.png" docs/figures/heap_profile.png
