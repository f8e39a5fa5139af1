#!/usr/bin/python3
"""bench/diagnosis/plan_cases.py --kept on a copy of one arm case: the plan a diagnosis
kept (in a run_suite.py result) is played on the reference with the rod forces varied as it
says (scaled, let go), added to training, and the case keeps its held-out recordings; a
result without a plan, and a plan that plays a recording the case lacks, are refused
naming what is missing. Runs the real gaitforge-sim (about 2 s).

    /usr/bin/python3 tests/diagnosis/plan_cases_test.py --bin-dir build/bin
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCRIPT = os.path.join(ROOT, "bench", "diagnosis", "plan_cases.py")
SUITE = os.path.join(HERE, "robots", "continuum_arm")
CASE = "damping-growth-1"


def read(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
    return header, np.loadtxt(path, delimiter=",", skiprows=1)


def plan(source, scale, release):
    """A run_suite.py result whose diagnosis kept a plan with one proposal."""
    inputs = {"from": source, "scale": scale, "time_scale": 1, "release_at_s": release}
    return {"results": [{"case": CASE, "plan": {"plan": [{"name": f"{source}, x{scale}", "inputs": inputs}]}}]}


def run(bin_dir, suite, results):
    return subprocess.run([sys.executable, SCRIPT, "--suite", suite, "--case", CASE, "--results",
                           results, "--kept", "--take", "1", "--out-suite", suite, "--bin", bin_dir],
                          capture_output=True, text=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin-dir", default=os.path.join(ROOT, "build", "bin"))
    args = ap.parse_args()
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    with tempfile.TemporaryDirectory() as tmp:
        suite = os.path.join(tmp, "suite")
        shutil.copytree(os.path.join(SUITE, "cases", CASE), os.path.join(suite, "cases", CASE))
        with open(os.path.join(SUITE, "answers.sealed.json")) as f:
            answer = json.load(f)[CASE]
        with open(os.path.join(suite, "answers.sealed.json"), "w") as f:
            json.dump({CASE: answer}, f)
        plan_path = os.path.join(tmp, "plan.json")
        with open(plan_path, "w") as f:
            # As a diagnosis keeps it: its local copies are named HASH-NAME.
            json.dump(plan("0123456789abcdef-step-a.csv", 0.5, 0.75), f)
        r = run(args.bin_dir, suite, plan_path)
        check(r.returncode == 0, f"plan_cases failed: {r.stderr}")
        out = os.path.join(suite, "cases", CASE + "-planned")
        with open(os.path.join(out, "case.json")) as f:
            case = json.load(f)
        check(case["train"][-1] == "train/planned-1.csv" and len(case["train"]) == 4,
              f"training set {case['train']}")
        check(case["held_out"] == ["held_out/release.csv"], f"held out {case['held_out']}")
        header, got = read(os.path.join(out, "train", "planned-1.csv"))
        _, step = read(os.path.join(suite, "cases", CASE, "train", "step-a.csv"))
        rods = [header.index(f"rod{i}.force") for i in (1, 2, 3)]
        before, after = got[:, 0] < 0.75, got[:, 0] >= 0.75
        check(np.allclose(got[before][:, rods], 0.5 * step[: before.sum()][:, rods]),
              "the forces before the release are not half the recording's")
        check(np.all(got[after][:, rods] == 0), "the forces after the release are not zero")
        check(set(h for h in header if h != "t") == {"tip.x", "tip.y", "tip.z", "rod1.force",
                                                     "rod2.force", "rod3.force"},
              f"channels {header}")
        tip_z = got[:, header.index("tip.z")]
        check(np.ptp(tip_z) > 1e-3, "the tip did not move")
        with open(os.path.join(out, "train", "planned-1.csv.json")) as f:
            check(json.load(f)["robot"] == "continuum_arm", "sidecar robot")
        with open(os.path.join(suite, "answers.sealed.json")) as f:
            planned = json.load(f)[CASE + "-planned"]
        check(planned["effect"] == answer["effect"] and planned["planned_from"]["case"] == CASE,
              f"answer {planned}")
        # A result whose diagnosis asked for nothing.
        with open(plan_path, "w") as f:
            json.dump({"results": [{"case": CASE}]}, f)
        r = run(args.bin_dir, suite, plan_path)
        check(r.returncode != 0 and "kept no plan" in r.stderr, f"no plan: {r.stderr}")
        with open(plan_path, "w") as f:
            json.dump(plan("walk.csv", 1, None), f)
        r = run(args.bin_dir, suite, plan_path)
        check(r.returncode != 0 and "plays 'walk.csv'" in r.stderr, f"bad plan: {r.stderr}")
    for f in failures:
        print("FAIL:", f)
    print("plan_cases_test:", "ok" if not failures else f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
