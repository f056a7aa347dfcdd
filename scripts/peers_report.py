#!/usr/bin/env python3
"""Rows and report of the peer comparison (scripts/peers.sh calls it).

    peers_report.py row CSV ROUND CODE N JOBDIR RC LOAD1 LOAD5 LOAD15
        Read one finished job's outputs in JOBDIR and append its row to CSV
        (written whole and flushed, so an interrupted run keeps every row so
        far). A job that failed gets a row too, with its status and reason.
    peers_report.py report CSV OUTDIR
        Medians per code and process/thread count, the ratios of fibresim to
        each peer, parallel efficiency and memory per body: printed, and
        written to OUTDIR/summary.md; OUTDIR/medians.csv (code, count, median
        rate; one series per code) is the figure's table.

CODE is fibresim, liggghts, lammps, spheres (fibresim on the 10^4-sphere bed)
or chute. Rates are bodies x steps / loop time of the timed steps: fibre-steps/s
for the fibre bed, sphere-steps/s for the sphere bed, atom-steps/s for the chute.
The peers' loop time is the last "Loop time" line of their log (the timed run,
after the warm-up run); fibresim's is summary.json's wall_s (the step loop,
set-up excluded). Peak RSS is /usr/bin/time -v's maximum resident set size,
summed over the ranks of an MPI job. Standard library only.
"""

import csv
import json
import os
import re
import statistics
import sys

LABEL = {
    "liggghts": "LIGGGHTS multisphere",
    "lammps": "LAMMPS rigid/small",
    "fibresim": "fibresim",
    "spheres": "fibresim spheres",
    "chute": "LAMMPS chute",
}
# Runs that are not the fibre bed: beside each other, not in the fibre figure.
SPHERE_CODES = ("spheres", "chute")
WHAT = {"chute": "M atom-steps/s", "spheres": "M sphere-steps/s"}
PEERS = ("liggghts", "lammps")
SPHERES_PER_FIBRE = 4
COLUMNS = [
    "round", "code", "label", "n", "unit", "status", "steps", "bodies", "loop_s", "rate_M",
    "peak_rss_kB", "rss_ranks_kB", "load1", "load5", "load15", "contacts_end", "job_dir",
]
LOOP = re.compile(r"^Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")
RSS = re.compile(r"Maximum resident set size \(kbytes\): (\d+)")


def unit(code):
    return "p" if code in PEERS or code == "chute" else "t"


def read(path):
    try:
        with open(path, errors="replace") as f:
            return f.read()
    except OSError:
        return None


def peak_rss(jobdir):
    """Per-rank (or the one process's) peak RSS from the time -v files."""
    files = sorted(f for f in os.listdir(jobdir) if f.startswith("time.rank")) or ["time.txt"]
    out = []
    for f in files:
        m = RSS.search(read(os.path.join(jobdir, f)) or "")
        if m:
            out.append(int(m.group(1)))
    return out


def last_error(text):
    lines = [l.strip() for l in (text or "").splitlines() if l.strip()]
    errs = [l for l in lines if "ERROR" in l or l.startswith("error") or "panicked" in l]
    return (errs or lines or ["no output"])[-1][:200]


def peer_result(jobdir, code):
    """(steps, bodies, loop_s, contacts_end) from a LIGGGHTS/LAMMPS log, or a reason."""
    log = read(os.path.join(jobdir, "log.txt"))
    if log is None:
        return "no log written: " + last_error(read(os.path.join(jobdir, "stdout.txt")))
    loops = [m for m in map(LOOP.match, log.splitlines()) if m]
    if code == "chute":
        if not loops:
            return "no Loop time in the log: " + last_error(log)
        m = loops[-1]
        return int(m.group(3)), int(m.group(4)), float(m.group(1)), ""
    done = re.search(r"TIMED_DONE contacts\(sum over spheres\) ([0-9.eE+-]+)", log)
    if not done or not loops:
        return "the timed run did not finish: " + last_error(log)
    m = loops[-1]
    atoms = int(m.group(4))
    # contact/atom counts each sphere-sphere contact at both spheres.
    return int(m.group(3)), atoms // SPHERES_PER_FIBRE, float(m.group(1)), round(float(done.group(1)) / 2)


def fibresim_result(jobdir):
    text = read(os.path.join(jobdir, "out", "summary.json"))
    if text is None:
        return "no summary.json: " + last_error(read(os.path.join(jobdir, "stdout.txt")))
    s = json.loads(text)
    if s.get("stopped"):
        return f"stopped: {s['stopped']}"
    contacts = ""
    energy = read(os.path.join(jobdir, "out", "energy.csv"))
    if energy:
        rows = list(csv.DictReader(energy.splitlines()))
        if rows and "contacts" in rows[-1]:
            contacts = rows[-1]["contacts"]
    return int(s["steps"]), int(s["bodies"]), float(s["wall_s"]), contacts


def row(args):
    csv_path, rnd, code, n, jobdir, rc, l1, l5, l15 = args
    res = fibresim_result(jobdir) if code in ("fibresim", "spheres") else peer_result(jobdir, code)
    ranks = peak_rss(jobdir)
    r = dict.fromkeys(COLUMNS, "")
    r.update(round=rnd, code=code, label=LABEL[code], n=n, unit=unit(code), load1=l1, load5=l5, load15=l15)
    r["job_dir"] = os.path.relpath(jobdir, os.path.dirname(os.path.abspath(csv_path)))
    r["peak_rss_kB"] = sum(ranks) if ranks else ""
    r["rss_ranks_kB"] = " ".join(map(str, ranks))
    if rc != "0" and not isinstance(res, str):
        res = f"exit status {rc}"
    if isinstance(res, str):
        r["status"] = f"failed (exit {rc}): {res}" if rc != "0" else f"failed: {res}"
    else:
        steps, bodies, loop_s, contacts = res
        r.update(status="ok", steps=steps, bodies=bodies, loop_s=f"{loop_s:.6g}", contacts_end=contacts)
        r["rate_M"] = f"{bodies * steps / loop_s / 1e6:.4f}"
    new = not os.path.exists(csv_path)
    with open(csv_path, "a", newline="") as f:
        w = csv.DictWriter(f, COLUMNS)
        if new:
            w.writeheader()
        w.writerow(r)
        f.flush()
        os.fsync(f.fileno())
    what = WHAT.get(code, "M fibre-steps/s")
    if r["status"] == "ok":
        print(f"  {r['label']} {n}{unit(code)}: {r['rate_M']} {what}, peak RSS {r['peak_rss_kB']} kB [load {l1}]")
    else:
        print(f"  {r['label']} {n}{unit(code)}: {r['status']}", file=sys.stderr)


def fmt(x, d=3):
    return f"{x:.{d}f}"


def report(args):
    csv_path, outdir = args
    if not os.path.exists(csv_path):
        print(f"no job wrote a row ({csv_path} is missing)", file=sys.stderr)
        return 1
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    ok = [r for r in rows if r["status"] == "ok"]
    failed = [r for r in rows if r["status"] != "ok"]
    groups = {}
    for r in ok:
        groups.setdefault((r["code"], int(r["n"])), []).append(r)
    order = ["liggghts", "lammps", "fibresim", "spheres", "chute"]
    keys = sorted(groups, key=lambda k: (k[0] in SPHERE_CODES, k[1], order.index(k[0])))
    med = {k: statistics.median(float(r["rate_M"]) for r in groups[k]) for k in keys}
    meta = read(os.path.join(outdir, "meta.txt")) or ""
    loads = [float(r["load1"]) for r in rows if r["load1"]]
    lines = []
    lines.append("| code | n | M bodies x steps/s, median | min - max | jobs | load (1 min) before, median | peak RSS kB, median | kB per body | contacts per body at the end |")
    lines.append("|---|---|---|---|---|---|---|---|---|")
    for k in keys:
        g = groups[k]
        rates = [float(r["rate_M"]) for r in g]
        rss = [int(r["peak_rss_kB"]) for r in g if r["peak_rss_kB"]]
        rss_med = statistics.median(rss) if rss else None
        bodies = int(g[0]["bodies"])
        contacts = [float(r["contacts_end"]) for r in g if r["contacts_end"]]
        n_fail = sum(1 for r in failed if (r["code"], int(r["n"])) == k)
        lines.append(
            f"| {LABEL[k[0]]} | {k[1]}{unit(k[0])} | {fmt(med[k])} | {fmt(min(rates))} - {fmt(max(rates))} | "
            f"{len(g)}{f' (+{n_fail} failed)' if n_fail else ''} | "
            f"{fmt(statistics.median(float(r['load1']) for r in g), 2)} | "
            f"{int(rss_med) if rss_med else '-'} | {fmt(rss_med / bodies, 2) if rss_med else '-'} | "
            f"{fmt(statistics.median(contacts) / bodies, 2) if contacts else '-'} |"
        )
    notes = []
    ns = sorted({n for c, n in keys if c not in SPHERE_CODES})
    for peer in PEERS:
        parts = [
            f"{n}: {fmt(med[('fibresim', n)] / med[(peer, n)], 2)}"
            for n in ns
            if ("fibresim", n) in med and (peer, n) in med
        ]
        if parts:
            notes.append(f"- fibresim / {LABEL[peer]} (ratio of medians, same n): " + ", ".join(parts))
    if ("chute", 1) in med:
        parts = [f"{n}t: {fmt(med[('spheres', n)] / med[('chute', 1)], 2)}" for n in sorted({n for c, n in keys if c == "spheres"})]
        if parts:
            notes.append(
                "- fibresim spheres (Hertz, frictionless) / LAMMPS chute on one core (gran/hooke/history, 32 000 atoms), "
                "bodies x steps/s: " + ", ".join(parts)
            )
    for code in ("fibresim", "spheres") + PEERS:
        if (code, 1) not in med:
            continue
        parts = [f"{n}{unit(code)}: {fmt(100 * med[(code, n)] / (n * med[(code, 1)]), 0)} %" for n in ns if n > 1 and (code, n) in med]
        if parts:
            notes.append(f"- parallel efficiency of {LABEL[code]} (median(n) / (n x median(1))): " + ", ".join(parts))
    if loads:
        notes.append(f"- load average (1 min) before the jobs: {min(loads):.2f} - {max(loads):.2f}, median {statistics.median(loads):.2f}")
    sizes = {LABEL[c]: int(groups[(c, n)][0]["bodies"]) for c, n in keys if c not in SPHERE_CODES}
    if len(set(sizes.values())) > 1:
        notes.append(f"- NOT THE SAME BED SIZE, the ratios compare unlike runs: {sizes}")
    for r in failed:
        notes.append(f"- round {r['round']}, {r['label']} {r['n']}{r['unit']}: {r['status']}")
    text = "\n".join(lines + [""] + notes) + "\n"
    with open(os.path.join(outdir, "summary.md"), "w") as f:
        f.write(meta + ("\n" if meta else "") + text)
    print(meta + ("\n" if meta else "") + text, end="")
    with open(os.path.join(outdir, "medians.csv"), "w") as f:
        f.write("series,threads,M_fibre_steps_per_s\n")
        f.writelines(f"{LABEL[c]},{n},{med[(c, n)]:.4f}\n" for c, n in keys if c not in SPHERE_CODES)
    return 1 if failed else 0


def main():
    if len(sys.argv) == 11 and sys.argv[1] == "row":
        row(sys.argv[2:])
    elif len(sys.argv) == 4 and sys.argv[1] == "report":
        sys.exit(report(sys.argv[2:]))
    else:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        sys.exit(2)


if __name__ == "__main__":
    main()
