#!/usr/bin/env python3
"""Check that a change of plumbing changed no result.

    scripts/same_results.py record BIN DIR     run every shipped scene with BIN into DIR,
                                               write DIR/manifest.txt (one sha256 per output)
    scripts/same_results.py compare DIR_A DIR_B  exit 1 if any output differs

Outputs are energy.csv, orientation.csv, trajectory.csv, summary.json and the
study tables (compare, converge, stress), less what measures the machine: the
wall-time keys and columns (`wall_s`, `ns_per_body_step`, `timing_runs`, and
the work-precision figure, which is drawn from them). Everything else must be
byte-identical.

The scene set: test cases 1-4 with every rotator (test cases 1 and 2 cut
short, except one full-length run each), the aspect-ratio-3 fibre, the stress
suite, `compare` and `converge` on test cases 3 and 4, a checkpointed run
resumed to the same end, and guard stops. About 3 minutes on 2 cores.
"""
import csv
import hashlib
import io
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SC = os.path.join(ROOT, "scenarios")
ROTATORS = ["euler", "leapfrog", "scalar", "direct", "pcdm", "pcdm-start", "rk4", "frozen"]
TIMING = {"wall_s", "ns_per_body_step", "timing_runs", "wall_resumed_s", "wall_total_s"}


def jobs():
    """(name, args, allowed exit codes) of every command to record."""
    j = []
    for r in ROTATORS:
        j.append((f"tc1_{r}", ["run", f"{SC}/single_fibre.toml", "--rotator", r, "--t-end", "0.4"], [0, 3]))
        j.append((f"tc2_{r}", ["run", f"{SC}/nine_fibres.toml", "--rotator", r, "--t-end", "0.3"], [0, 3]))
        j.append((f"tc3_{r}", ["run", f"{SC}/torque_sphere.toml", "--rotator", r], [0, 3]))
        j.append((f"tc4_{r}", ["run", f"{SC}/torque_fibre.toml", "--rotator", r], [0, 3]))
        j.append((f"ar3_{r}", ["run", f"{SC}/single_fibre_ar3.toml", "--rotator", r, "--t-end", "0.4"], [0, 3]))
    j.append(("tc1_full", ["run", f"{SC}/single_fibre.toml"], [0]))
    j.append(("tc2_full", ["run", f"{SC}/nine_fibres.toml"], [0]))
    for case in ["spin", "impact_50", "steel_drop"]:
        for r in ["euler", "scalar", "pcdm", "leapfrog"]:
            j.append((f"guard_{case}_{r}", ["run", f"{SC}/stress/{case}.toml", "--rotator", r, "--allow-large-dt"], [0, 3]))
    j.append(("stress", ["stress", "--dir", f"{SC}/stress"], [0]))
    j.append(("compare_tc3", ["compare", f"{SC}/torque_sphere.toml", "--rotators", "all"], [0]))
    j.append(("compare_tc4", ["compare", f"{SC}/torque_fibre.toml", "--rotators", "all"], [0]))
    j.append(("converge_tc3", ["converge", f"{SC}/torque_sphere.toml", "--rotators", "all"], [0]))
    j.append(("converge_tc4", ["converge", f"{SC}/torque_fibre.toml", "--rotators", "all"], [0]))
    return j


def where(key, value):
    """A scenario path relative to the checkout, so that two clones compare."""
    if key == "scenario" and isinstance(value, str) and "scenarios/" in value:
        return value[value.index("scenarios/"):]
    return value


def normalised(path):
    """File bytes with the machine-dependent parts removed."""
    name = os.path.basename(path)
    data = open(path, "rb").read()
    if name.endswith(".json"):
        obj = json.loads(data)

        def strip(o):
            if isinstance(o, dict):
                return {k: where(k, strip(v)) for k, v in o.items() if k not in TIMING}
            if isinstance(o, list):
                return [strip(v) for v in o]
            return o

        return json.dumps(strip(obj), sort_keys=False).encode()
    if name.endswith(".csv") or name.endswith(".md"):
        text = data.decode()
        if name.endswith(".csv"):
            rows = list(csv.reader(io.StringIO(text)))
            if rows:
                keep = [i for i, h in enumerate(rows[0]) if h not in TIMING]
                out = io.StringIO()
                w = csv.writer(out, lineterminator="\n")
                for r in rows:
                    w.writerow([r[i] for i in keep if i < len(r)])
                return out.getvalue().encode()
        # Markdown tables of the studies carry no timings except the stress
        # tables' run time line, dropped here.
        return "\n".join(l for l in text.splitlines() if "wall" not in l and " s on " not in l).encode()
    return data


def record(binary, out):
    os.makedirs(out, exist_ok=True)
    binary = os.path.abspath(binary)
    manifest = []
    for name, args, ok in jobs():
        # A fresh folder per job (also for binaries without --force).
        shutil.rmtree(os.path.join(out, name), ignore_errors=True)
        cmd = [binary] + args + ["--out", name, "-q"]  # relative: messages name the same path
        if args[0] == "run" and "--allow-large-dt" not in args:
            cmd.append("--allow-large-dt")
        p = subprocess.run(cmd, capture_output=True, text=True, cwd=out)
        manifest.append(f"{name} exit {p.returncode} stderr {hashlib.sha256(p.stderr.encode()).hexdigest()[:16]}")
        if p.returncode not in ok:
            print(f"{name}: exit {p.returncode}: {p.stderr.strip()}", file=sys.stderr)
    # Resume: a checkpointed run continued to the end writes what one run writes.
    shutil.rmtree(os.path.join(out, "resume"), ignore_errors=True)
    subprocess.run([binary, "run", f"{SC}/nine_fibres.toml", "--t-end", "0.05", "--checkpoint-every", "200000",
                    "--out", "resume", "-q"], check=True, cwd=out)
    subprocess.run([binary, "run", "--resume", "resume/checkpoint.json", "--t-end", "0.1", "-q"],
                   check=True, cwd=out)
    for dirpath, _, files in sorted(os.walk(out)):
        for f in sorted(files):
            if not (f.endswith(".csv") or f.endswith(".json") or f.endswith(".md") or f.endswith(".svg")):
                continue
            if f in ("checkpoint.json", "manifest.txt") or f.startswith("work_precision"):
                continue
            p = os.path.join(dirpath, f)
            rel = os.path.relpath(p, out)
            manifest.append(f"{rel} {hashlib.sha256(normalised(p)).hexdigest()}")
    with open(os.path.join(out, "manifest.txt"), "w") as m:
        m.write("\n".join(manifest) + "\n")
    print(f"{len(manifest)} entries in {out}/manifest.txt")


def compare(a, b):
    la = open(os.path.join(a, "manifest.txt")).read().splitlines()
    lb = open(os.path.join(b, "manifest.txt")).read().splitlines()
    da, db = dict(l.rsplit(" ", 1) if " exit " not in l else (l, "") for l in la), None
    db = dict(l.rsplit(" ", 1) if " exit " not in l else (l, "") for l in lb)
    bad = 0
    for k in sorted(set(da) | set(db)):
        if da.get(k) != db.get(k):
            print(f"differs: {k}: {da.get(k)} vs {db.get(k)}")
            bad += 1
    print(f"{len(da)} vs {len(db)} entries, {bad} differ")
    return 1 if bad else 0


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "record":
        record(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 4 and sys.argv[1] == "compare":
        sys.exit(compare(sys.argv[2], sys.argv[3]))
    else:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
