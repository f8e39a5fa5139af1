#!/usr/bin/python3
"""Jepsen-style chaos test for gaitforge (issue 5), on one host (loopback).

1. Reference: a coordinator and 4 workers run a GA study with no faults.
2. Chaos: the same spec and seed, a coordinator on a fixed port (--lease-ms 2000,
   --max-attempts 50) and 4 workers, while a nemesis kill -9s workers (and starts
   replacements), SIGSTOPs a worker past its lease then SIGCONTs it, kill -9s the
   coordinator mid-generation and restarts it on the same port and database, and SIGSTOPs a
   worker across a coordinator restart (a partition during the restart, simulated).
3. A checker reads both databases read-only and asserts: every job ended done or poisoned,
   exactly one accepted result per key, evaluations counted == distinct keys, PRAGMA
   integrity_check is ok, and the chaos run's result equals the reference bit for bit.

Exit 0 on pass, 1 on failure (logs of every process are kept in a temp dir, printed).
The module is also a library: netns.py imports the process helpers and the checker.

Run with /usr/bin/python3 (stdlib only):
    /usr/bin/python3 tests/chaos/chaos.py --bin-dir build/bin [--json-out FILE] [--keep]
"""

import argparse
import atexit
import json
import os
import random
import shutil
import signal
import socket
import sqlite3
import struct
import subprocess
import sys
import tempfile
import time


from chaos_procs import *  # noqa: F401,F403  (re-exported for netns.py and the bench)
from chaos_procs import _cleanup_procs, _f  # noqa: F401
from chaos_check import *  # noqa: F401,F403
from chaos_check import _diff  # noqa: F401

# --------------------------------------------------------------------------------------
# Runs


def paced_interval(reference_seconds, steps=6, share=0.5, bounds=(0.6, 2.0)):
    """The nemesis' gap between actions: its first `steps` actions (the coverage) fit in
    `share` of the fault-free run's length, within `bounds` seconds; (lo, hi) for uniform()."""
    hi = min(bounds[1], max(bounds[0], share * reference_seconds / steps))
    return (hi / 2.0, hi)


def run_reference(bin_dir, workdir, spec_path, workers=4, timeout=300.0, prefix=None):
    """Fault-free run on loopback. Returns (db, study_id, seconds)."""
    os.makedirs(workdir, exist_ok=True)
    db = os.path.join(workdir, "reference.db")
    coord = Coordinator(bin_dir, workdir, db, "127.0.0.1", 0, ["--lease-ms", "10000"], prefix,
                        name="coordinator")
    coord.start()
    procs = [start_worker(bin_dir, workdir, coord.target, "ref-w%d" % i, prefix=prefix) for i in range(workers)]
    t0 = time.monotonic()
    study_id = submit(bin_dir, coord.target, spec_path, prefix)
    st = wait_completed(db, study_id, timeout)
    secs = time.monotonic() - t0
    for p in procs:
        stop_proc(p)
    coord.stop()
    if not st or st["state"] != "completed":
        raise RuntimeError("reference run did not complete: %r (logs in %s)" % (st, workdir))
    return db, study_id, secs


class Nemesis:
    """Faults on a cluster. Events go to self.events and nemesis.log.

    The first len(PLAN) actions are fixed so that every kind of fault happens early; after
    that actions are drawn by WEIGHTS. isolate()/heal() cut a worker off and back: here
    SIGSTOP/SIGCONT; netns.py overrides them with a real network partition.

    The plan reaches MIN_COVERAGE in its first six actions, the plain isolation last among
    them: a coordinator kill waits while a worker is cut off (2.5 leases), and with the
    isolation third a quick run ended before the plan had killed enough (CI, 12.7 s run).
    """

    PLAN = ["kill_coordinator", "kill_worker", "partition_restart", "kill_worker", "kill_coordinator",
            "isolate_worker", "kill_worker", "kill_coordinator", "isolate_worker"]
    WEIGHTS = {"kill_worker": 4, "kill_coordinator": 2, "isolate_worker": 2, "partition_restart": 1}
    ISOLATE = "worker_stops_past_lease"  # its name in self.counts
    ISOLATE_VERB = ("SIGSTOP", "SIGCONT")

    def __init__(self, cluster, rng, lease_ms, interval=(1.0, 2.0), first_interval=None, first_steps=6):
        self.c, self.rng, self.lease_ms, self.interval = cluster, rng, lease_ms, interval
        # The gap before each of the first `first_steps` actions (the coverage), then `interval`.
        self.first_interval, self.first_steps = first_interval or interval, first_steps
        self.t0 = time.monotonic()
        self.next_at = self.t0 + rng.uniform(*self.first_interval)
        self.step = 0
        self.pending = []  # [when, worker, why, kind]: heal(worker) at `when`
        self.events = []
        self.counts = {"worker_kills": 0, self.ISOLATE: 0, "coordinator_kills": 0,
                       "coordinator_kills_mid_generation": 0, "partitions_across_restart": 0}
        self.restart_seconds = []

    # How a worker is cut off; netns.py overrides these two.
    def isolate(self, w):
        signal_proc(w[1], signal.SIGSTOP)

    def heal(self, w):
        if alive(w[1]):
            signal_proc(w[1], signal.SIGCONT)

    def log(self, what):
        t = time.monotonic() - self.t0
        self.events.append((round(t, 3), what))
        with open(os.path.join(self.c.workdir, "nemesis.log"), "a") as f:
            f.write("%8.3f %s\n" % (t, what))

    def isolated(self):
        return {x[1][0] for x in self.pending}

    def pick_worker(self, healthy_only=True):
        iso = self.isolated()
        cands = [w for w in self.c.workers if alive(w[1]) and not (healthy_only and w[0] in iso)]
        return self.rng.choice(cands) if cands else None

    def wait_mid_generation(self):
        """Waits (bounded) until the generation in flight has some but not all of its results.
        The bound covers a generation held up by a worker cut off past its lease (on a loaded
        2-core machine a 3 s bound missed the window now and then)."""
        P, elite = self.c.spec["population"], self.c.spec["ga"]["elite"]
        end = time.monotonic() + max(3.0, 3.0 * self.lease_ms / 1000.0)
        st = None
        while time.monotonic() < end:
            st = self.c.status()
            if st and st["state"] == "running":
                need = P if st["generations_done"] == 0 else P - elite
                if 0 < st["inflight"] < need:
                    return True, st
            time.sleep(0.02)
        return False, st

    def restart_coordinator(self, why):
        mid, st = self.wait_mid_generation()
        self.c.coord.kill9()
        t_kill = time.monotonic()
        self.counts["coordinator_kills"] += 1
        self.counts["coordinator_kills_mid_generation"] += int(mid)
        self.log("kill -9 coordinator (%s; generation %s, %s results in, mid-generation=%s)" % (
            why, st and st["generations_done"], st and st["inflight"], mid))
        self.c.coord.start()
        self.restart_seconds.append(time.monotonic() - t_kill)
        self.log("coordinator restarted on %s after %.3f s" % (self.c.coord.target, self.restart_seconds[-1]))

    def hurry(self, st, now):
        """Acts now, not at next_at, while the coverage's actions outnumber the generations
        left: a quick run must not end before the plan has made its coverage."""
        if st and self.step < self.first_steps:
            left = self.c.spec["generations"] - st["generations_done"]
            if left <= self.first_steps - self.step + 1:
                self.next_at = min(self.next_at, now)

    def tick(self, st=None):
        now = time.monotonic()
        self.hurry(st, now)
        for item in [x for x in self.pending if x[0] <= now]:
            self.pending.remove(item)
            self.heal(item[1])
            self.log("%s %s (%s)" % (self.ISOLATE_VERB[1], item[1][0], item[2]))
        if now < self.next_at:
            return
        action = self.PLAN[self.step] if self.step < len(self.PLAN) else self.rng.choices(
            list(self.WEIGHTS), weights=list(self.WEIGHTS.values()))[0]
        if action in ("kill_coordinator", "partition_restart") and any(x[3] == "plain" for x in self.pending):
            # Let the isolated worker's leases expire and their generation commit in this same
            # coordinator process first, so that the expiries show in the generations table.
            self.next_at = now + 0.2
            return
        self.step += 1
        getattr(self, action)()
        gap = self.first_interval if self.step < self.first_steps else self.interval
        self.next_at = time.monotonic() + self.rng.uniform(*gap)

    def kill_worker(self):
        w = self.pick_worker()
        if not w:
            return
        kill9(w[1])
        self.counts["worker_kills"] += 1
        self.c.workers.remove(w)
        nw = self.c.add_worker(like=w)
        self.log("kill -9 worker %s; started replacement %s" % (w[0], nw[0]))

    def isolate_worker(self):
        if len(self.pending) >= 2:
            return self.kill_worker()
        w = self.pick_worker()
        if not w:
            return
        secs = 2.5 * self.lease_ms / 1000.0
        self.isolate(w)
        self.pending.append([time.monotonic() + secs, w, "after %.1f s; lease %d ms" % (secs, self.lease_ms),
                             "plain"])
        self.counts[self.ISOLATE] += 1
        self.log("%s worker %s for %.1f s (past its %d ms lease)" % (self.ISOLATE_VERB[0], w[0], secs,
                                                                     self.lease_ms))

    def kill_coordinator(self):
        self.restart_coordinator("crash")

    def partition_restart(self):
        w = self.pick_worker()
        if not w:
            return self.kill_coordinator()
        self.isolate(w)
        self.log("partition (%s) worker %s across a coordinator restart" % (self.ISOLATE_VERB[0], w[0]))
        self.restart_coordinator("crash while %s is partitioned" % w[0])
        secs = 1.5 * self.lease_ms / 1000.0
        self.pending.append([time.monotonic() + secs, w, "partition healed %.1f s after the restart" % secs,
                             "restart"])
        self.counts["partitions_across_restart"] += 1

    def finish(self):
        for item in self.pending:
            self.heal(item[1])
        self.pending = []


class LocalCluster:
    def __init__(self, bin_dir, workdir, spec, db, port, coord_flags, threads=1):
        self.bin_dir, self.workdir, self.spec, self.db, self.threads = bin_dir, workdir, spec, db, threads
        self.coord = Coordinator(bin_dir, workdir, db, "127.0.0.1", port, coord_flags)
        self.workers = []  # [worker_id, Popen]
        self.n = 0
        self.study_id = None

    def add_worker(self, like=None):
        wid = "w%d" % self.n
        self.n += 1
        w = [wid, start_worker(self.bin_dir, self.workdir, self.coord.target, wid, self.threads)]
        self.workers.append(w)
        return w

    def status(self):
        return study_status(self.db, self.study_id)

    def stop_all(self):
        for w in self.workers:
            stop_proc(w[1])
        return self.coord.stop()


MIN_COVERAGE = {"coordinator_kills": 3, "coordinator_kills_mid_generation": 2, "worker_kills": 2,
                "worker_stops_past_lease": 1, "partitions_across_restart": 1}


def format_summary(res):
    lines = ["gaitforge chaos test (%s): %s" % (res["variant"], "PASS" if res["pass"] else "FAIL")]
    sp = res["spec"]
    lines.append("  spec: %s, %d x %d (population x generations), seed %d, work_us %d; lease %d ms, "
                 "max-attempts %d" % (sp["objective"]["name"], sp["population"], sp["generations"],
                                      sp["seed"], sp["objective"]["params"]["work_us"], res["lease_ms"],
                                      res["max_attempts"]))
    lines.append("  reference (no faults): %.1f s; chaos run: %.1f s; total wall %.1f s; nemesis seed %d" % (
        res["reference_seconds"], res["chaos_seconds"], res["wall_seconds"], res["nemesis_seed"]))
    if res.get("network"):
        lines.append("  network: %s" % res["network"])
    f = res["faults"]
    lines.append("  faults injected: " + ", ".join("%s %d" % (k.replace("_", " "), v) for k, v in f.items()))
    if res.get("restart_seconds"):
        rs = res["restart_seconds"]
        lines.append("  coordinator kill -> serving again: min %.3f s, max %.3f s" % (min(rs), max(rs)))
    q = res.get("queue_counters") or {}
    if q:
        lines.append("  queue counters from the generations table (each row counts only the process that "
                     "committed it): leases %d, lease_expiries %d, duplicates %d, backups %d, poisoned %d" % (
                         q["leases"], q["lease_expiries"], q["duplicates"], q["backups"], q["poisoned"]))
    lg = res.get("logs") or {}
    if lg:
        lines.append("  logs: coordinator warn %d / error %d lines; workers: report failed %d, refused %d, "
                     "unreachable %d" % (lg["coordinator_warn"], lg["coordinator_error"],
                                         lg["worker_report_failed"], lg["worker_refused"],
                                         lg["worker_unreachable"]))
    lines.append("  checks:")
    lines += res["check_lines"]
    if res.get("error"):
        lines.append("  error: %s" % res["error"])
    if not res["pass"]:
        lines.append("  logs of every process kept in %s" % res["workdir"])
    return "\n".join(lines)


def common_args(doc, lease_ms=2000, workers=4):
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--bin-dir", default=os.path.join(here, "..", "..", "build", "bin"))
    ap.add_argument("--json-out", help="write the summary as JSON here")
    ap.add_argument("--seed", type=int, default=20240517, help="study seed")
    ap.add_argument("--nemesis-seed", type=int, default=None, help="default: random (printed)")
    ap.add_argument("--work-us", type=int, default=40000)
    ap.add_argument("--population", type=int, default=50)
    ap.add_argument("--generations", type=int, default=20)
    ap.add_argument("--workers", type=int, default=workers)
    ap.add_argument("--lease-ms", type=int, default=lease_ms)
    ap.add_argument("--max-attempts", type=int, default=50)
    ap.add_argument("--timeout", type=float, default=300.0, help="limit on the chaos run, seconds")
    ap.add_argument("--keep", action="store_true", help="keep the temp dir even on success")
    return ap


def check_bins(bin_dir):
    for b in ("gaitforge-coordinator", "gaitforge-worker", "gaitforge"):
        if not os.access(os.path.join(bin_dir, b), os.X_OK):
            return "%s not found in %s" % (b, bin_dir)
    return None


def new_run(args, variant):
    """(workdir, spec, spec_path, res) for a run; res is the summary being filled in."""
    nseed = args.nemesis_seed if args.nemesis_seed is not None else random.SystemRandom().randrange(1 << 31)
    workdir = tempfile.mkdtemp(prefix="gaitforge-chaos-%s-" % variant)
    spec = make_spec(args.seed, args.population, args.generations, args.work_us)
    spec_path = write_spec(spec, os.path.join(workdir, "spec.json"))
    res = {"variant": variant, "pass": False, "spec": spec, "lease_ms": args.lease_ms,
           "max_attempts": args.max_attempts, "nemesis_seed": nseed, "workdir": workdir,
           "reference_seconds": 0.0, "chaos_seconds": 0.0, "faults": {}, "check_lines": [],
           "t_start": time.monotonic()}
    print("chaos(%s): logs in %s, nemesis seed %d" % (variant, workdir, nseed), flush=True)
    return workdir, spec, spec_path, res


def chaos_phase(cl, nem, spec_path, args, res, ref_db, ref_id, coverage, prefix=None):
    """Submits the study on cluster `cl`, runs nemesis `nem` until it ends, stops the cluster
    and runs every check. Fills in `res`."""
    t0 = time.monotonic()
    cl.study_id = submit(cl.bin_dir, cl.coord.target, spec_path, prefix)
    nem.t0 = t0
    try:
        st = wait_completed(cl.db, cl.study_id, args.timeout, tick=nem.tick, poll=0.05)
    finally:
        nem.finish()
    res["chaos_seconds"] = time.monotonic() - t0
    res["faults"] = dict(nem.counts)
    res["restart_seconds"] = [round(x, 3) for x in nem.restart_seconds]
    res["nemesis_events"] = nem.events
    rc = cl.stop_all()
    print("chaos(%s): chaos run ended (%s) in %.1f s" % (res["variant"], st and st["state"],
                                                         res["chaos_seconds"]), flush=True)
    res["queue_counters"] = fault_counters(cl.db, cl.study_id)
    res["logs"] = log_summary(cl.workdir)
    check = Check()
    check.add("chaos run finished within %.0f s" % args.timeout, st and st["state"] != "running",
              "state %s" % (st and st["state"]))
    check.add("coordinator exits 0 on SIGTERM at the end", rc == 0, "exit %s" % rc)
    short = {k: (res["faults"].get(k, 0), v) for k, v in coverage.items() if res["faults"].get(k, 0) < v}
    check.add("nemesis coverage reached (%s)" % ", ".join("%s>=%d" % kv for kv in coverage.items()),
              not short, "short (got, wanted): %s" % short if short else "")
    full = run_checker(ref_db, ref_id, cl.db, cl.study_id, res["spec"])
    check.items += full.items
    res["check_lines"] = check.lines()
    res["checks"] = [{"name": n, "ok": o, "detail": d} for n, o, d in check.items]
    res["pass"] = check.ok


def finish_run(args, res):
    res["wall_seconds"] = time.monotonic() - res.pop("t_start")
    text = format_summary(res)
    print(text, flush=True)
    if args.json_out:
        with open(args.json_out, "w") as f:
            json.dump(res, f, indent=2, default=str)
    if res["pass"] and not args.keep:
        shutil.rmtree(res["workdir"], ignore_errors=True)
    return 0 if res["pass"] else 1


def main(argv=None):
    args = common_args(__doc__).parse_args(argv)
    bin_dir = os.path.abspath(args.bin_dir)
    err = check_bins(bin_dir)
    if err:
        print("chaos: " + err, file=sys.stderr)
        return 1
    workdir, spec, spec_path, res = new_run(args, "local")
    try:
        ref_db, ref_id, res["reference_seconds"] = run_reference(bin_dir, os.path.join(workdir, "reference"),
                                                                 spec_path, args.workers)
        print("chaos(local): reference run completed in %.1f s" % res["reference_seconds"], flush=True)
        cdir = os.path.join(workdir, "chaos")
        os.makedirs(cdir)
        cl = LocalCluster(bin_dir, cdir, spec, os.path.join(cdir, "chaos.db"), free_port(),
                          ["--lease-ms", str(args.lease_ms), "--max-attempts", str(args.max_attempts)])
        cl.coord.start()
        for _ in range(args.workers):
            cl.add_worker()
        nem = Nemesis(cl, random.Random(res["nemesis_seed"]), args.lease_ms,
                      first_interval=paced_interval(res["reference_seconds"]))
        chaos_phase(cl, nem, spec_path, args, res, ref_db, ref_id, MIN_COVERAGE)
    except Exception as e:  # a harness failure is a test failure, with the logs kept
        import traceback
        res["error"] = "%s: %s" % (type(e).__name__, e)
        traceback.print_exc()
    return finish_run(args, res)


if __name__ == "__main__":
    sys.exit(main())
