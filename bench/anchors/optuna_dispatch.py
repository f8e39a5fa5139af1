#!/usr/bin/python3
"""Anchor for issue 30: Optuna's dispatch efficiency with its RDB (SQLite) storage and K
worker processes, each evaluation a wait of a fixed time, as gaitforge-swarm's emulated
workers do.

K processes (fork) call study.optimize on one SQLite file; each trial samples the 13
genes (Optuna's default TPE, as a user would) and sleeps --eval seconds. Efficiency =
trials x eval / (K x wall), the figure bench/scaling.py reports for gaitforge. Process
start-up is excluded (the clock starts when every process has loaded the study).

    /usr/bin/python3 bench/anchors/optuna_dispatch.py --processes 16 --eval 0.5 --json
"""
import argparse
import json
import multiprocessing as mp
import os
import tempfile
import time

import optuna

from rastrigin import HI, LO, NAMES, rastrigin_fitness

STUDY = "dispatch"


def storage(url):
    return optuna.storages.RDBStorage(url, engine_kwargs={"connect_args": {"timeout": 300}})


def worker(url, seconds_each, deadline, start, eval_s, out):
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.load_study(study_name=STUDY, storage=storage(url))
    start.wait()
    done = 0

    def objective(trial):
        x = [trial.suggest_float(n, lo, hi) for n, lo, hi in zip(NAMES, LO, HI)]
        time.sleep(eval_s)
        return rastrigin_fitness(x)

    while time.time() < deadline.value:
        study.optimize(objective, n_trials=1)
        done += 1
    out.put(done)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--processes", type=int, default=16)
    p.add_argument("--eval", type=float, default=0.5, help="seconds per trial")
    p.add_argument("--seconds", type=float, default=30, help="length of the run")
    p.add_argument("--json", action="store_true")
    a = p.parse_args()
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    ctx = mp.get_context("fork")
    with tempfile.TemporaryDirectory(prefix="optuna-dispatch-") as tmp:
        url = "sqlite:///" + os.path.join(tmp, "study.db")
        st = storage(url)
        optuna.create_study(study_name=STUDY, storage=st, direction="maximize")
        st.engine.dispose()
        start, out = ctx.Event(), ctx.Queue()
        deadline = ctx.Value("d", 0.0)
        procs = [ctx.Process(target=worker, args=(url, 0, deadline, start, a.eval, out))
                 for _ in range(a.processes)]
        for pr in procs:
            pr.start()
        time.sleep(2 + 0.05 * a.processes)  # let every process load the study
        t0 = time.time()
        deadline.value = t0 + a.seconds
        start.set()
        trials = sum(out.get() for _ in procs)
        wall = time.time() - t0
        for pr in procs:
            pr.join()
    res = {"tool": "optuna-rdb-sqlite", "processes": a.processes, "eval": a.eval,
           "trials": trials, "wall_s": round(wall, 2),
           "efficiency": round(trials * a.eval / (a.processes * wall), 4),
           "overhead_ms_per_trial": round(1000 * (a.processes * wall / trials - a.eval), 1)}
    print(json.dumps(res) if a.json else
          "optuna %s, %d processes, %.3f s trials: %d trials in %.1f s, efficiency %.3f, "
          "%.1f ms overhead per trial" % (optuna.__version__, a.processes, a.eval, trials, wall,
                                           res["efficiency"], res["overhead_ms_per_trial"]))


if __name__ == "__main__":
    main()
