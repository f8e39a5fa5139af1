#!/usr/bin/python3
"""Foundation benchmark (issue 2): gaitforge beside its anchors, in one run.

  * durable evaluations per second with the analytic objective, 1, 2 and 8 workers,
    every result committed to SQLite (synchronous=FULL), and the wall time of the
    150 x 200 study, against Optuna on SQLite (trials per second) on the same objective;
  * the GA's own overhead per generation of 200, against DEAP's.

Run from the repository root after ./scripts/build.sh:
    /usr/bin/python3 bench/foundation.py [--workers 1 2 8] [--json]
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
PY = "/usr/bin/python3"


def run_json(cmd, cwd=None):
    out = subprocess.run(cmd, cwd=cwd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def gaitforge_study(workers, spec):
    with tempfile.TemporaryDirectory(prefix="gf-bench-") as d:
        t0 = time.monotonic()
        subprocess.run([os.path.join(BIN, "gaitforge"), "local", spec, "--workers", str(workers),
                        "--json"], cwd=d, check=True, capture_output=True, text=True)
        wall = time.monotonic() - t0
        studies = run_json([os.path.join(BIN, "gaitforge"), "list", "--json"], cwd=d)["studies"]
        s = studies[0]
        study_s = (int(s["updated_unix_ms"]) - int(s["created_unix_ms"])) / 1000.0
        evals = int(s["evaluations"])
        return {"workers": workers, "evaluations": evals, "study_seconds": study_s,
                "wall_seconds": wall, "evals_per_second": evals / study_s}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2, 8])
    ap.add_argument("--spec", default=os.path.join(ROOT, "examples", "analytic-ga.yaml"))
    ap.add_argument("--optuna-trials", type=int, default=300)
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    a = ap.parse_args()

    res = {"gaitforge": [gaitforge_study(w, a.spec) for w in a.workers]}
    res["optuna"] = [run_json([PY, os.path.join(ROOT, "bench/anchors/optuna_sqlite.py"),
                               "--trials", str(a.optuna_trials), "--processes", str(p), "--json"])
                     for p in (1, 2)]
    res["ga_overhead"] = run_json([os.path.join(BIN, "gaitforge-bench-ga"), "2000"])
    res["deap_overhead"] = run_json([PY, os.path.join(ROOT, "bench/anchors/deap_ga_overhead.py"),
                                     "--json"])
    if a.json:
        print(json.dumps(res, indent=2))
        return
    print("Durable evaluations per second, analytic.rastrigin, 150 x 200 GA (synchronous=FULL)")
    print(f"  {'system':28s} {'evals/s':>10s} {'study s':>9s} {'wall s':>8s}")
    for r in res["gaitforge"]:
        print(f"  gaitforge, {r['workers']} worker(s){'':9s} {r['evals_per_second']:10.0f} "
              f"{r['study_seconds']:9.2f} {r['wall_seconds']:8.2f}")
    for r in res["optuna"]:
        print(f"  optuna sqlite, {r.get('processes', 1)} process(es){'':4s} "
              f"{r['trials_per_second']:10.1f} {'':9s} {r['seconds']:8.2f}  ({r['trials']} trials)")
    print("Optimiser overhead per generation of 200 (13 genes), evaluation excluded")
    print(f"  gaitforge GA   {res['ga_overhead']['ms_per_generation']:.4f} ms")
    print(f"  DEAP GA        {res['deap_overhead']['ms_per_generation']:.4f} ms")


if __name__ == "__main__":
    sys.exit(main())
