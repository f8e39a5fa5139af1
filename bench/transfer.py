#!/usr/bin/python3
"""Transfer benchmark (issue 26): do evolved gaits walk on a build of the robot they were
not evolved on?

Evolves the caterpillar's 13-gene gait three ways through the real CLI (`gaitforge local`,
2 workers, SQLite files): with the paper's fitness; with robust evaluation (the gap
finder's six numeric variants, several cycles, mean - k sd) for the same number of
generations; and with the paper's fitness for the robust study's budget of simulations
(six times the generations: one simulation per genotype against six). Then
runs gaits of each study on an independent build, bench/diagnosis/rig2d.py (another body
discretisation, contact law and integrator; docs/diagnosis.md), with nothing concealed and
with a concealed hose. For each study and set (the 20 best distinct gaits of the whole
study; 20 distinct gaits spread over the final population's ranks) it prints the ratio of
achieved to predicted travel (sums over the set; predicted = the study's fitness, or for
the robust study the ensemble mean, robust.mean), the Spearman rank correlation of
predicted and achieved travel, and the best gait's achieved travel.

    /usr/bin/python3 bench/transfer.py [--bin build/bin] [--population 100]
        [--generations 30] [--quick]

Prints a table and writes transfer.json in --out. --quick: a smoke run (small studies,
few gaits) to check the pipeline, not a measurement.
"""
import argparse
import json
import os
import sqlite3
import struct
import subprocess
import sys
import time

import numpy as np
from scipy.stats import spearmanr

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "diagnosis"))
import rig2d  # noqa: E402

ROBUST_MEMBERS = 6  # numerics: [standard] on the caterpillar
SCENARIOS = {"nothing concealed": {}, "hose 0.05 N + 0.5 N/m": {"hose_n": 0.05, "hose_n_per_m": 0.5}}


def spec(name, population, generations, robust):
    text = (f"name: {name}\nseed: 1\nengine: ga\npopulation: {population}\n"
            f"generations: {generations}\nga: {{elite: 10, mutation_rate: 0.10}}\n"
            "objective:\n  name: caterpillar.distance\n")
    if not robust:
        return text + "  params: {cycles: 1, settle_cycles: 2}\n"
    return text + ("  params: {cycles: 2, settle_cycles: 1}\n"
                   "  robust:\n    numerics: [standard]\n"
                   "    statistic: mean_minus_sd\n    k: 0.5\n")


def evolve(args, name, generations, robust):
    db = os.path.join(args.out, f"{name}.db")
    if os.path.exists(db):
        os.remove(db)
    path = os.path.join(args.out, f"{name}.yaml")
    with open(path, "w") as f:
        f.write(spec(name, args.population, generations, robust))
    t0 = time.monotonic()
    r = subprocess.run([os.path.join(args.bin, "gaitforge"), "--db", db, "local", path,
                        "--workers", "2"], capture_output=True, text=True)
    wall = time.monotonic() - t0
    if r.returncode != 0:
        sys.exit(f"transfer: {name} failed ({r.returncode}): {r.stderr[-2000:]}")
    return db, wall


def genes_of(blob):
    return list(struct.unpack(f"<{len(blob) // 8}d", blob))


def same_gait(a, b):
    """Equal up to one shift of all 12 phases (the hall of fame's rule)."""
    if abs(a[12] - b[12]) > 1e-9:
        return False
    d = [((x - y) % 1.0) for x, y in zip(a[:12], b[:12])]
    return all(min(abs(x - d[0]), 1 - abs(x - d[0])) < 1e-9 for x in d)


def individuals(db, robust):
    """(generation, fitness, predicted, genes) of every valid individual evaluated."""
    con = sqlite3.connect(db)
    rows = con.execute("SELECT generation, member, genes, fitness FROM individuals "
                       "WHERE valid = 1 AND carried = 0").fetchall()
    mean = dict(((g, m), v) for g, m, v in con.execute(
        "SELECT generation, member, value FROM metrics WHERE name = 'robust.mean'"))
    out = []
    for g, m, blob, fit in rows:
        out.append((g, fit, mean.get((g, m), fit) if robust else fit, genes_of(blob)))
    last = con.execute("SELECT MAX(generation) FROM individuals").fetchone()[0]
    final = [(fit, mean.get((g, m), fit) if robust else fit, genes_of(blob)) for g, m, blob, fit in
             con.execute("SELECT generation, member, genes, fitness FROM individuals "
                         "WHERE valid = 1 AND generation = ?", (last,))]
    return out, final


def distinct(ranked, n, every=1):
    chosen = []
    for k, item in enumerate(ranked):
        if k % every:
            continue
        if any(same_gait(item[-1], c[-1]) for c in chosen):
            continue
        chosen.append(item)
        if len(chosen) == n:
            break
    return chosen


def gait_sets(db, robust, n):
    every, final = individuals(db, robust)
    best = distinct(sorted(every, key=lambda r: -r[1]), n)
    final.sort(key=lambda r: -r[0])
    spread = distinct(final, n, every=max(1, len(final) // n))
    return {"best": [(p, g) for _, _, p, g in best], "spread": [(p, g) for _, p, g in spread]}


def measure(sets, cycles):
    """Achieved travel per cycle on rig2d for every gait of every set, every scenario, in
    one batch."""
    runs = [(study, kind, i, scen) for study in sets for kind in sets[study]
            for i in range(len(sets[study][kind])) for scen in SCENARIOS]
    genes = [sets[s][k][i][1] for s, k, i, _ in runs]
    effects = [SCENARIOS[scen] for _, _, _, scen in runs]
    achieved = rig2d.travel(genes, effects, settle=1, cycles=cycles)
    return {run: a for run, a in zip(runs, achieved)}


def table(sets, achieved, walls):
    rows = []
    for study in sets:
        for scen in SCENARIOS:
            for kind in ("best", "spread"):
                pred = np.array([p for p, _ in sets[study][kind]])
                ach = np.array([achieved[(study, kind, i, scen)] for i in range(len(pred))])
                ok = np.isfinite(ach)
                rho = spearmanr(pred[ok], ach[ok]).correlation if ok.sum() > 2 else float("nan")
                rows.append({"study": study, "scenario": scen, "set": kind, "gaits": int(ok.sum()),
                             "predicted_cm": 100 * pred[ok].mean(),
                             "achieved_cm": 100 * ach[ok].mean(),
                             "ratio": ach[ok].sum() / pred[ok].sum(), "spearman": rho,
                             "best_gait_cm": 100 * ach[0] if kind == "best" else float("nan"),
                             "wall_s": walls[study]})
    print(f"{'study':<14}{'scenario':<22}{'set':<8}{'n':>3}{'pred cm':>9}{'real cm':>9}"
          f"{'ratio':>7}{'rho':>7}{'best cm':>9}{'wall s':>8}")
    for r in rows:
        print(f"{r['study']:<14}{r['scenario']:<22}{r['set']:<8}{r['gaits']:>3}"
              f"{r['predicted_cm']:>9.2f}{r['achieved_cm']:>9.2f}{r['ratio']:>7.2f}"
              f"{r['spearman']:>7.2f}{r['best_gait_cm']:>9.2f}{r['wall_s']:>8.0f}")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default=os.path.join(HERE, "..", "build", "bin"))
    ap.add_argument("--out", default="transfer-out")
    ap.add_argument("--population", type=int, default=100)
    ap.add_argument("--generations", type=int, default=30)
    ap.add_argument("--gaits", type=int, default=20)
    ap.add_argument("--cycles", type=int, default=4, help="measured cycles on rig2d")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    if args.quick:
        args.population, args.generations, args.gaits, args.cycles = 12, 3, 3, 2
    os.makedirs(args.out, exist_ok=True)
    walls, sets = {}, {}
    for name, robust in (("paper", False), ("robust", True)):
        db, walls[name] = evolve(args, name, args.generations, robust)
        sets[name] = gait_sets(db, robust, args.gaits)
        print(f"{name}: evolved in {walls[name]:.0f} s", flush=True)
    # The paper's fitness for the robust study's number of simulations (6 members each).
    longer = args.generations * ROBUST_MEMBERS
    db, walls["paper-long"] = evolve(args, "paper-long", longer, False)
    sets["paper-long"] = gait_sets(db, False, args.gaits)
    print(f"paper-long: {longer} generations in {walls['paper-long']:.0f} s", flush=True)
    t0 = time.monotonic()
    achieved = measure(sets, args.cycles)
    print(f"rig2d: {len(achieved)} runs in {time.monotonic() - t0:.0f} s", flush=True)
    rows = table(sets, achieved, walls)
    with open(os.path.join(args.out, "transfer.json"), "w") as f:
        json.dump({"rows": rows, "population": args.population,
                   "generations": args.generations, "paper_long_generations": longer}, f, indent=1)


if __name__ == "__main__":
    main()
