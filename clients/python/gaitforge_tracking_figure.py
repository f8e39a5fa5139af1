#!/usr/bin/python3
"""Tracking figure: the path and the tip under each controller, and each one's error over time.

Reads the per-tick CSVs `gaitforge-sim track --out` writes (t, <marker>.<axis>.ref,
<marker>.<axis>, ...): the left panel shows the reference and every run's marker on the first
two steered axes, the right panel each run's distance from the reference against time (the
lead-in, t < 0, left out).

Usage: gaitforge_tracking_figure.py --run LABEL=TICKS.csv [--run ...] --out FILE.svg
       [--title TEXT]
Run it under /usr/bin/python3 (Debian's python3-matplotlib).
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"gaitforge_tracking_figure: {path}: no ticks")
    refs = [c[:-4] for c in rows[0] if c.endswith(".ref")]
    if not refs:
        sys.exit(f"gaitforge_tracking_figure: {path}: no <marker>.<axis>.ref column (not a track --out CSV)")
    rows = [r for r in rows if float(r["t"]) >= 0]
    t = [float(r["t"]) for r in rows]
    ref = {c: [float(r[c + ".ref"]) for r in rows] for c in refs}
    pos = {c: [float(r[c]) for r in rows] for c in refs}
    err = [math.sqrt(sum((ref[c][i] - pos[c][i]) ** 2 for c in refs)) for i in range(len(t))]
    return refs, t, ref, pos, err


def draw(runs, out, title="Tracking"):
    """runs: (label, ticks CSV) pairs; draws the figure to `out` and returns its path."""
    fig, (path_ax, err_ax) = plt.subplots(1, 2, figsize=(11, 4.6))
    for k, (label, file) in enumerate(runs):
        refs, t, ref, pos, err = read(file)
        a, b = refs[0], refs[1] if len(refs) > 1 else refs[0]
        if k == 0:
            path_ax.plot([1000 * v for v in ref[a]], [1000 * v for v in ref[b]], "k--", lw=2, label="reference")
        path_ax.plot([1000 * v for v in pos[a]], [1000 * v for v in pos[b]], lw=1.2,
                     label=f"{label} (max {1000 * max(err):.1f} mm)")
        err_ax.plot(t, [1000 * e for e in err], lw=1.2, label=label)
    path_ax.set_xlabel(f"{a} (mm)")
    path_ax.set_ylabel(f"{b} (mm)")
    path_ax.set_aspect("equal", adjustable="datalim")
    path_ax.legend(fontsize=8)
    path_ax.set_title("path")
    err_ax.set_xlabel("t (s)")
    err_ax.set_ylabel("distance from the reference (mm)")
    err_ax.set_yscale("log")
    err_ax.legend(fontsize=8)
    err_ax.set_title("error")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--run", action="append", required=True, help="LABEL=TICKS.csv")
    p.add_argument("--out", required=True)
    p.add_argument("--title", default="Tracking")
    args = p.parse_args()
    print(draw([run.partition("=")[::2] for run in args.run], args.out, args.title))


if __name__ == "__main__":
    main()
