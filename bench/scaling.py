#!/usr/bin/python3
"""Scaling benchmark (issue 30): one coordinator feeding N emulated workers.

For N workers (default 16, 64, 256, 1024), evaluation times (50 ms, 500 ms, 5 s; constant
or lognormal) and several studies at once sharing the pool (1, 4, 16), runs
gaitforge-swarm (bench/swarm: N emulated workers in one process, one gRPC connection
each, the real worker's protocol code) against a fresh coordinator and prints a table:
dispatch efficiency (busy worker-time / (N x wall)), the coordinator's CPU per evaluation
and the swarm's own CPU, lease latency and generation turnaround (p50/p99), SQLite commit
latency (from the coordinator's metrics), heartbeat and watch-stream traffic, and the
coordinator's peak memory. Each study is sized to ~2 s of work per worker and generation
(--work: other amounts) and ~45 s in all. Draws efficiency against N as a figure
(matplotlib, python3-matplotlib).

Run from the repository root after ./scripts/build.sh, with the CPU to itself:
    /usr/bin/python3 bench/scaling.py [--workers 256 1024] [--evals 0.05 0.5]
        [--studies 1 4] [--dist constant|lognormal] [--goal] [--json FILE] [--figure FILE]
--goal runs only the issue's two goal cells (500 ms at 1024 workers, 50 ms at 256).
--anchor also runs the issue's anchor, Optuna's RDB storage on SQLite with K = N processes
(bench/anchors/optuna_dispatch.py), for every one-study cell with N up to --anchor-max
(64: more Python processes do not fit 2 cores), and prints both side by side.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "scale"))
import swarm_procs  # noqa: E402

COLUMNS = [("N", "workers", "%d"), ("eval", "eval", "%s"), ("st", "studies", "%d"),
           ("W s", "work_s", "%g"),
           ("eff", "efficiency", "%.3f"), ("wall s", "wall_s", "%.1f"),
           ("evals", "results_accepted", "%d"), ("coord us/ev", "coordinator_cpu_us_per_eval", "%.0f"),
           ("swarm cpu s", "swarm_cpu_s", "%.1f"), ("lease p50", "lease_ms_p50", "%.1f"),
           ("lease p99", "lease_ms_p99", "%.0f"), ("turn p50", "turnaround_ms_p50", "%.1f"),
           ("turn p99", "turnaround_ms_p99", "%.0f"), ("disp p50", "dispatch_ms_p50", "%.0f"), ("commit p50", "commit_ms_p50", "%.2f"),
           ("commit p99", "commit_ms_p99", "%.1f"), ("hb/s", "heartbeat_per_s", "%.0f"),
           ("watch msg", "watch_messages", "%d"), ("peak MiB", "coordinator_peak_mib", "%.0f")]


def flatten(r):
    r = dict(r)
    r["heartbeat_per_s"] = r["heartbeat"]["per_second"]
    r["watch_messages"] = r["watch"]["messages"]
    return r


def fmt(v, f):
    if v is None:
        return "-"
    try:
        return f % v
    except TypeError:
        return str(v)


def table(rows):
    head = [c[0] for c in COLUMNS]
    body = [[fmt(flatten(r).get(k), f) for _, k, f in COLUMNS] for r in rows]
    widths = [max(len(h), *(len(b[i]) for b in body)) if body else len(h) for i, h in enumerate(head)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(head, widths))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(b, widths)) for b in body]
    return "\n".join(lines)


def figure(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    series = {}
    for r in rows:
        key = (r["eval"], r["studies"], r.get("work_s", 2.0))
        series.setdefault(key, []).append((r["workers"], r["efficiency"]))
    for (ev, st, work), pts in sorted(series.items()):
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o",
                label="%s, %d stud%s, %g s/generation" % (ev, st, "y" if st == 1 else "ies", work))
    ax.axhline(0.95, color="grey", ls=":", lw=1)
    ax.axhline(0.90, color="grey", ls="--", lw=1)
    ax.set_xscale("log", base=2)
    ax.set_xlabel("emulated workers N (one coordinator, 2 cores)")
    ax.set_ylabel("dispatch efficiency")
    ax.set_ylim(0, 1.02)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)


def anchor(n, ev, seconds):
    """Optuna's figures for K = n processes and ev-second trials (bench/anchors)."""
    script = os.path.join(ROOT, "bench", "anchors", "optuna_dispatch.py")
    out = subprocess.run([sys.executable, script, "--processes", str(n), "--eval", str(ev),
                          "--seconds", str(seconds), "--json"],
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def side_by_side(rows, anchors):
    lines = ["%5s  %6s  %14s  %12s  %14s  %12s  %s" % (
        "N", "eval", "gaitforge eff", "results/s", "optuna eff", "trials/s", "optuna ms/trial")]
    for r in rows:
        a = anchors.get((r["workers"], r["eval"]))
        if a is None:
            continue
        lines.append("%5d  %6s  %14.3f  %12.0f  %14.3f  %12.1f  %.0f" % (
            r["workers"], r["eval"].split(":")[1], r["efficiency"],
            r["results_accepted"] / r["wall_s"], a["efficiency"], a["trials"] / a["wall_s"],
            a["overhead_ms_per_trial"]))
    return "\n".join(lines)


def run_anchors(args, rows):
    anchors = {}
    for r in rows:
        if r["studies"] == 1 and r["workers"] <= args.anchor_max and args.dist == "constant":
            ev = float(r["eval"].split(":")[1])
            anchors[(r["workers"], r["eval"])] = anchor(r["workers"], ev, args.anchor_seconds)
    print("\nAnchor, same machine: Optuna's RDB storage, K = N processes on one SQLite file\n"
          + side_by_side(rows, anchors), flush=True)
    return list(anchors.values())


def cells(args):
    if args.goal:
        return [(1024, 0.5, 1, w) for w in args.work] + [(256, 0.05, 1, w) for w in args.work]
    return [(n, e, s, w) for w in args.work for s in args.studies for e in args.evals
            for n in args.workers]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin-dir", default=os.path.join(ROOT, "build", "bin"))
    ap.add_argument("--workers", type=int, nargs="+", default=[16, 64, 256, 1024])
    ap.add_argument("--evals", type=float, nargs="+", default=[0.05, 0.5, 5.0])
    ap.add_argument("--studies", type=int, nargs="+", default=[1])
    ap.add_argument("--dist", choices=["constant", "lognormal"], default="constant")
    ap.add_argument("--sigma", type=float, default=1.0, help="lognormal's sigma")
    ap.add_argument("--seconds", type=float, default=45, help="target length of a cell")
    ap.add_argument("--work", type=float, nargs="+", default=[2.0],
                    help="seconds of work per worker and generation (the study's size)")
    ap.add_argument("--goal", action="store_true")
    ap.add_argument("--json", help="write every cell's figures here")
    ap.add_argument("--figure", help="efficiency against N (SVG or PNG)")
    ap.add_argument("--coordinator-flag", action="append", default=[])
    ap.add_argument("--anchor", action="store_true", help="also run Optuna (K = N processes)")
    ap.add_argument("--anchor-max", type=int, default=64, help="largest N the anchor runs")
    ap.add_argument("--anchor-seconds", type=float, default=20)
    args = ap.parse_args()
    rows = []
    for n, ev, st, work in cells(args):
        dist = "constant:%g" % ev if args.dist == "constant" else "lognormal:%g:%g" % (ev, args.sigma)
        with tempfile.TemporaryDirectory(prefix="gf-scale-") as d:
            r = swarm_procs.cell(args.bin_dir, d, n, dist, ev, st, args.seconds, args.coordinator_flag,
                                 work_s=work)
        r["work_s"] = work
        rows.append(r)
        print(table([r]).splitlines()[-1] if len(rows) > 1 else table([r]), flush=True)
    print("\n" + table(rows))
    anchors = run_anchors(args, rows) if args.anchor else []
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"cells": rows, "anchors": anchors}, f, indent=1)
    if args.figure:
        figure(rows, args.figure)


if __name__ == "__main__":
    main()
