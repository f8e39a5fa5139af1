#!/usr/bin/python3
"""Calibration benchmark (issue 7): the wall time of a calibration of 5 parameters on 3
recordings with 2 workers, and the parameter recovery error.

Recordings are made by gaitforge-sim with known parameters (the truth), the study starts
from robots/caterpillar/robot.yaml's values, CMA-ES fits all five; the script prints the fit beside the
truth. Run from the repository root after ./scripts/build.sh:
    /usr/bin/python3 bench/calibration.py [--workers 2] [--evaluations 1200] [--json]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "bin")

GAITS = [
    "0.066346016790415963,0.92228296711382263,0.99884798501519678,0.91495911032617716,"
    "0.013764065590901597,0.027395295966066602,0.32783986902260742,0.36116692841980558,"
    "0.1062628441354091,0.40778045503790639,0.36272688662110386,0.30411357539492101,"
    "0.35444634996911673",
    "0.05,0.2,0.35,0.3,0.45,0.6,0.45,0.6,0.75,0.7,0.85,0.0,0.5",
    "0.0,0.1,0.2,0.5,0.6,0.7,0.3,0.4,0.5,0.8,0.9,0.0,0.7",
]
# name: (truth, nominal in robots/caterpillar/robot.yaml, lo, hi)
PARAMS = {
    "actuators.force_n": (9.6, 8.8, 7.0, 11.0),
    "scale.link_stiffness": (1.15, 1.0, 0.7, 1.4),
    "links.axial_damping_ratio": (0.8, 1.0, 0.4, 1.6),
    "scale.mass": (1.1, 1.0, 0.8, 1.25),
    "actuators.return_spring_n_per_m": (70.0, 63.0, 40.0, 90.0),
}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--evaluations", type=int, default=1200)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    truth = ",".join(f"{k}={v[0]}" for k, v in PARAMS.items())
    with tempfile.TemporaryDirectory(prefix="gf-calib-") as d:
        for i, g in enumerate(GAITS):
            subprocess.run([os.path.join(BIN, "gaitforge-sim"), "trajectory", "--robot", "caterpillar", "--genes", g,
                            "--cycles", "10", "--set", truth, "--out", f"{d}/r{i}.csv"],
                           check=True, capture_output=True)
        bounds = "\n".join(f"  - {{name: {k}, lo: {v[2]}, hi: {v[3]}}}" for k, v in PARAMS.items())
        mean0 = ", ".join(str(v[1]) for v in PARAMS.values())
        with open(f"{d}/calib.yaml", "w") as f:
            f.write(f"""name: calib5
seed: 3
engine: cmaes
population: 10
generations: 1000
objective:
  name: caterpillar.calibration
  options: {{error: shape}}
  recordings: [r0.csv, r1.csv, r2.csv]
bounds:
{bounds}
cmaes:
  mean0: [{mean0}]
  sigma0: 0.25
  restarts: none
  max_evaluations: {a.evaluations}
""")
        t0 = time.monotonic()
        subprocess.run([os.path.join(BIN, "gaitforge"), "local", "calib.yaml", "--workers",
                        str(a.workers), "--json"], cwd=d, check=True, capture_output=True)
        wall = time.monotonic() - t0
        studies = json.loads(subprocess.run([os.path.join(BIN, "gaitforge"), "list", "--json"],
                                            cwd=d, check=True, capture_output=True,
                                            text=True).stdout)["studies"]
        sid = studies[0]["study_id"]
        hof = json.loads(subprocess.run([os.path.join(BIN, "gaitforge"), "hof", sid, "--json"],
                                        cwd=d, check=True, capture_output=True, text=True).stdout)
        best = hof["entries"][0]["individual"]
        spread = hof.get("spread", [])
        rows = []
        for i, (name, (tv, nominal, lo, hi)) in enumerate(PARAMS.items()):
            fit = best["genes"][i]
            rows.append({"name": name, "truth": tv, "start": nominal, "fit": fit,
                         "spread": spread[i] if i < len(spread) else None,
                         "relative_error": abs(fit - tv) / abs(tv)})
        out = {"wall_seconds": wall, "evaluations": int(studies[0]["evaluations"]),
               "workers": a.workers, "error": -best["evaluation"]["fitness"], "parameters": rows}
    if a.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"calibration of {len(PARAMS)} parameters on {len(GAITS)} recordings, "
          f"{a.workers} workers: {wall:.1f} s wall, {out['evaluations']} evaluations, "
          f"final error {1000 * out['error']:.3f} mm")
    print(f"  {'parameter':34s} {'truth':>9s} {'start':>9s} {'fit':>10s} {'sd':>9s} {'rel.err':>8s}")
    for r in rows:
        sd = f"{r['spread']:.3g}" if r["spread"] is not None else "-"
        print(f"  {r['name']:34s} {r['truth']:9.4g} {r['start']:9.4g} {r['fit']:10.5g} {sd:>9s} "
              f"{100 * r['relative_error']:7.2f}%")
    return 0


if __name__ == "__main__":
    sys.exit(main())
