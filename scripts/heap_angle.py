#!/usr/bin/env python3
"""The angle of repose of a settled heap (scripts/heap.sh):

    scripts/heap_angle.py HEAP.toml [--png FIGURE.png]

The heap's surface: 400 points sampled in each fibre (scripts/fibre_frames.py);
around the vertical axis through the fibres' mean centre, the highest point
in each ring of width D and each of 8 azimuthal sectors is the surface
height h(r) of that sector. The flank is where the median profile over the
sectors lies between 15 % and 85 % of the heap's height H (the rounded top
and the toe left out); the angle is atan of the slope of a least-squares line
through the median profile there, and the sectors' own fits give its spread.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fibre_frames as ff  # noqa: E402

SECTORS = 8


def surface(toml):
    lo, hi, body_file = ff.scenario(toml)
    _, x, q, d, l = ff.bodies(body_file)
    u = ff.unit_cylinder_points(400) * np.array([l[0], d[0], d[0]])
    p = np.concatenate([ff.rotate(q[s:s + 200], u) + x[s:s + 200, None, :]
                        for s in range(0, len(x), 200)], axis=0).reshape(-1, 3)
    c = x[:, :2].mean(axis=0)
    r = np.hypot(p[:, 0] - c[0], p[:, 1] - c[1])
    sector = ((np.arctan2(p[:, 1] - c[1], p[:, 0] - c[0]) + np.pi) / (2 * np.pi) * SECTORS).astype(int) % SECTORS
    dr = d[0]
    ring = (r / dr).astype(int)
    rings = ring.max() + 1
    h = np.full((SECTORS, rings), np.nan)
    np.fmax.at(h, (sector, ring), p[:, 2])
    return (np.arange(rings) + 0.5) * dr, h, len(x), d[0], l[0], lo[2]


def fit(r, h, floor):
    """Slope angle (deg) and intercept of the flank of profile h(r)."""
    z = h - floor
    top = np.nanmax(z)
    ok = np.isfinite(z) & (z >= 0.15 * top) & (z <= 0.85 * top)
    # The flank: from the first ring below 85 % to the last above 15 %.
    first = np.argmax(np.isfinite(z) & (z <= 0.85 * top) & (r > r[np.nanargmax(z)]))
    ok &= r >= r[first]
    b, a = np.polyfit(r[ok], z[ok], 1)
    return np.degrees(np.arctan(-b)), a, ok, top


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("heap")
    ap.add_argument("--png")
    args = ap.parse_args()
    r, h, n, D, L, floor = surface(args.heap)
    median = np.nanmedian(h, axis=0)
    angle, a, ok, top = fit(r, median, floor)
    per = []
    for s in range(SECTORS):
        try:
            per.append(fit(r, h[s], floor)[0])
        except (ValueError, TypeError, np.linalg.LinAlgError):
            pass
    per = np.array(per)
    radius = r[np.isfinite(median) & (median - floor > D)].max()
    print(f"{n} fibres (L/D = {L / D:.0f}): heap height {100 * top:.1f} cm, radius {100 * radius:.1f} cm "
          f"({top / L:.1f} L high, {radius / L:.1f} L wide); flank fitted over r = "
          f"{100 * r[ok].min():.1f}–{100 * r[ok].max():.1f} cm ({ok.sum()} rings)")
    print(f"angle of repose {angle:.1f}° (median profile); the {len(per)} sectors' fits: "
          f"{per.mean():.1f}° ± {per.std(ddof=1):.1f}° (min {per.min():.1f}°, max {per.max():.1f}°)")
    if args.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7.5, 2.9))
        for s in range(SECTORS):
            ax.plot(100 * r, 100 * (h[s] - floor), ".", ms=3, color="0.7")
        ax.plot(100 * r, 100 * (median - floor), "k-", lw=1.2, label="median over 8 sectors")
        rr = r[ok]
        ax.plot(100 * rr, 100 * (a - np.tan(np.radians(angle)) * rr), "r--", lw=1.5,
                label=f"fit: {angle:.1f}°")
        ax.set_xlabel("distance from the heap's axis r (cm)")
        ax.set_ylabel("surface height (cm)")
        ax.set_aspect("equal")
        ax.set_title(f"heap of {n} fibres, L/D = {L / D:.0f}")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.png, dpi=110)


if __name__ == "__main__":
    main()
