#!/usr/bin/env python3
"""Turn the LIGGGHTS dump of the settled multisphere bed into a LAMMPS data file.

    dump2data.py BED.dump BED.data

The dump (peers/liggghts/in.dump) lists every sphere sorted by id; LIGGGHTS
inserts a multisphere body's spheres with consecutive ids, so spheres
4k+1 .. 4k+4 are fibre k+1. Each group is checked to be one fibre (four
spheres of diameter 0.01 m on a line, end centres 0.02 m apart) before it is
written, so a dump of another layout is refused rather than mis-assigned.

The data file is for atom_style sphere with a molecule id per sphere (read with
`fix property/atom mol`), for fix rigid/small. Each sphere's density is the
fibre's mass (the dump's per-sphere mass column holds the body mass) over four
sphere volumes, so a LAMMPS body weighs what the LIGGGHTS body weighs; its
inertia, summed from the spheres, counts the overlaps twice (LIGGGHTS
integrates the union instead). Positions and velocities are copied as written.
Standard library only. Exit status 2 with a message on bad input.
"""

import math
import os
import sys

SPHERES = 4
DIAMETER = 0.01
END_SPAN = 0.02  # distance between the end spheres' centres, m
TOL = 1e-6  # m: far above the full-precision dump's rounding, far below a sphere's size


def fail(path, line, what, fix):
    where = f"{path}:{line}" if line else path
    print(f"dump2data: {where}: {what}; {fix}", file=sys.stderr)
    sys.exit(2)


def read_dump(path):
    try:
        lines = open(path).read().splitlines()
    except OSError as e:
        fail(path, 0, f"cannot read it ({e.strerror})", "give the dump written by peers/liggghts/in.dump")
    try:
        head = next(k for k, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
        bounds = next(k for k, l in enumerate(lines) if l.startswith("ITEM: BOX BOUNDS"))
    except StopIteration:
        fail(path, 0, "no 'ITEM: BOX BOUNDS' or 'ITEM: ATOMS' header", "give a LIGGGHTS text dump (write_dump ... custom)")
    box = []
    for d in range(3):
        parts = lines[bounds + 1 + d].split()
        box.append((parts[0], parts[1]))
    cols = lines[head].split()[2:]
    need = ["id", "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz", "radius", "mass"]
    missing = [c for c in need if c not in cols]
    if missing:
        fail(path, head + 1, f"columns {missing} missing", "write the dump with peers/liggghts/in.dump")
    rows = []
    for k, l in enumerate(lines[head + 1 :], start=head + 2):
        vals = l.split()
        if len(vals) != len(cols):
            fail(path, k, f"{len(vals)} values for {len(cols)} columns", "the dump is truncated: write it again")
        rows.append((k, dict(zip(cols, vals))))
    return box, rows


def check_fibres(path, rows):
    if not rows or len(rows) % SPHERES:
        fail(path, 0, f"{len(rows)} spheres, not a multiple of {SPHERES}", "the bed must hold whole 4-sphere fibres")
    for i, (k, a) in enumerate(rows):
        if int(a["id"]) != i + 1:
            fail(path, k, f"id {a['id']} where {i + 1} was expected", "the dump must be sorted by id with no gaps (modify sort id)")
        if abs(2.0 * float(a["radius"]) - DIAMETER) > TOL:
            fail(path, k, f"sphere diameter {2 * float(a['radius'])} m", f"the fibres are made of spheres of diameter {DIAMETER} m")
    for b in range(len(rows) // SPHERES):
        group = rows[b * SPHERES : (b + 1) * SPHERES]
        p = [[float(a[c]) for c in ("x", "y", "z")] for _, a in group]
        span = math.dist(p[0], p[-1])
        # Collinear and evenly spaced: each centre where it sits on the line between the ends.
        off = max(
            math.dist(p[j], [p[0][c] + (p[-1][c] - p[0][c]) * j / (SPHERES - 1) for c in range(3)])
            for j in range(SPHERES)
        )
        if abs(span - END_SPAN) > TOL or off > TOL:
            k = group[0][0]
            fail(
                path,
                k,
                f"spheres {b * SPHERES + 1}-{(b + 1) * SPHERES} are not one fibre (end span {span:.6g} m, off line {off:.3g} m)",
                "ids must number each body's spheres consecutively, as LIGGGHTS's insert/pack does",
            )


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        sys.exit(2)
    src, dst = sys.argv[1], sys.argv[2]
    box, rows = read_dump(src)
    check_fibres(src, rows)
    r = float(rows[0][1]["radius"])
    body_mass = float(rows[0][1]["mass"])
    rho = (body_mass / SPHERES) / (4.0 / 3.0 * math.pi * r**3)
    out = [
        f"LAMMPS data file of the settled LIGGGHTS multisphere bed {src}: {len(rows) // SPHERES} fibres of {SPHERES} spheres, "
        f"sphere density {rho:.6g} kg/m^3 (fibre mass {body_mass:.6g} kg)",
        "",
        f"{len(rows)} atoms",
        "1 atom types",
        "",
    ]
    out += [f"{lo} {hi} {n}lo {n}hi" for (lo, hi), n in zip(box, "xyz")]
    out += ["", "Atoms # sphere", ""]
    out += [f"{a['id']} 1 {2 * float(a['radius']):.6g} {rho:.8g} {a['x']} {a['y']} {a['z']}" for _, a in rows]
    out += ["", "Velocities", ""]
    out += [f"{a['id']} {a['vx']} {a['vy']} {a['vz']} {a['omegax']} {a['omegay']} {a['omegaz']}" for _, a in rows]
    out += ["", "Molecules", ""]
    out += [f"{a['id']} {(int(a['id']) - 1) // SPHERES + 1}" for _, a in rows]
    tmp = dst + ".part"
    try:
        with open(tmp, "w") as f:
            f.write("\n".join(out) + "\n")
        os.replace(tmp, dst)
    except OSError as e:
        fail(dst, 0, f"cannot write it ({e.strerror})", "give a writable path")
    print(f"{dst}: {len(rows) // SPHERES} fibres, fibre mass {body_mass:.6g} kg, sphere density {rho:.6g} kg/m^3")


if __name__ == "__main__":
    main()
