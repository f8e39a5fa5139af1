#!/usr/bin/python3
"""Anchor benchmark: DEAP's CMA-ES (deap.cma.Strategy) on gaitforge's CMA-ES benchmark.

Same setup as bench/cmaes_bench.cc: x0 uniform in [-5, 5)^d drawn exactly as gaitforge
draws it (core::KeyedRng(seed, 0, i, kInit), SplitMix64, reimplemented below), sigma0 = 2,
DEAP's default lambda = 4 + floor(3 ln d), numpy seeded with the seed. DEAP has no bounds
and no restarts. A run succeeds when a generation's best f < 1e-8 within the budget
(1e5 evaluations; Rastrigin also stops once sigma < 1e-12, converged in a local optimum).
Overhead: microseconds per generate + update (evaluation excluded), d = 10, sphere.

    /usr/bin/python3 bench/anchors/deap_cma.py [--seeds 15] [--json]
"""
import argparse
import json
import math
import statistics
import time

import numpy
from deap import base, cma, creator

creator.create("FitnessMin", base.Fitness, weights=(-1.0,))
creator.create("Individual", list, fitness=creator.FitnessMin)

M64 = (1 << 64) - 1


def mix64(x):
    x = (x + 0x9E3779B97F4A7C15) & M64
    x = ((x ^ (x >> 30)) * 0xBF58476D1CE4E5B9) & M64
    x = ((x ^ (x >> 27)) * 0x94D049BB133111EB) & M64
    return x ^ (x >> 31)


def keyed_uniform(seed, generation, member, purpose, lo, hi):
    """First draw of core::KeyedRng(seed, generation, member, purpose).Uniform(lo, hi)."""
    s = mix64(seed)
    s = mix64(s ^ ((generation * 0xD1B54A32D192ED03) & M64))
    s = mix64(s ^ ((member * 0xABC98388FB8FAC03) & M64))
    s = mix64(s ^ ((purpose * 0x8CB92BA72F3D8DD7) & M64))
    z = (s + 0x9E3779B97F4A7C15) & M64  # NextU64: advance, then finalise
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & M64
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & M64
    z ^= z >> 31
    x = lo + (hi - lo) * ((z >> 11) * 2.0 ** -53)
    return x if x < hi else lo


def start_point(seed, d):
    return [keyed_uniform(seed, 0, i, 1, -5.0, 5.0) for i in range(d)]


def sphere(x):
    return sum(v * v for v in x)


def ellipsoid(x):
    n = len(x)
    return sum(1e6 ** (i / (n - 1)) * v * v for i, v in enumerate(x))


def rosenbrock(x):
    return sum(100.0 * (x[i + 1] - x[i] ** 2) ** 2 + (1.0 - x[i]) ** 2 for i in range(len(x) - 1))


def rastrigin(x):
    return 10.0 * len(x) + sum(v * v - 10.0 * math.cos(2.0 * math.pi * v) for v in x)


FUNCTIONS = {"sphere": sphere, "ellipsoid": ellipsoid, "rosenbrock": rosenbrock,
             "rastrigin": rastrigin}
PROBLEMS = [("sphere", 10), ("ellipsoid", 10), ("rosenbrock", 10), ("sphere", 13),
            ("ellipsoid", 13), ("rosenbrock", 13), ("rastrigin", 10)]


def solve(name, d, seed, budget=100000):
    """Evaluations until a generation's best f < 1e-8, or -1."""
    numpy.random.seed(seed)
    f = FUNCTIONS[name]
    strategy = cma.Strategy(centroid=start_point(seed, d), sigma=2.0)
    evals = 0
    while evals + strategy.lambda_ <= budget and strategy.sigma > 1e-12:
        pop = strategy.generate(creator.Individual)
        best = math.inf
        for ind in pop:
            v = f(ind)
            ind.fitness.values = (v,)
            best = min(best, v)
        evals += len(pop)
        if best < 1e-8:
            return evals
        strategy.update(pop)
    return -1


def overhead_us(generations=2000, d=10):
    numpy.random.seed(1)
    strategy = cma.Strategy(centroid=start_point(1, d), sigma=2.0)
    total = 0.0
    pop = strategy.generate(creator.Individual)
    for _ in range(generations):
        for ind in pop:  # untimed
            ind.fitness.values = (sphere(ind),)
        t0 = time.perf_counter()
        strategy.update(pop)
        pop = strategy.generate(creator.Individual)
        total += time.perf_counter() - t0
    return 1e6 * total / generations


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seeds", type=int, default=15)
    p.add_argument("--json", action="store_true", help="print one JSON line instead")
    a = p.parse_args()
    rows = []
    for name, d in PROBLEMS:
        evals = [e for e in (solve(name, d, s) for s in range(1, a.seeds + 1)) if e > 0]
        rows.append({"function": name, "dim": d, "restarts": "none", "successes": len(evals),
                     "median_evals": statistics.median(evals) if evals else -1})
    res = {"tool": "deap-cma", "seeds": a.seeds, "overhead_us": round(overhead_us(), 3),
           "rows": rows}
    if a.json:
        print(json.dumps(res))
        return
    print(f"DEAP cma.Strategy: evaluations to f < 1e-8, {a.seeds} seeds")
    print(f"{'function':<11} {'d':>3} {'solved':>8} {'median evals':>13}")
    for r in rows:
        print(f"{r['function']:<11} {r['dim']:>3} {r['successes']:>5}/{a.seeds:<3}"
              f" {r['median_evals']:>13.0f}")
    print(f"overhead per generation (generate + update, d = 10): {res['overhead_us']:.1f} us")


if __name__ == "__main__":
    main()
