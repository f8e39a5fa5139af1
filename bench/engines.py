#!/usr/bin/python3
"""Engine benchmark (issue 4): gaitforge's CMA-ES beside DEAP's, in one table.

Runs build/bin/gaitforge-bench-cmaes and bench/anchors/deap_cma.py with the same seeds
and setup (x0 uniform in [-5, 5)^d from the same keyed stream, sigma0 = 2, default
lambda; see bench/cmaes_bench.cc) and prints evaluations to f < 1e-8 (median over the
solved seeds), seeds solved, and the optimiser's own overhead per generation.

Run from the repository root after building gaitforge-bench-cmaes:
    /usr/bin/python3 bench/engines.py [--seeds 15] [--json]
"""
import argparse
import json
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PY = "/usr/bin/python3"


def run_json(cmd):
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def fmt(v):
    return "-" if v is None or v < 0 else f"{v:.0f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", type=int, default=61,
                    help="seeds per function (61: a median steady to about 1%%; the issue quotes 15)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    a = ap.parse_args()
    ours = run_json([os.path.join(ROOT, "build", "bin", "gaitforge-bench-cmaes"),
                     "--seeds", str(a.seeds), "--json"])
    deap = run_json([PY, os.path.join(ROOT, "bench", "anchors", "deap_cma.py"),
                     "--seeds", str(a.seeds), "--json"])
    if a.json:
        print(json.dumps({"gaitforge": ours, "deap": deap}, indent=2))
        return
    deap_rows = {(r["function"], r["dim"]): r for r in deap["rows"]}
    n = a.seeds
    print(f"Evaluations to f < 1e-8 (median over solved seeds), {n} seeds, sigma0 = 2,"
          " x0 ~ U[-5, 5)^d, default lambda")
    print(f"{'function':<11} {'d':>3} | {'gaitforge':>9} {'solved':>7} {'restarts':>8} |"
          f" {'DEAP':>7} {'solved':>7} | {'ratio':>5}")
    for r in ours["rows"]:
        d = deap_rows.get((r["function"], r["dim"]))
        ratio = ""
        if d and d["median_evals"] > 0 and r["median_evals"] > 0:
            ratio = f"{r['median_evals'] / d['median_evals']:.2f}"
        print(f"{r['function']:<11} {r['dim']:>3} | {fmt(r['median_evals']):>9}"
              f" {r['successes']:>4}/{n:<2} {r['restarts']:>8} |"
              f" {fmt(d['median_evals'] if d else None):>7}"
              f" {(str(d['successes']) + '/' + str(n)) if d else '':>7} | {ratio:>5}")
    print(f"overhead per generation, d = 10, lambda = 10 (evaluation excluded): gaitforge "
          f"{ours['overhead_us']:.1f} us, DEAP {deap['overhead_us']:.1f} us "
          f"({deap['overhead_us'] / ours['overhead_us']:.0f}x)")
    print("gaitforge restarts: IPOP/BIPOP start only after a run's stopping criteria fire;"
          " DEAP's cma.Strategy has none.")


if __name__ == "__main__":
    main()
