#!/usr/bin/python3
"""Resilience benchmark (issue 5): what durability and faults cost.

  (a) the cost of durability: evaluations per second with --sync full vs --sync normal,
      analytic.rastrigin with work_us 0, the 150 x 200 study (examples/analytic-ga.yaml:
      population 200, 150 generations), 2 workers, otherwise the same run. Rate =
      studies.evaluations / (updated_ms - created_ms), i.e. timed by the coordinator.
  (b) recovery after a coordinator kill: kill -9 mid-generation and an immediate restart on
      the same port and database; time from the kill until the coordinator serves again,
      and until the next result is accepted (individuals.reported_ms of the first
      evaluated row accepted after the kill; workers reconnect with backoff).
  (c) evaluations wasted per worker kill: kill -9 a worker every few seconds (and start a
      replacement); wasted = leases - accepted - duplicates from the generations table
      (evaluations leased and never reported), minus the same figure of a run without
      kills, divided by the number of kills. One coordinator process throughout, so its
      counters are complete.

Run from the repository root after ./scripts/build.sh:
    /usr/bin/python3 bench/resilience.py [--repeats 2] [--kills 5] [--json]
"""
import argparse
import json
import os
import random
import signal
import statistics
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "chaos"))
import chaos  # noqa: E402  (process helpers and read-only DB helpers)


def cluster(bin_dir, d, flags, workers, threads=1, port=0):
    cl = chaos.LocalCluster(bin_dir, d, None, os.path.join(d, "bench.db"), port, flags, threads)
    cl.coord.start()
    for _ in range(workers):
        cl.add_worker()
    return cl


def study_row(db, study_id):
    con = chaos.ro_connect(db)
    try:
        r = con.execute("SELECT evaluations, created_ms, updated_ms, state FROM studies WHERE study_id = ?",
                        (study_id,)).fetchone()
        return {"evaluations": r[0], "created_ms": r[1], "updated_ms": r[2], "state": r[3]}
    finally:
        con.close()


def durability_run(bin_dir, sync, workers):
    with tempfile.TemporaryDirectory(prefix="gf-resil-sync-") as d:
        spec = chaos.make_spec(seed=42, population=200, generations=150, work_us=0, name="analytic-ga")
        spec_path = chaos.write_spec(spec, os.path.join(d, "spec.json"))
        cl = cluster(bin_dir, d, ["--sync", sync], workers)
        try:
            sid = chaos.submit(bin_dir, cl.coord.target, spec_path)
            st = chaos.wait_completed(cl.db, sid, 600, poll=0.05)
            assert st and st["state"] == "completed", st
            r = study_row(cl.db, sid)
        finally:
            cl.stop_all()
        secs = (r["updated_ms"] - r["created_ms"]) / 1000.0
        return {"sync": sync, "evaluations": r["evaluations"], "seconds": secs,
                "evals_per_second": r["evaluations"] / secs}


def first_accept_after(db, study_id, t_ms):
    con = chaos.ro_connect(db)
    try:
        return con.execute("SELECT MIN(reported_ms) FROM individuals WHERE study_id = ? AND carried = 0 AND "
                           "reported_ms > ?", (study_id, t_ms)).fetchone()[0]
    finally:
        con.close()


def recovery_run(bin_dir, kills, workers):
    with tempfile.TemporaryDirectory(prefix="gf-resil-rec-") as d:
        spec = chaos.make_spec(seed=7, population=50, generations=400, work_us=2000, name="recovery")
        spec_path = chaos.write_spec(spec, os.path.join(d, "spec.json"))
        cl = cluster(bin_dir, d, ["--lease-ms", "2000"], workers, port=chaos.free_port())
        cl.spec = spec
        out = []
        try:
            cl.study_id = chaos.submit(bin_dir, cl.coord.target, spec_path)
            nem = chaos.Nemesis(cl, random.Random(1), 2000)
            time.sleep(1.0)
            for _ in range(kills):
                mid, st = nem.wait_mid_generation()
                if not st or st["state"] != "running":
                    break
                t_kill = time.time()
                cl.coord.kill9()
                t0 = time.monotonic()
                cl.coord.start()
                serving = time.monotonic() - t0
                first = None
                end = time.monotonic() + 30
                while first is None and time.monotonic() < end:
                    first = first_accept_after(cl.db, cl.study_id, int(t_kill * 1000))
                    if first is None:
                        time.sleep(0.01)
                out.append({"mid_generation": mid, "serving_s": serving,
                            "first_result_s": None if first is None else first / 1000.0 - t_kill})
                time.sleep(1.5)
        finally:
            cl.stop_all()
        return out


def waste_run(bin_dir, kills, workers, interval=2.0, seed=3):
    with tempfile.TemporaryDirectory(prefix="gf-resil-waste-") as d:
        spec = chaos.make_spec(seed=11, population=50, generations=40, work_us=20000, name="waste")
        spec_path = chaos.write_spec(spec, os.path.join(d, "spec.json"))
        cl = cluster(bin_dir, d, ["--lease-ms", "2000", "--max-attempts", "50"], workers)
        rng = random.Random(seed)
        done_kills = 0
        try:
            sid = chaos.submit(bin_dir, cl.coord.target, spec_path)
            next_kill = time.monotonic() + interval
            while True:
                st = chaos.study_status(cl.db, sid)
                if st and st["state"] != "running":
                    break
                if done_kills < kills and time.monotonic() >= next_kill:
                    w = rng.choice(cl.workers)
                    chaos.kill9(w[1])
                    cl.workers.remove(w)
                    cl.add_worker()
                    done_kills += 1
                    next_kill = time.monotonic() + interval
                time.sleep(0.05)
            r = study_row(cl.db, sid)
            q = chaos.fault_counters(cl.db, sid)
        finally:
            cl.stop_all()
        never = q["leases"] - q["evaluations"] - q["duplicates"]
        return {"kills": done_kills, "seconds": (r["updated_ms"] - r["created_ms"]) / 1000.0,
                "never_reported": never, **q}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--bin-dir", default=os.path.join(ROOT, "build", "bin"))
    ap.add_argument("--repeats", type=int, default=2, help="runs per --sync mode (alternating)")
    ap.add_argument("--kills", type=int, default=5, help="coordinator kills (b) and worker kills (c)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--json-out", help="also write the JSON object to this file")
    ap.add_argument("--from-json", help="print the table of a saved --json result, run nothing")
    a = ap.parse_args()
    bin_dir = os.path.abspath(a.bin_dir)
    if a.from_json:
        with open(a.from_json) as f:
            print_table(json.load(f))
        return

    res = {"durability": [], "recovery": [], "waste": {}}
    for _ in range(a.repeats):
        for sync in ("full", "normal"):
            res["durability"].append(durability_run(bin_dir, sync, 2))
    res["recovery"] = recovery_run(bin_dir, a.kills, 2)
    res["waste"]["baseline"] = waste_run(bin_dir, 0, 4)
    res["waste"]["kills"] = waste_run(bin_dir, a.kills, 4)

    med = {s: statistics.median(r["evals_per_second"] for r in res["durability"] if r["sync"] == s)
           for s in ("full", "normal")}
    res["summary"] = {"evals_per_second_full": med["full"], "evals_per_second_normal": med["normal"],
                      "durability_cost_pct": 100.0 * (1 - med["full"] / med["normal"])}
    rec = [r for r in res["recovery"] if r["first_result_s"] is not None]
    if rec:
        res["summary"].update({
            "recovery_serving_s_median": statistics.median(r["serving_s"] for r in rec),
            "recovery_first_result_s_median": statistics.median(r["first_result_s"] for r in rec),
            "recovery_first_result_s_max": max(r["first_result_s"] for r in rec)})
    wb, wk = res["waste"]["baseline"], res["waste"]["kills"]
    if wk["kills"]:
        res["summary"]["wasted_evaluations_per_worker_kill"] = (wk["never_reported"] - wb["never_reported"]) / wk["kills"]

    if a.json_out:
        with open(a.json_out, "w") as f:
            json.dump(res, f, indent=2)
    if a.json:
        print(json.dumps(res, indent=2))
        return
    print_table(res)


def print_table(res):
    s = res["summary"]
    med = {x: s["evals_per_second_" + x] for x in ("full", "normal")}
    rec = [r for r in res["recovery"] if r["first_result_s"] is not None]
    wb, wk = res["waste"]["baseline"], res["waste"]["kills"]
    print("(a) Durability, analytic.rastrigin work_us 0, 200 x 150 GA (28,510 evaluations), 2 workers")
    print("    %-8s %8s %10s %12s" % ("sync", "runs", "seconds", "evals/s"))
    for sync in ("full", "normal"):
        rs = [r for r in res["durability"] if r["sync"] == sync]
        print("    %-8s %8d %10.2f %12.0f" % (sync, len(rs), statistics.median(r["seconds"] for r in rs), med[sync]))
    print("    cost of synchronous=FULL: %.1f %% fewer evaluations per second (medians)" % s["durability_cost_pct"])
    print("(b) Recovery after kill -9 of the coordinator mid-generation + immediate restart "
          "(2 workers, 50 x 400, work_us 2000)")
    print("    %-6s %6s %14s %18s" % ("kill", "mid", "serving (s)", "next result (s)"))
    for i, r in enumerate(res["recovery"]):
        print("    %-6d %6s %14.3f %18s" % (i + 1, r["mid_generation"], r["serving_s"],
                                          "-" if r["first_result_s"] is None else "%.3f" % r["first_result_s"]))
    if rec:
        print("    median: serving %.3f s, next accepted result %.3f s after the kill (max %.3f s)" % (
            s["recovery_serving_s_median"], s["recovery_first_result_s_median"], s["recovery_first_result_s_max"]))
    print("(c) Waste per worker kill (4 workers, 50 x 40, work_us 20000, lease 2000 ms)")
    print("    %-9s %6s %8s %8s %11s %11s %8s %15s %8s" % ("run", "kills", "seconds", "leases", "evaluations",
                                                          "duplicates", "backups", "never reported", "expiries"))
    for name, r in (("baseline", wb), ("kills", wk)):
        print("    %-9s %6d %8.2f %8d %11d %11d %8d %15d %8d" % (
            name, r["kills"], r["seconds"], r["leases"], r["evaluations"], r["duplicates"], r["backups"],
            r["never_reported"], r["lease_expiries"]))
    if "wasted_evaluations_per_worker_kill" in s:
        print("    wasted evaluations per worker kill: %.1f (leased, never reported; baseline subtracted); "
              "time per kill: %.2f s" % (s["wasted_evaluations_per_worker_kill"],
                                        (wk["seconds"] - wb["seconds"]) / wk["kills"]))


if __name__ == "__main__":
    main()
