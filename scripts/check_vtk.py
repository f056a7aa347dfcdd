#!/usr/bin/env python3
"""Check a run's VTK series with VTK itself (the `vtk` package from PyPI).

    scripts/check_vtk.py OUT_DIR               check OUT_DIR/fibres.pvd, its frames and box.vtp
    scripts/check_vtk.py --run BIN OUT_DIR     first run BIN on test case 2 with --vtk-every 2000
                                               (t_end 0.2 s: 1000 frames) into OUT_DIR
    --no-install                               do not pip-install vtk; exit 77 if it is missing

Checks, for every frame the .pvd lists (parsed as XML; the VTK wheel has no
PVD reader): the file opens with vtkXMLPolyDataReader, has one VTK_LINE cell
per body of summary.json and the documented cell arrays with their component
counts, and its TimeValue equals the .pvd's timestep; the times increase. On
the last frame (the run's last step), body 0's two points are its end-face
centres x -+ (L/2) R(q) e_x from summary.json's final state and the
scenario's L, to float32 rounding; its velocity and quaternion equal the
summary's, rounded. box.vtp: 8 points, 12 lines, the scenario's box.
Exit 0 when all hold, 1 with the failures listed.
"""
import json
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

CELL_ARRAYS = {
    "id": 1, "material": 1, "diameter": 1, "length": 1, "quaternion": 4, "axis": 3,
    "velocity": 3, "omega": 3, "omega_body": 3, "speed": 1, "kinetic_energy": 1, "contacts": 1,
}
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def need_vtk(install):
    try:
        import vtk  # noqa: F401
    except ImportError:
        if not install:
            print("vtk is not importable (pip install vtk); skipped")
            sys.exit(77)
        subprocess.run([sys.executable, "-m", "pip", "install", "-q", "vtk"], check=True)
    import vtk
    return vtk


def rotate_x(q):
    """R(q) e_x for q = [w, x, y, z] (docs/physics.md section 1)."""
    w, x, y, z = q
    return [1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)]


def f32_close(a, b, scale=1.0):
    return abs(a - b) <= 2e-7 * max(abs(a), abs(b), scale)


def main(argv):
    install = "--no-install" not in argv
    argv = [a for a in argv if a != "--no-install"]
    if argv[:1] == ["--run"]:
        binary, out = argv[1], argv[2]
        subprocess.run([binary, "run", os.path.join(ROOT, "scenarios/nine_fibres.toml"), "--vtk-every", "2000",
                        "--t-end", "0.2", "-q", "--out", out, "--force"], check=True)
    elif len(argv) == 1:
        out = argv[0]
    else:
        print(__doc__)
        return 2
    vtk = need_vtk(install)
    from vtk.util.numpy_support import vtk_to_numpy  # noqa: F401 (numpy ships with the wheel)

    fails = []
    summary = json.load(open(os.path.join(out, "summary.json")))
    n = summary["bodies"]
    dt = summary["dt"]
    pvd = ET.parse(os.path.join(out, "fibres.pvd")).getroot()
    if pvd.get("type") != "Collection":
        fails.append("fibres.pvd is not a Collection")
    sets = pvd.findall("./Collection/DataSet")
    if not sets:
        fails.append("fibres.pvd lists no frame")
    last_t = -math.inf
    data = None
    for ds in sets:
        t = float(ds.get("timestep"))
        if not t > last_t:
            fails.append(f"timestep {t} does not increase")
        last_t = t
        path = os.path.join(out, ds.get("file"))
        r = vtk.vtkXMLPolyDataReader()
        r.SetFileName(path)
        r.Update()
        data = r.GetOutput()
        name = ds.get("file")
        if data.GetNumberOfCells() != n or data.GetNumberOfLines() != n:
            fails.append(f"{name}: {data.GetNumberOfCells()} cells, expected {n} lines")
        cd = data.GetCellData()
        for a, comps in CELL_ARRAYS.items():
            arr = cd.GetArray(a)
            if arr is None:
                fails.append(f"{name}: no cell array {a}")
            elif arr.GetNumberOfComponents() != comps or arr.GetNumberOfTuples() != n:
                fails.append(f"{name}: {a} has {arr.GetNumberOfComponents()} x {arr.GetNumberOfTuples()}")
        tv = data.GetFieldData().GetArray("TimeValue")
        if tv is None or tv.GetValue(0) != t:
            fails.append(f"{name}: TimeValue {tv and tv.GetValue(0)} != pvd timestep {t}")
        if any(data.GetCellType(k) != vtk.VTK_LINE for k in range(data.GetNumberOfCells())):
            fails.append(f"{name}: a cell is not a VTK_LINE")
        if fails:
            break
    if data is not None and not fails:
        steps = summary["steps"]
        step = data.GetFieldData().GetArray("step").GetValue(0)
        if step != steps or last_t != steps * dt:
            fails.append(f"last frame is step {step} (t = {last_t}), the run ended at step {steps}")
        final = summary["final"][0]
        scenario = summary["scenario"]
        length = data.GetCellData().GetArray("length").GetValue(0)
        if os.path.exists(scenario):
            import tomllib
            sc = tomllib.load(open(scenario, "rb"))
            if not f32_close(length, sc["body"][0]["length"]):
                fails.append(f"length {length} != scenario's {sc['body'][0]['length']}")
            length = sc["body"][0]["length"]
            b = sc.get("box")
            if b:
                r = vtk.vtkXMLPolyDataReader()
                r.SetFileName(os.path.join(out, "box.vtp"))
                r.Update()
                box = r.GetOutput()
                bounds = box.GetBounds()
                want = (b["min"][0], b["max"][0], b["min"][1], b["max"][1], b["min"][2], b["max"][2])
                if box.GetNumberOfPoints() != 8 or box.GetNumberOfLines() != 12 or tuple(bounds) != want:
                    fails.append(f"box.vtp: {box.GetNumberOfPoints()} points, {box.GetNumberOfLines()} lines, bounds {bounds} != {want}")
        a = rotate_x(final["q"])
        ends = [[x - s * 0.5 * length * ak for x, ak in zip(final["x"], a)] for s in (1, -1)]
        for k, end in enumerate(ends):
            p = data.GetPoint(k)  # body 0's two points
            if not all(f32_close(pc, ec) for pc, ec in zip(p, end)):
                fails.append(f"body 0 end {k}: {p} != {end} from summary.json")
        v = data.GetCellData().GetArray("velocity").GetTuple3(0)
        q = data.GetCellData().GetArray("quaternion").GetTuple4(0)
        if not all(f32_close(a, b) for a, b in zip(v, final["v"])):
            fails.append(f"body 0 velocity {v} != {final['v']}")
        if not all(f32_close(a, b) for a, b in zip(q, final["q"])):
            fails.append(f"body 0 quaternion {q} != {final['q']} (w, x, y, z)")
    for f in fails:
        print("FAIL:", f)
    if not fails:
        print(f"VTK {vtk.vtkVersion.GetVTKVersion()}: {len(sets)} frames of {n} fibres read; "
              f"fields, times, box and body 0's end points agree with summary.json")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
