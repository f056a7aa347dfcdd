#!/usr/bin/env python3
"""The markdown table of docs/studies.md, "The default rotator", from the
outputs of scripts/default_rotator.sh:

    scripts/default_rotator_table.py OUT_DIR

reads OUT_DIR/{drop_energy,drop_trajectory,bed_trajectory}/convergence.csv
and orders.csv (fibresim converge) and OUT_DIR/cost_{drop,bed}.txt (cargo
bench --bench contact_rotators), and prints one row per rotator: the
full-budget energy error of the whole drop, the distance and energy error at
the end of its first 0.06 s and of the bed's 2 ms with the fitted order of
the distance, and the CPU time per body-step on each scene.
"""
import csv
import os
import sys


def table(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def points(out, study):
    """{(rotator, dt): row} of a convergence.csv."""
    return {(r["rotator"], float(r["dt"])): r
            for r in table(os.path.join(out, study, "convergence.csv"))}


def orders(out, study, metric):
    return {r["rotator"]: r["order"]
            for r in table(os.path.join(out, study, "orders.csv"))
            if r["metric"] == metric}


def costs(out, scene):
    """{rotator: CPU ns per body-step} from the bench's printout."""
    got = {}
    with open(os.path.join(out, f"cost_{scene}.txt")) as f:
        for line in f:
            w = line.split()
            if len(w) > 2 and w[0][0].isalpha() and w[1].replace(".", "").isdigit():
                got[w[0]] = float(w[1])
    return got


def e(x):
    return f"{float(x):.2g}" if x not in ("", None) else "–"


def cell(p, col):
    if p is None:
        return "–"
    if p["stopped"]:
        return "stopped"
    return e(p[col])


def main(out):
    dts = [4e-6, 2e-6, 1e-6]
    whole = points(out, "drop_energy")
    window = points(out, "drop_trajectory")
    bed = points(out, "bed_trajectory")
    o_window = orders(out, "drop_trajectory", "position_error_m")
    o_bed = orders(out, "bed_trajectory", "position_error_m")
    c_drop, c_bed = costs(out, "drop"), costs(out, "bed")
    rotators = list(dict.fromkeys(r for r, _ in window))
    print("| rotator | drop, 0.3 s: E_full max, δt = 4 / 2 / 1 µs (%) "
          "| drop, first 0.06 s: E_full max, 4 / 1 µs (%) | distance at T, 4 / 1 µs (m), order "
          "| bed_1k, 2 ms: E_full max, 4 / 1 µs (%) | distance at T, 4 / 1 µs (m) "
          "| CPU ns per body-step: drop / bed |")
    print("|---|---|---|---|---|---|---|")
    for k in rotators:
        get = lambda pts, dt: pts.get((k, dt))
        row = [
            f"`{k}`",
            " / ".join(cell(get(whole, d), "energy_error_full_max_pct") for d in dts),
            " / ".join(cell(get(window, d), "energy_error_full_max_pct") for d in (4e-6, 1e-6)),
            " / ".join(cell(get(window, d), "position_error_m") for d in (4e-6, 1e-6))
            + f", {float(o_window[k]):.2f}",
            " / ".join(cell(get(bed, d), "energy_error_full_max_pct") for d in (4e-6, 1e-6)),
            " / ".join(cell(get(bed, d), "position_error_m") for d in (4e-6, 1e-6)),
            f"{c_drop[k]:.0f} / {c_bed[k]:.0f}" if k in c_drop and k in c_bed else "–",
        ]
        print("| " + " | ".join(row) + " |")
    for study in ("drop_trajectory", "bed_trajectory"):
        r = table(os.path.join(out, study, "reference.csv"))[0]
        print(f"\n{study}: reference {r['kind']} at δt = {float(r['dt']):.3g} s; its own error "
              f"(distance to its twin at 2 δt) {e(r['richardson_position_m'])} m, "
              f"{e(r['richardson_geodesic_rad'])} rad")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/default_rotator")
