"""Readers shared by the bed and heap scripts: a scenario's box, a body file
(exact f64 states) and a fibresim VTK frame's cell arrays, and the volume of
fibres inside a box by sampled points."""
import glob
import os
import re
import tomllib
import zlib

import numpy as np


def scenario(path):
    """(box min, box max, body file path) of a scenario TOML."""
    with open(path, "rb") as f:
        s = tomllib.load(f)
    body = os.path.join(os.path.dirname(path), s["bodies"]["file"])
    return np.array(s["box"]["min"]), np.array(s["box"]["max"]), body


def bodies(path):
    """The body file's columns as arrays: id, x (N×3), q (N×4, w first), D, L."""
    a = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding=None)
    x = np.stack([a["x"], a["y"], a["z"]], axis=1).astype(float)
    q = np.stack([a["qw"], a["qx"], a["qy"], a["qz"]], axis=1).astype(float)
    return a["id"].astype(int), x, q, a["diameter"].astype(float), a["length"].astype(float)


def rotate(q, v):
    """R(q) v for unit quaternions q (N×4, w first) and body vectors v (M×3): N×M×3."""
    w, r = q[:, 0][:, None, None], q[:, 1:][:, None, :]
    v = v[None, :, :]
    t = 2.0 * np.cross(r, v)
    return v + w * t + np.cross(r, t)


def axes(q):
    """Each fibre's axis R(q) e_x."""
    return rotate(q, np.array([[1.0, 0.0, 0.0]]))[:, 0, :]


def unit_cylinder_points(n, seed=0):
    """n points uniform in the cylinder of unit length and unit diameter along x
    (a fixed pseudo-random set, so a measurement is repeatable)."""
    g = np.random.default_rng(seed)
    r = 0.5 * np.sqrt(g.random(n))
    a = 2 * np.pi * g.random(n)
    return np.stack([g.random(n) - 0.5, r * np.cos(a), r * np.sin(a)], axis=1)


def volume_in_box(x, q, d, l, lo, hi, samples=4000, chunk=200):
    """Σ over fibres of the fibre volume inside the box [lo, hi], each fibre's
    share from `samples` points uniform in it (a fibre wholly in or out is
    exact). All fibres share one D and one L here (the beds of this study)."""
    assert np.ptp(d) == 0 and np.ptp(l) == 0, "one fibre size per bed"
    u = unit_cylinder_points(samples) * np.array([l[0], d[0], d[0]])
    vol = np.pi / 4 * d[0] ** 2 * l[0]
    total = 0.0
    for s in range(0, len(x), chunk):
        p = rotate(q[s:s + chunk], u) + x[s:s + chunk, None, :]
        inside = np.all((p >= lo) & (p <= hi), axis=2)
        total += vol * inside.mean(axis=1).sum()
    return total


def vtk_frame(path):
    """{name: array} of the cell data of a fibresim .vtp frame (appended raw,
    UInt64 headers, little endian; zlib blocks when the header names
    vtkZLibDataCompressor)."""
    raw = open(path, "rb").read()
    zipped = b"vtkZLibDataCompressor" in raw[:400]
    head, _, data = raw.partition(b'<AppendedData encoding="raw">')
    base = data.index(b"_") + 1
    types = {"Float32": "<f4", "Float64": "<f8", "Int32": "<i4", "Int64": "<i8"}
    out = {}
    for m in re.finditer(rb'<DataArray type="(\w+)" Name="(\w+)" NumberOfComponents="(\d+)"[^>]*offset="(\d+)"', head):
        t, name, comps, off = m.group(1).decode(), m.group(2).decode(), int(m.group(3)), int(m.group(4))
        if zipped:
            # VTK's compressed layout: [blocks, block size, last block size,
            # each block's compressed size], then the blocks.
            nb = int(np.frombuffer(data, "<u8", 1, base + off)[0])
            sizes = np.frombuffer(data, "<u8", nb, base + off + 24).astype(int)
            at, parts = base + off + 24 + 8 * nb, []
            for s in sizes:
                parts.append(zlib.decompress(data[at:at + s]))
                at += s
            a = np.frombuffer(b"".join(parts), types[t])
        else:
            n = int(np.frombuffer(data, "<u8", 1, base + off)[0])
            a = np.frombuffer(data, types[t], n // np.dtype(types[t]).itemsize, base + off + 8)
        out[name] = a.reshape(-1, comps) if comps > 1 else a
    return out


def last_frame(run_dir):
    """The last VTK frame of a run's output folder."""
    return sorted(glob.glob(os.path.join(run_dir, "vtk", "fibres_*.vtp")))[-1]
