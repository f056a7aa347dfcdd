#!/usr/bin/env python3
"""Packing fraction and coordination number of the settled beds of
scripts/friction_beds.sh:

    scripts/bed_packing.py OUT_DIR

For each OUT_DIR/bed_<name>.toml (its body file: the exact settled states)
and OUT_DIR/frame_<name>/ (a VTK frame of the same bed, whose `contacts`
array counts the bodies and walls each fibre touches):

- the measuring box: the bed's horizontal cross-section less m = L/2 + D
  from every side wall, and in height from m above the floor to m below
  the free surface, taken as the 95th percentile of the fibres'
  topmost points (so a few fibres standing proud do not raise it);
- φ: the fibre volume inside the measuring box over its volume, each fibre
  cut by the box counted by 4000 points sampled in it
  (scripts/fibre_frames.py: a fibre wholly in or out is exact);
- Z: the mean number of bodies touched by the fibres whose centre lies in
  the measuring box (no wall is within reach of them: a fibre reaches
  √(L² + D²)/2 < m from its centre); Z_nr the same over the
  fibres with at least two contacts (rattlers, with 0 or 1, left out), and
  their share;
- ⟨cos² θ⟩: θ a fibre's axis against the vertical, over the same fibres
  (1/3 isotropic, 0 all lying flat);
- φ·L/D beside Z/2: for thin rods Philipse's random contact equation says
  φ L/D = ⟨c⟩/2 (docs/beds.md), so the two columns meet for long fibres.
"""
import glob
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fibre_frames as ff  # noqa: E402


def measure(toml, frame_dir):
    lo, hi, body_file = ff.scenario(toml)
    ids, x, q, d, l = ff.bodies(body_file)
    L, D = l[0], d[0]
    a = ff.axes(q)
    top = x[:, 2] + 0.5 * L * np.abs(a[:, 2]) + 0.5 * D * np.sqrt(1 - a[:, 2] ** 2)
    surface = np.percentile(top, 95)
    m = L / 2 + D
    mlo = np.array([lo[0] + m, lo[1] + m, lo[2] + m])
    mhi = np.array([hi[0] - m, hi[1] - m, surface - m])
    phi = ff.volume_in_box(x, q, d, l, mlo, mhi) / np.prod(mhi - mlo)
    if np.any(mhi <= mlo):
        return None  # a bed too thin for a measuring box clear of walls and surface
    f = ff.vtk_frame(ff.last_frame(frame_dir))
    contacts = dict(zip(f["id"].tolist(), f["contacts"].tolist()))
    inside = np.all((x >= mlo) & (x <= mhi), axis=1)
    z = np.array([contacts[int(i)] for i in ids[inside]])
    nr = z[z >= 2]
    cos2 = np.mean(a[inside, 2] ** 2)
    # Bed-wide: every fibre, wall contacts included (the number docs/beds.md
    # quotes for the shipped beds).
    z_all = np.mean(list(contacts.values()))
    return dict(n=len(ids), ar=L / D, phi=phi, box=mhi - mlo, surface=surface, n_in=int(inside.sum()),
                z=z.mean(), z_nr=nr.mean(), rattlers=1 - len(nr) / len(z), z_bed=z_all, cos2=cos2)


def main(out):
    rows = []
    for toml in sorted(glob.glob(os.path.join(out, "bed_*.toml"))):
        name = os.path.basename(toml)[4:-5]
        frame = os.path.join(out, f"frame_{name}")
        if not os.path.isdir(frame):
            continue
        mu = name.split("_mu")[1]
        mu = "0" if mu == "0" else "0." + mu[1:]
        m = measure(toml, frame)
        if m is None:
            print(f"{name}: too thin for a measuring box", file=sys.stderr)
            continue
        rows.append((name, mu, m))
    rows.sort(key=lambda r: (r[2]["ar"], float(r[1])))
    print("| L/D | μ | fibres | settled | measuring box (cm), fibres in it | φ | Z | Z without rattlers (share of rattlers) | φ·L/D, Z/2 | Z of the whole bed, walls counted | ⟨cos² θ⟩ |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, mu, m in rows:
        settled = "–"
        summary = os.path.join(out, f"settle_{name}", "summary.json")
        if os.path.exists(summary):
            s = json.load(open(summary))
            settled = f"yes, {s['steps']} steps" if s.get("settled") else f"no ({s['steps']} steps)"
        b = " × ".join(f"{100 * v:.1f}" for v in m["box"])
        print(f"| {m['ar']:.0f} | {mu} | {m['n']} | {settled} | {b}, {m['n_in']} | {m['phi']:.3f} | {m['z']:.2f} | "
              f"{m['z_nr']:.2f} ({100 * m['rattlers']:.0f} %) | {m['phi'] * m['ar']:.2f}, {m['z'] / 2:.2f} | {m['z_bed']:.2f} | {m['cos2']:.2f} |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/beds")
