#!/usr/bin/python3
"""Anchor benchmark: Optuna on SQLite storage, optimising gaitforge's analytic.rastrigin.

The objective (rastrigin.py) matches workers/objectives/analytic.cc over the 13-gene
caterpillar space, shift 0.2, fitness = -loss maximised.

Each run uses a fresh SQLite file in a temporary directory. With --processes K > 1, K
processes (multiprocessing, fork) each call study.optimize on the same storage, sharing
the trials between them. The wall time covers the optimisation only (process start-up
included for K > 1; study creation excluded).

    /usr/bin/python3 bench/anchors/optuna_sqlite.py --trials 300
    /usr/bin/python3 bench/anchors/optuna_sqlite.py --trials 300 --processes 2 --json
"""
import argparse
import json
import multiprocessing as mp
import os
import tempfile
import time

import optuna

from rastrigin import HI, LO, NAMES, rastrigin_fitness  # gaitforge's objective

STUDY = "anchor"


def objective(trial):
    # Optuna's suggest_float samples the closed [lo, hi]; the difference is immaterial here.
    x = [trial.suggest_float(n, lo, hi) for n, lo, hi in zip(NAMES, LO, HI)]
    return rastrigin_fitness(x)


def make_storage(url):
    # A generous busy timeout: K writers on one SQLite file otherwise hit "database is locked".
    return optuna.storages.RDBStorage(url, engine_kwargs={"connect_args": {"timeout": 120}})


def make_sampler(name, seed):
    if name == "tpe":
        return optuna.samplers.TPESampler(seed=seed)
    if name == "random":
        return optuna.samplers.RandomSampler(seed=seed)
    return None  # Optuna's default (TPESampler, unseeded)


def worker(url, n_trials, sampler, seed):
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.load_study(study_name=STUDY, storage=make_storage(url),
                              sampler=make_sampler(sampler, seed))
    study.optimize(objective, n_trials=n_trials, n_jobs=1)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--trials", type=int, default=300, help="total trials (default 300)")
    p.add_argument("--processes", type=int, default=1,
                   help="processes sharing the SQLite file (default 1: in-process)")
    p.add_argument("--sampler", choices=["default", "tpe", "random"], default="default",
                   help="default = Optuna's default sampler, unseeded; tpe/random are seeded")
    p.add_argument("--seed", type=int, default=42,
                   help="sampler seed (process k uses seed + k)")
    p.add_argument("--json", action="store_true", help="print one JSON line instead")
    a = p.parse_args()
    optuna.logging.set_verbosity(optuna.logging.WARNING)

    k = max(1, a.processes)
    share = [a.trials // k + (1 if r < a.trials % k else 0) for r in range(k)]
    with tempfile.TemporaryDirectory(prefix="optuna-anchor-") as tmp:
        url = "sqlite:///" + os.path.join(tmp, "study.db")
        storage = make_storage(url)
        optuna.create_study(study_name=STUDY, storage=storage, direction="maximize")
        storage.engine.dispose()  # no pooled connection crosses the fork

        t0 = time.perf_counter()
        if k == 1:
            worker(url, a.trials, a.sampler, a.seed)
        else:
            ctx = mp.get_context("fork")
            procs = [ctx.Process(target=worker, args=(url, share[r], a.sampler, a.seed + r))
                     for r in range(k)]
            for pr in procs:
                pr.start()
            for pr in procs:
                pr.join()
            if any(pr.exitcode != 0 for pr in procs):
                raise SystemExit("a worker process failed")
        seconds = time.perf_counter() - t0

        study = optuna.load_study(study_name=STUDY, storage=make_storage(url))
        done = [t for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE]
        best = study.best_value

    out = {"tool": "optuna-sqlite", "trials": len(done), "seconds": round(seconds, 3),
           "trials_per_second": round(len(done) / seconds, 2), "processes": k}
    if a.json:
        print(json.dumps(out))
    else:
        print(f"optuna {optuna.__version__} sqlite, sampler={a.sampler}, processes={k}: "
              f"{len(done)} trials in {seconds:.2f} s = {len(done) / seconds:.1f} trials/s "
              f"(best fitness {best:.3f})")


if __name__ == "__main__":
    main()
