"""Process and database helpers of the chaos harness (chaos.py, netns.py, bench/resilience.py):
starting, signalling and reaping the real binaries, specs, and read-only views of the results
database."""
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


def spawn(argv, log_path, prefix=None, new_session=True):
    """Starts argv (after `prefix`, e.g. ['ip', 'netns', 'exec', NS]), output to log_path,
    in a session of its own unless `new_session` is False."""
    full = list(prefix or []) + list(argv)
    with open(log_path, "ab") as log:
        log.write(("\n### %s harness: start %s\n" % (time.strftime("%H:%M:%S"), " ".join(full))).encode())
        log.flush()
        p = subprocess.Popen(full, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                             start_new_session=new_session)
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
                return int(text.split()[0])  # second line: the metrics port
        except (FileNotFoundError, ValueError):
            pass
        if proc.poll() is not None:
            return None
        time.sleep(0.02)
    return None


class Coordinator:
    """A gaitforge-coordinator that can be kill -9'd and restarted on the same port and DB."""

    def __init__(self, bin_dir, workdir, db, listen_host, port, flags, prefix=None, name="coordinator",
                 new_session=True):
        self.bin_dir, self.workdir, self.db = bin_dir, workdir, db
        self.new_session = new_session
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
            self.proc = spawn(argv, self.log, self.prefix, self.new_session)
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

