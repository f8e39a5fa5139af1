#!/usr/bin/python3
"""Scale test (issue 30), correctness only, no timings: 16 emulated workers
(gaitforge-swarm, the real worker's protocol code) run a GA study while 10% of them are
kill -9'd (and come back under new ids) and the coordinator is kill -9'd once mid-run and
restarted on the same port and database. The chaos checker (tests/chaos) then asserts that
every job ended done exactly once, the counts agree, and the result is bit-identical to a
fault-free run by two real gaitforge-workers.

    /usr/bin/python3 tests/scale/scale_test.py --bin-dir build/bin [--workers 16] [--keep]
Exit 0 pass, 1 fail, 77 skip (binaries missing).
"""
import argparse
import os
import shutil
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import swarm_procs  # noqa: E402
from swarm_procs import chaos  # noqa: E402


class CoordinatorKiller:
    """kill -9s the coordinator once, after `after_gens` committed generations, and
    restarts it on the same port and database."""

    def __init__(self, coord, after_gens):
        self.coord, self.after_gens, self.done, self.study_id = coord, after_gens, False, None

    def __call__(self, _swarm):
        if self.done:
            return
        st = chaos.study_status(self.coord.db)
        if st and st["state"] == "running" and st["generations_done"] >= self.after_gens and st["inflight"] > 0:
            self.coord.kill9()
            time.sleep(0.3)
            self.coord.start()
            self.done = True


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin-dir", required=True)
    ap.add_argument("--workers", type=int, default=16)
    ap.add_argument("--keep", action="store_true")
    args = ap.parse_args()
    for b in ("gaitforge-coordinator", "gaitforge-worker", "gaitforge", "gaitforge-swarm"):
        if not os.path.exists(os.path.join(args.bin_dir, b)):
            print("skip: %s not built" % b)
            return 77
    work = tempfile.mkdtemp(prefix="gf-scale-test-")
    spec = chaos.make_spec(seed=30, population=58, generations=12, work_us=0, name="scale-test")
    spec_path = chaos.write_spec(spec, os.path.join(work, "spec.json"))
    ref_db, ref_id, _ = chaos.run_reference(args.bin_dir, os.path.join(work, "ref"), spec_path, workers=2)

    d = os.path.join(work, "swarm")
    os.makedirs(d)
    db = os.path.join(d, "scale.db")
    coord = swarm_procs.start_coordinator(args.bin_dir, d, db, port=chaos.free_port(),
                                          flags=["--lease-ms", "2000", "--max-attempts", "50"])
    killer = CoordinatorKiller(coord, after_gens=4)
    try:
        # Evaluations of ~50 ms (heavy tail) keep 16 workers busy for ~5 s; 10% of the
        # workers die between 0.3 s and 2.3 s in.
        res = swarm_procs.run_swarm(args.bin_dir, d, coord, spec, args.workers, "lognormal:0.05:1",
                                    extra=["--kill-fraction", "0.1", "--kill-from", "0.3",
                                           "--kill-window", "2", "--seed", "30"],
                                    during=killer, timeout=300)
    finally:
        coord.stop()
    check = chaos.run_checker(ref_db, ref_id, db, res["study_ids"][0], spec)
    check.add("swarm: the study completed", res["states"] == ["completed"], str(res["states"]))
    want_kills = round(0.1 * args.workers)
    check.add("faults: %d emulated workers killed" % want_kills, res["kills"] == want_kills,
              "%d kills" % res["kills"])
    check.add("faults: the coordinator was killed once mid-run", killer.done and coord.starts == 2,
              "%d starts" % coord.starts)
    print("\n".join(check.lines()))
    print("swarm: %d accepted, %d duplicates, %d refused, %d lease calls, %d heartbeats" % (
        res["results_accepted"], res["duplicates"], res["refused"], res["lease"]["calls"],
        res["heartbeat"]["calls"]))
    if check.ok and not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    else:
        print("logs and databases in %s" % work)
    print("PASS" if check.ok else "FAIL")
    return 0 if check.ok else 1


if __name__ == "__main__":
    sys.exit(main())
