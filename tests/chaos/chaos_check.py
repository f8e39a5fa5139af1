"""The Jepsen-style checker of the chaos harness: invariants of one run's database and
bit-for-bit equality with the fault-free reference."""
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

from chaos_procs import *  # noqa: F401,F403
from chaos_procs import _f  # noqa: F401

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

