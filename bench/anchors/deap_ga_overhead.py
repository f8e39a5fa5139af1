#!/usr/bin/python3
"""Anchor benchmark: DEAP's own GA overhead per generation, evaluation excluded.

Mirrors the caterpillar paper's GA as gaitforge runs it (services/engines/ga/): 200
individuals of 13 genes in the caterpillar space, elitism of 10 (the best 10 copied
unchanged), roulette selection (tools.selRoulette) on windowed fitness w = f - f_min,
one-point crossover of every selected pair (tools.cxOnePoint; DEAP draws the cut per pair,
gaitforge once per generation), and per-gene re-initialisation mutation with p = 0.10.

Fitness is gaitforge's analytic.rastrigin (rastrigin.py), so selection sees a real
landscape, but it is computed outside the timed region: the figure is selection +
variation + bookkeeping (sorting for the elite, cloning, fitness invalidation, the
windowed weights) only.

    /usr/bin/python3 bench/anchors/deap_ga_overhead.py --generations 200
"""
import argparse
import json
import random
import statistics
import time

from deap import base, creator, tools

from rastrigin import HI, LO, rastrigin_fitness  # gaitforge's objective

creator.create("FitnessMax", base.Fitness, weights=(1.0,))
creator.create("Roulette", base.Fitness, weights=(1.0,))  # the windowed weight
creator.create("Individual", list, fitness=creator.FitnessMax, roulette=None)


def random_gene(i):
    return random.uniform(LO[i], HI[i])


def mut_reinit(ind, rate):
    """Each gene, independently with probability rate, becomes a fresh uniform draw."""
    for i in range(len(ind)):
        if random.random() < rate:
            ind[i] = random_gene(i)
    return (ind,)


def make_toolbox(rate):
    tb = base.Toolbox()
    tb.register("individual", lambda: creator.Individual(random_gene(i) for i in range(len(LO))))
    tb.register("population", tools.initRepeat, list, tb.individual)
    tb.register("mate", tools.cxOnePoint)
    tb.register("mutate", mut_reinit, rate=rate)
    tb.register("select", tools.selRoulette, fit_attr="roulette")
    return tb


def evaluate(pop):
    """Untimed: fitness of every member without one."""
    for ind in pop:
        if not ind.fitness.valid:
            ind.fitness.values = (rastrigin_fitness(ind),)


def next_generation(tb, pop, elite):
    """Timed: the optimiser's own work for one generation."""
    fits = [ind.fitness.values[0] for ind in pop]
    f_min = min(fits)
    all_zero = max(fits) == f_min
    for ind, f in zip(pop, fits):  # windowing; if every weight is 0, all get 1
        ind.roulette = creator.Roulette((1.0 if all_zero else f - f_min,))
    n_children = len(pop) - elite
    chosen = tb.select(pop, n_children + n_children % 2)
    for ind in pop:  # drop the weight so clone copies only what DEAP itself would
        del ind.roulette
    offspring = [tb.clone(ind) for ind in tools.selBest(pop, elite)]
    parents = [tb.clone(ind) for ind in chosen]
    for a, b in zip(parents[::2], parents[1::2]):
        tb.mate(a, b)
        for child in (a, b):
            tb.mutate(child)
            del child.fitness.values
    return offspring + parents[:n_children]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--population", type=int, default=200, help="individuals (default 200)")
    p.add_argument("--generations", type=int, default=200, help="timed generations (default 200)")
    p.add_argument("--elite", type=int, default=10, help="elitism (default 10)")
    p.add_argument("--mutation-rate", type=float, default=0.10, help="per gene (default 0.10)")
    p.add_argument("--seed", type=int, default=42)
    p.add_argument("--json", action="store_true", help="print one JSON line instead")
    a = p.parse_args()

    random.seed(a.seed)
    tb = make_toolbox(a.mutation_rate)
    pop = tb.population(n=a.population)
    evaluate(pop)
    times = []
    for _ in range(a.generations):
        t0 = time.perf_counter()
        pop = next_generation(tb, pop, a.elite)
        times.append(time.perf_counter() - t0)
        evaluate(pop)
    ms = 1000 * statistics.fmean(times)
    median = 1000 * statistics.median(times)
    best = max(ind.fitness.values[0] for ind in pop)
    if a.json:
        print(json.dumps({"tool": "deap-ga", "ms_per_generation": round(ms, 4),
                          "median_ms": round(median, 4), "generations": a.generations,
                          "population": a.population}))
    else:
        print(f"deap GA, population {a.population}, {a.generations} generations: "
              f"{ms:.3f} ms/generation mean, {median:.3f} median, excluding evaluation "
              f"(best fitness {best:.3f})")


if __name__ == "__main__":
    main()
