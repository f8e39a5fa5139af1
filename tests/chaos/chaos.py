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

# --------------------------------------------------------------------------------------
# Processes

_ALL_PROCS = []  # every Popen this harness started; atexit ends the ones still alive


def _cleanup_procs():
    for p in _ALL_PROCS:
        if p.poll() is None:
            try:
                os.kill(p.pid, signal.SIGCONT)
                os.kill(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
    for p in _ALL_PROCS:
        try:
            p.wait(timeout=5)
        except Exception:
            pass


atexit.register(_cleanup_procs)


def _on_signal(signum, _frame):
    sys.exit(128 + signum)  # runs atexit handlers


for _s in (signal.SIGTERM, signal.SIGHUP):
    signal.signal(_s, _on_signal)


def spawn(argv, log_path, prefix=None):
    """Starts argv (after `prefix`, e.g. ['ip', 'netns', 'exec', NS]), output to log_path."""
    full = list(prefix or []) + list(argv)
    with open(log_path, "ab") as log:
        log.write(("\n### %s harness: start %s\n" % (time.strftime("%H:%M:%S"), " ".join(full))).encode())
        log.flush()
        p = subprocess.Popen(full, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                             start_new_session=True)
    _ALL_PROCS.append(p)
    return p


def alive(p):
    return p is not None and p.poll() is None


def signal_proc(p, sig):
    try:
        os.kill(p.pid, sig)
        return True
    except ProcessLookupError:
        return False


def stop_proc(p, timeout=15.0):
    """SIGCONT + SIGTERM, then SIGKILL after `timeout`. Returns the exit code."""
    if p is None:
        return None
    if p.poll() is None:
        signal_proc(p, signal.SIGCONT)
        signal_proc(p, signal.SIGTERM)
        try:
            p.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            signal_proc(p, signal.SIGKILL)
            p.wait()
    return p.returncode


def kill9(p):
    signal_proc(p, signal.SIGKILL)
    p.wait()


def free_port(host="127.0.0.1"):
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((host, 0))
        return s.getsockname()[1]


def wait_port_file(path, proc, timeout=30.0):
    """The port the coordinator wrote to `path`, or None if it exited / timed out."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        try:
            with open(path) as f:
                text = f.read().strip()
            if text:
                return int(text)
        except (FileNotFoundError, ValueError):
            pass
        if proc.poll() is not None:
            return None
        time.sleep(0.02)
    return None


class Coordinator:
    """A gaitforge-coordinator that can be kill -9'd and restarted on the same port and DB."""

    def __init__(self, bin_dir, workdir, db, listen_host, port, flags, prefix=None, name="coordinator"):
        self.bin_dir, self.workdir, self.db = bin_dir, workdir, db
        self.host, self.port, self.flags, self.prefix = listen_host, port, list(flags), prefix
        self.log = os.path.join(workdir, name + ".log")
        self.port_file = os.path.join(workdir, name + ".port")
        self.proc = None
        self.starts = 0

    @property
    def target(self):
        return "%s:%d" % (self.host, self.port)

    def start(self, timeout=30.0):
        """Starts it; retries while the port is still taken. Returns seconds to serving."""
        t0 = time.monotonic()
        end = t0 + timeout
        exits, prev = 0, None
        while True:
            try:
                os.unlink(self.port_file)
            except FileNotFoundError:
                pass
            argv = [os.path.join(self.bin_dir, "gaitforge-coordinator"), "--listen",
                    "%s:%d" % (self.host, self.port), "--db", self.db, "--port-file",
                    self.port_file] + self.flags
            self.proc = spawn(argv, self.log, self.prefix)
            got = wait_port_file(self.port_file, self.proc, max(1.0, end - time.monotonic()))
            if got is not None:
                if self.port == 0:
                    self.port = got
                self.starts += 1
                return time.monotonic() - t0
            last = self.last_log_line()
            exits = exits + 1 if self.proc.poll() is not None and last == prev else 0
            prev = last
            if time.monotonic() >= end or exits >= 10:
                raise RuntimeError("coordinator did not start within %.0f s; last log line: %s (see %s)" % (
                    time.monotonic() - t0, last, self.log))
            if self.proc.poll() is None:
                kill9(self.proc)
            time.sleep(0.2)  # e.g. exit 2: port not yet free, or the DB lock still held

    def last_log_line(self):
        try:
            with open(self.log, errors="replace") as f:
                lines = [x.strip() for x in f if x.strip() and not x.startswith("### ")]
            return lines[-1] if lines else ""
        except OSError:
            return ""

    def kill9(self):
        if alive(self.proc):
            kill9(self.proc)

    def stop(self):
        return stop_proc(self.proc)


def start_worker(bin_dir, workdir, target, worker_id, threads=1, prefix=None):
    argv = [os.path.join(bin_dir, "gaitforge-worker"), "--coordinator", target, "--threads",
            str(threads), "--worker-id", worker_id]
    return spawn(argv, os.path.join(workdir, worker_id + ".log"), prefix)


def submit(bin_dir, target, spec_path, prefix=None, timeout=60.0):
    argv = list(prefix or []) + [os.path.join(bin_dir, "gaitforge"), "--coordinator", target,
                                 "--timeout", "20", "submit", spec_path]
    end = time.monotonic() + timeout
    while True:
        r = subprocess.run(argv, capture_output=True, text=True)
        if r.returncode == 0:
            return r.stdout.strip().split()[-1]
        if time.monotonic() > end or r.returncode not in (4, 5):
            raise RuntimeError("submit failed (exit %d): %s" % (r.returncode, r.stderr.strip()))
        time.sleep(0.3)


# --------------------------------------------------------------------------------------
# Spec and the database (always read-only here)


def make_spec(seed=20240517, population=50, generations=20, work_us=40000, name="chaos-rastrigin"):
    return {"name": name, "seed": seed, "engine": "ga", "population": population,
            "generations": generations,
            "objective": {"name": "analytic.rastrigin", "params": {"work_us": work_us}},
            "ga": {"elite": 10, "mutation_rate": 0.1}}


def write_spec(spec, path):
    with open(path, "w") as f:
        json.dump(spec, f)
    return path


def ro_connect(db):
    con = sqlite3.connect("file:%s?mode=ro" % db, uri=True, timeout=5)
    con.execute("PRAGMA busy_timeout = 5000")
    return con


def study_status(db, study_id=None):
    """(state, generations_done, in-flight evaluated rows) or None while unreadable."""
    try:
        con = ro_connect(db)
        try:
            q = "SELECT study_id, state, generations_done FROM studies"
            row = (con.execute(q + " WHERE study_id = ?", (study_id,)) if study_id
                   else con.execute(q)).fetchone()
            if row is None:
                return None
            n = con.execute("SELECT COUNT(*) FROM individuals WHERE study_id = ? AND generation = ? "
                            "AND carried = 0", (row[0], row[2])).fetchone()[0]
            return {"study_id": row[0], "state": row[1], "generations_done": row[2], "inflight": n}
        finally:
            con.close()
    except sqlite3.Error:
        return None


def wait_completed(db, study_id, timeout, tick=None, poll=0.1):
    """Polls until the study is not running. tick() runs between polls (the nemesis)."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        st = study_status(db, study_id)
        if st and st["state"] != "running":
            return st
        if tick:
            tick(st)
        time.sleep(poll)
    return study_status(db, study_id)


def _f(x):
    """A REAL column as its exact IEEE bits (None stays None)."""
    return None if x is None else struct.pack("<d", x).hex()


def snapshot(db, study_id):
    """Everything of a study's result that the determinism contract covers, bit-exact."""
    con = ro_connect(db)
    try:
        s = con.execute("SELECT hex(spec), state, generations_total, generations_done, best_fitness, "
                        "mean_fitness, evaluations, error FROM studies WHERE study_id = ?",
                        (study_id,)).fetchone()
        snap = {"study": (s[0], s[1], s[2], s[3], _f(s[4]), _f(s[5]), s[6], s[7])}
        snap["individuals"] = {
            (r[0], r[1]): (r[2], r[3], _f(r[4]), r[5], r[6], r[7], r[8])
            for r in con.execute("SELECT generation, member, hex(genes), valid, fitness, reason, carried, "
                                 "origin_generation, origin_member FROM individuals WHERE study_id = ?",
                                 (study_id,))}
        snap["metrics"] = {
            (r[0], r[1], r[2]): _f(r[3])
            for r in con.execute("SELECT generation, member, name, value FROM metrics WHERE study_id = ?",
                                 (study_id,))}
        snap["generations"] = {
            r[0]: (_f(r[1]), _f(r[2]), _f(r[3]), _f(r[4]), r[5], r[6], r[7])
            for r in con.execute("SELECT generation, best, mean, stddev, diversity, evaluations, invalid, "
                                 "hex(engine_state) FROM generations WHERE study_id = ?", (study_id,))}
        snap["hall_of_fame"] = {
            (r[0], r[1]): (r[2], r[3], r[4], r[5], _f(r[6]))
            for r in con.execute("SELECT generation, rank, origin_generation, origin_member, hex(genes), "
                                 "valid, fitness FROM hall_of_fame WHERE study_id = ?", (study_id,))}
        return snap
    finally:
        con.close()


def fault_counters(db, study_id):
    """Queue counters summed over the generations table (per committing coordinator process)."""
    con = ro_connect(db)
    try:
        r = con.execute("SELECT COALESCE(SUM(leases),0), COALESCE(SUM(lease_expiries),0), "
                        "COALESCE(SUM(duplicates),0), COALESCE(SUM(backups),0), "
                        "COALESCE(SUM(poisoned),0), COALESCE(SUM(evaluations),0) "
                        "FROM generations WHERE study_id = ?", (study_id,)).fetchone()
        return dict(zip(("leases", "lease_expiries", "duplicates", "backups", "poisoned",
                         "evaluations"), r))
    finally:
        con.close()


# --------------------------------------------------------------------------------------
# The checker


class Check:
    def __init__(self):
        self.items = []  # (name, ok, detail)

    def add(self, name, ok, detail=""):
        self.items.append((name, bool(ok), detail))
        return ok

    @property
    def ok(self):
        return all(ok for _, ok, _ in self.items)

    def lines(self):
        return ["  [%s] %s%s" % ("ok" if ok else "FAIL", name, (": " + detail) if detail else "")
                for name, ok, detail in self.items]


def _diff(name, a, b, limit=5):
    """Human-readable differences of two dicts (reference a, chaos b)."""
    out = []
    for k in sorted(set(a) | set(b), key=repr):
        if a.get(k) != b.get(k):
            out.append("%s %r: reference %r, chaos %r" % (name, k, a.get(k), b.get(k)))
            if len(out) >= limit:
                out.append("...")
                break
    return out


def check_invariants(db, study_id, spec, check, label="chaos"):
    """Jepsen-style invariants on one database. Returns the number of poisoned jobs."""
    P, G = spec["population"], spec["generations"]
    elite = spec.get("ga", {}).get("elite", 10)
    con = ro_connect(db)
    try:
        ic = [r[0] for r in con.execute("PRAGMA integrity_check")]
        check.add("%s: PRAGMA integrity_check" % label, ic == ["ok"], ",".join(ic)[:200])
        fk = con.execute("PRAGMA foreign_key_check").fetchall()
        check.add("%s: PRAGMA foreign_key_check" % label, not fk, "%d violations" % len(fk) if fk else "")
        nstudies = con.execute("SELECT COUNT(*) FROM studies").fetchone()[0]
        st = con.execute("SELECT state, generations_done, generations_total, evaluations, error "
                         "FROM studies WHERE study_id = ?", (study_id,)).fetchone()
        check.add("%s: study completed" % label, st and st[0] == "completed" and st[1] == G and st[2] == G,
                  "state=%s generations_done=%s/%s error=%r nstudies=%d" % (st[0], st[1], st[2], st[4], nstudies))
        # Every job ended done or poisoned: P rows for each of G generations, none elsewhere.
        per_gen = dict(con.execute("SELECT generation, COUNT(*) FROM individuals WHERE study_id = ? "
                                   "GROUP BY generation", (study_id,)).fetchall())
        missing = {g: P - per_gen.get(g, 0) for g in range(G) if per_gen.get(g, 0) != P}
        extra = sorted(g for g in per_gen if not 0 <= g < G)
        total = sum(per_gen.values())
        bad_members = con.execute("SELECT COUNT(*) FROM individuals WHERE study_id = ? AND "
                                  "(member < 0 OR member >= ?)", (study_id, P)).fetchone()[0]
        poisoned = con.execute("SELECT COUNT(*) FROM individuals WHERE study_id = ? AND valid = 0 AND "
                               "reason LIKE 'poisoned%'", (study_id,)).fetchone()[0]
        # Done = a result from a worker (valid, or invalid with a reason), or carried.
        undone = con.execute(
            "SELECT COUNT(*) FROM individuals WHERE study_id = ? AND NOT ("
            " (carried = 1) OR (reason LIKE 'poisoned%' AND valid = 0) OR"
            " (carried = 0 AND worker_id != '' AND ((valid = 1 AND fitness IS NOT NULL) OR"
            "  (valid = 0 AND reason != ''))))", (study_id,)).fetchone()[0]
        check.add("%s: every job ended done or poisoned" % label,
                  not missing and not extra and not bad_members and not undone and total == P * G,
                  "%d rows = %d x %d (done %d, poisoned %d)%s%s%s" % (
                      total, P, G, total - poisoned, poisoned,
                      "; missing per generation %s" % missing if missing else "",
                      "; rows beyond the study: generations %s" % extra if extra else "",
                      "; %d rows neither done nor poisoned" % undone if undone else ""))
        # Exactly one accepted result per key (the PK makes a second row impossible; check it
        # anyway, and that no carried row stands in for an evaluation or the reverse).
        dup = con.execute("SELECT COUNT(*) FROM (SELECT generation, member FROM individuals WHERE "
                          "study_id = ? GROUP BY generation, member HAVING COUNT(*) > 1)",
                          (study_id,)).fetchone()[0]
        carried_per_gen = dict(con.execute("SELECT generation, SUM(carried) FROM individuals WHERE "
                                           "study_id = ? GROUP BY generation", (study_id,)).fetchall())
        want_carried = {g: (0 if g == 0 else elite) for g in range(G)}
        bad_carried = {g: carried_per_gen.get(g, 0) for g in range(G)
                       if carried_per_gen.get(g, 0) != want_carried[g]}
        orphan = con.execute(
            "SELECT COUNT(*) FROM individuals c LEFT JOIN individuals o ON o.study_id = c.study_id AND "
            "o.generation = c.origin_generation AND o.member = c.origin_member WHERE c.study_id = ? AND "
            "c.carried = 1 AND (o.member IS NULL OR o.carried = 1 OR o.genes != c.genes OR "
            "o.valid != c.valid OR o.fitness IS NOT c.fitness)", (study_id,)).fetchone()[0]
        check.add("%s: exactly one accepted result per key" % label, dup == 0 and not bad_carried and orphan == 0,
                  "duplicate keys %d, generations with a wrong carried count %s, carried rows not "
                  "matching their origin %d" % (dup, bad_carried or "none", orphan))
        # Evaluations counted == distinct keys evaluated.
        distinct = con.execute("SELECT COUNT(*) FROM (SELECT DISTINCT generation, member FROM individuals "
                               "WHERE study_id = ? AND carried = 0)", (study_id,)).fetchone()[0]
        gen_sum = con.execute("SELECT COALESCE(SUM(evaluations),0) FROM generations WHERE study_id = ?",
                              (study_id,)).fetchone()[0]
        gen_bad = con.execute(
            "SELECT COUNT(*) FROM generations g WHERE g.study_id = ? AND (g.evaluations != (SELECT COUNT(*) "
            "FROM individuals i WHERE i.study_id = g.study_id AND i.generation = g.generation AND i.carried = 0)"
            " OR g.invalid != (SELECT COUNT(*) FROM individuals i WHERE i.study_id = g.study_id AND "
            "i.generation = g.generation AND i.valid = 0))", (study_id,)).fetchone()[0]
        ngen = con.execute("SELECT COUNT(*) FROM generations WHERE study_id = ?", (study_id,)).fetchone()[0]
        expect = P + (G - 1) * (P - elite)
        check.add("%s: evaluations counted == distinct keys" % label,
                  st and st[3] == distinct == gen_sum == expect and gen_bad == 0 and ngen == G,
                  "studies.evaluations %s, distinct evaluated keys %d, sum(generations.evaluations) %d, "
                  "expected %d; generations rows %d, rows with wrong counts %d" % (
                      st[3] if st else None, distinct, gen_sum, expect, ngen, gen_bad))
        hof_bad = con.execute("SELECT COUNT(*) FROM (SELECT generation, COUNT(*) n FROM hall_of_fame WHERE "
                              "study_id = ? GROUP BY generation HAVING n != ?)",
                              (study_id, max(elite, 1))).fetchone()[0]
        hof_gens = con.execute("SELECT COUNT(DISTINCT generation) FROM hall_of_fame WHERE study_id = ?",
                               (study_id,)).fetchone()[0]
        check.add("%s: hall of fame complete" % label, hof_bad == 0 and hof_gens == G,
                  "%d generations, %d with a wrong entry count" % (hof_gens, hof_bad))
        return poisoned
    finally:
        con.close()


def check_equal(ref_db, ref_id, db, study_id, check):
    a, b = snapshot(ref_db, ref_id), snapshot(db, study_id)
    for part in ("study", "individuals", "metrics", "generations", "hall_of_fame"):
        if part == "study":
            diffs = [] if a[part] == b[part] else ["studies row: reference %r, chaos %r" % (a[part], b[part])]
        else:
            diffs = _diff(part, a[part], b[part])
        n = 1 if part == "study" else len(a[part])
        check.add("bit-identical to the fault-free run: %s" % part, not diffs,
                  ("%d rows" % n) if not diffs else "; ".join(diffs))


def run_checker(ref_db, ref_id, db, study_id, spec):
    check = Check()
    check_invariants(ref_db, ref_id, spec, check, label="reference")
    poisoned = check_invariants(db, study_id, spec, check)
    check_equal(ref_db, ref_id, db, study_id, check)
    if poisoned:
        check.add("no job poisoned (max-attempts is high, poisoning depends on timing)", False,
                  "%d poisoned: the bit-exact comparison cannot hold for them" % poisoned)
    return check


def log_summary(workdir):
    """Counts of warnings/errors in the coordinator logs and the workers' exit lines."""
    out = {"coordinator_warn": 0, "coordinator_error": 0, "worker_exit_lines": [], "worker_refused": 0,
           "worker_report_failed": 0, "worker_unreachable": 0}
    for name in sorted(os.listdir(workdir)):
        if not name.endswith(".log"):
            continue
        with open(os.path.join(workdir, name), errors="replace") as f:
            for line in f:
                if name.startswith("coordinator"):
                    if " warn " in line or " warning " in line:
                        out["coordinator_warn"] += 1
                    if " error " in line or " critical " in line:
                        out["coordinator_error"] += 1
                else:
                    if " exits: " in line:
                        out["worker_exit_lines"].append(line.strip().split("] ", 1)[-1])
                    if "report refused" in line:
                        out["worker_refused"] += 1
                    if "report failed" in line:
                        out["worker_report_failed"] += 1
                    if "unreachable" in line:
                        out["worker_unreachable"] += 1
    return out


# --------------------------------------------------------------------------------------
# Runs


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
    """

    PLAN = ["kill_coordinator", "kill_worker", "isolate_worker", "partition_restart", "kill_worker",
            "kill_coordinator", "isolate_worker", "kill_worker", "kill_coordinator"]
    WEIGHTS = {"kill_worker": 4, "kill_coordinator": 2, "isolate_worker": 2, "partition_restart": 1}
    ISOLATE = "worker_stops_past_lease"  # its name in self.counts
    ISOLATE_VERB = ("SIGSTOP", "SIGCONT")

    def __init__(self, cluster, rng, lease_ms, interval=(1.0, 2.0)):
        self.c, self.rng, self.lease_ms, self.interval = cluster, rng, lease_ms, interval
        self.t0 = time.monotonic()
        self.next_at = self.t0 + rng.uniform(*interval)
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

    def wait_mid_generation(self, timeout=3.0):
        """Waits (bounded) until the generation in flight has some but not all of its results."""
        P, elite = self.c.spec["population"], self.c.spec["ga"]["elite"]
        end = time.monotonic() + timeout
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

    def tick(self, _st=None):
        now = time.monotonic()
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
        self.next_at = time.monotonic() + self.rng.uniform(*self.interval)

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
        nem = Nemesis(cl, random.Random(res["nemesis_seed"]), args.lease_ms)
        chaos_phase(cl, nem, spec_path, args, res, ref_db, ref_id, MIN_COVERAGE)
    except Exception as e:  # a harness failure is a test failure, with the logs kept
        import traceback
        res["error"] = "%s: %s" % (type(e).__name__, e)
        traceback.print_exc()
    return finish_run(args, res)


if __name__ == "__main__":
    sys.exit(main())
