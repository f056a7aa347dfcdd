#!/usr/bin/env python3
"""The markdown table and the work–precision figure of docs/studies.md,
"Rotators with friction", from the outputs of scripts/friction_rotators.sh:

    scripts/friction_rotators_table.py OUT_DIR [--png FIGURE.png]

reads OUT_DIR/{drop_energy,drop_trajectory,bed_trajectory}/convergence.csv,
orders.csv and reference.csv (fibresim converge) and
OUT_DIR/cost_{drop,bed}.txt (cargo bench --bench contact_rotators), prints one
row per rotator (the full-budget energy error of the whole frictional drop,
the distance, angle and energy error at the end of its first 0.03 s and of the
bed's 2 ms with the fitted order of the distance, the CPU time per body-step
on each scene, and the instructions per body-step of the callgrind stage)
and the references' own errors, and draws the work–precision
figure: error against CPU time of the run (the bench's CPU ns per body-step
× bodies × steps), for the rotators the bench times.
"""
import argparse
import csv
import os


def table(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def points(out, study):
    """{(rotator, dt): row} of a convergence.csv ({} if the study is absent)."""
    path = os.path.join(out, study, "convergence.csv")
    if not os.path.exists(path):
        return {}
    return {(r["rotator"], float(r["dt"])): r for r in table(path)}


def orders(out, study, metric):
    path = os.path.join(out, study, "orders.csv")
    if not os.path.exists(path):
        return {}
    return {r["rotator"]: r["order"] for r in table(path) if r["metric"] == metric}


def costs(out, scene):
    """{rotator: CPU ns per body-step} from the bench's printout."""
    got = {}
    path = os.path.join(out, f"cost_{scene}.txt")
    if not os.path.exists(path):
        return got
    with open(path) as f:
        for line in f:
            w = line.split()
            if len(w) > 2 and w[0][0].isalpha() and w[1].replace(".", "").isdigit():
                got[w[0]] = float(w[1])
    return got


def instructions(out):
    """{rotator: instructions per body-step} of the callgrind stage."""
    path = os.path.join(out, "instructions_drop.txt")
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return {w[0]: int(w[2]) for w in (line.split() for line in f) if len(w) == 3}


def e(x):
    return f"{float(x):.2g}" if x not in ("", None) else "–"


def cell(p, col):
    if p is None:
        return "–"
    if p["stopped"]:
        return "stopped"
    return e(p[col])


def order(o, k):
    return f"{float(o[k]):.2f}" if k in o and o[k] not in ("", "NaN", "nan") else "–"


def figure(out, png, whole, window, c_drop):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = 50  # bodies of the drop
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    panels = [(window, "geodesic_rad", "first 0.03 s: largest angle to the reference at T (rad)"),
              (whole, "energy_error_full_max_pct", "drop, 0.3 s: largest full-budget energy error (%)")]
    markers = "os^vD<>phx*+"
    for ax, (pts, col, label) in zip(axes, panels):
        for i, k in enumerate(c_drop):
            xs, ys = [], []
            for (rot, dt), p in sorted(pts.items(), key=lambda kv: -kv[0][1]):
                if rot != k or p["stopped"] or p[col] in ("", None):
                    continue
                xs.append(c_drop[k] * 1e-9 * n * int(p["steps"]))
                ys.append(float(p[col]))
            if xs:
                ax.loglog(xs, ys, marker=markers[i % len(markers)], label=k, lw=1, ms=5)
        ax.set_xlabel("CPU time of the run (s, one thread)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7, ncol=2)
    fig.suptitle("50 fibres dropped with friction μ = 0.5, e = 0.5")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", nargs="?", default="out/friction_rotators")
    ap.add_argument("--png")
    args = ap.parse_args()
    out = args.out
    whole = points(out, "drop_energy")
    window = points(out, "drop_trajectory")
    bed = points(out, "bed_trajectory")
    o_window = orders(out, "drop_trajectory", "position_error_m")
    g_window = orders(out, "drop_trajectory", "geodesic_rad")
    o_bed = orders(out, "bed_trajectory", "position_error_m")
    c_drop, c_bed = costs(out, "drop"), costs(out, "bed")
    ir = instructions(out)
    rotators = list(dict.fromkeys(r for r, _ in window or whole))
    print("| rotator | drop, 0.3 s: E_full max, δt = 4 / 2 / 1 µs (%) "
          "| drop, first 0.03 s: E_full max, 4 / 0.5 µs (%) | distance at T, 4 / 1 / 0.5 µs (m), order "
          "| angle at T, 4 / 1 / 0.5 µs (rad), order "
          "| frictional bed, 2 ms: E_full max, 4 / 1 µs (%) | distance at T, 4 / 1 µs (m), order "
          "| CPU ns per body-step: drop / bed | instructions per body-step, drop |")
    print("|---|---|---|---|---|---|---|---|---|")
    for k in rotators:
        def get(pts, dt):
            return pts.get((k, dt))
        row = [
            f"`{k}`",
            " / ".join(cell(get(whole, d), "energy_error_full_max_pct") for d in (4e-6, 2e-6, 1e-6)),
            " / ".join(cell(get(window, d), "energy_error_full_max_pct") for d in (4e-6, 5e-7)),
            " / ".join(cell(get(window, d), "position_error_m") for d in (4e-6, 1e-6, 5e-7))
            + f", {order(o_window, k)}",
            " / ".join(cell(get(window, d), "geodesic_rad") for d in (4e-6, 1e-6, 5e-7))
            + f", {order(g_window, k)}",
            " / ".join(cell(get(bed, d), "energy_error_full_max_pct") for d in (4e-6, 1e-6)),
            " / ".join(cell(get(bed, d), "position_error_m") for d in (4e-6, 1e-6)) + f", {order(o_bed, k)}",
            f"{c_drop[k]:.0f} / {c_bed[k]:.0f}" if k in c_drop and k in c_bed else "–",
            f"{ir[k]}" if k in ir else "–",
        ]
        print("| " + " | ".join(row) + " |")
    damped, undamped = points(out, "control_damped"), points(out, "control_undamped")
    if damped and undamped:
        print("\n| rotator | whole drop, E_full max at δt = 4 / 2 / 1 µs (%): friction and damping "
              "| damping alone (μ = 0) | friction alone (no restitution) |")
        print("|---|---|---|---|")
        for k in dict.fromkeys(r for r, _ in damped):
            row = [f"`{k}`"] + [" / ".join(cell(pts.get((k, d)), "energy_error_full_max_pct")
                                           for d in (4e-6, 2e-6, 1e-6))
                                 for pts in (whole, damped, undamped)]
            print("| " + " | ".join(row) + " |")
    for study in ("drop_trajectory", "bed_trajectory"):
        path = os.path.join(out, study, "reference.csv")
        if os.path.exists(path):
            r = table(path)[0]
            print(f"\n{study}: reference {r['kind']} at δt = {float(r['dt']):.3g} s; its own error "
                  f"(distance to its twin at 2 δt) {e(r['richardson_position_m'])} m, "
                  f"{e(r['richardson_geodesic_rad'])} rad")
    if args.png and c_drop:
        figure(out, args.png, whole, window, c_drop)


if __name__ == "__main__":
    main()
