#!/usr/bin/python3
"""The caterpillar's independent MuJoCo build (bench/independent/caterpillar_mujoco.cc,
binary gaitforge-bench-caterpillar-mujoco) from Python, with rig2d.py's interface: travel
of a batch of gaits, and recordings.

Effects (one dict per run) in the build's own forms: hose_n, hose_n_per_m (a pull straight
back on the rear lump, growing with travel from rest, or from the markers' mean x
hose_anchor_x_m), drag_n_s_per_m (linear, over all lumps),
actuator_lag_s, slope_rad, force_scale; and the build's own structure varied (nulls of another
build): ground_mu (default 2), contact_time_s (default 0.002). Runs are split over `jobs` processes.
"""
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
BIN = os.environ.get("GAITFORGE_BIN", os.path.join(HERE, "..", "..", "build", "bin"))
TOOL = "gaitforge-bench-caterpillar-mujoco"


def _line(genes, effects):
    return " ".join([repr(float(g)) for g in genes] + [f"{k}={float(v)!r}" for k, v in effects.items()])


def _run(lines, settle, cycles, extra=()):
    cmd = [os.path.join(BIN, TOOL), "--settle", str(settle), "--cycles", str(cycles), *extra]
    r = subprocess.run(cmd, input="\n".join(lines) + "\n", capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{TOOL} failed ({r.returncode}): {r.stderr.strip()}")
    return [float(l.split()[0]) for l in r.stdout.splitlines() if l.strip()]


def travel(genes, effects, settle=1, cycles=5, jobs=2):
    """Forward travel per cycle (m) of the markers' mean x for run i (genes[i], effects[i]);
    NaN for a run that diverged."""
    lines = [_line(g, e) for g, e in zip(genes, effects)]
    chunks = [lines[k::jobs] for k in range(jobs)]
    with ThreadPoolExecutor(jobs) as pool:
        parts = list(pool.map(lambda c: _run(c, settle, cycles) if c else [], chunks))
    out = np.empty(len(lines))
    for k in range(jobs):
        out[k::jobs] = parts[k]
    return out


def record(path, genes, effects, settle=2, cycles=10, rate_hz=100):
    """One run's markers as a recording CSV at `path` (docs/recording-format.md), from the
    end of the settle cycles; returns its travel per cycle."""
    return _run([_line(genes, effects)], settle, cycles, ("--record", path, "--rate", str(rate_hz)))[0]
