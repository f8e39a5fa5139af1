#!/usr/bin/python3
"""bench/diagnosis/plan_cases.py --kept on a copy of one arm case: the plan a diagnosis
kept (in a run_suite.py result) is played on the reference with the rod forces varied as it
says (scaled, let go), added to training, and the case keeps its held-out recordings; a
result without a plan, and a plan that plays a recording the case lacks, are refused
naming what is missing; and a MuJoCo case's plan recorded on that build and held out
(--as held_out). Runs the real gaitforge-sim and MuJoCo build (about 3 s).

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


def copy_case(src_suite, case, tmp):
    """A suite in `tmp` holding only `case` and its answer; returns (suite, answer)."""
    suite = os.path.join(tmp, "suite")
    shutil.copytree(os.path.join(src_suite, "cases", case), os.path.join(suite, "cases", case))
    with open(os.path.join(src_suite, "answers.sealed.json")) as f:
        answer = json.load(f)[case]
    with open(os.path.join(suite, "answers.sealed.json"), "w") as f:
        json.dump({case: answer}, f)
    return suite, answer


def check_foreign(bin_dir, check):
    """A MuJoCo case's kept plan (gait A, 2 cycles from rest) recorded on the MuJoCo build
    with the case's own hose, and held out (--as held_out): training stays as it was, the
    recording starts from the robot at rest (its markers 32 mm apart, not all at 0)."""
    suite_src, case = os.path.join(HERE, "foreign-mujoco"), "mujoco-hose"
    genes = [0.066346, 0.922283, 0.998848, 0.914959, 0.0137641, 0.0273953, 0.32784, 0.361167,
             0.106263, 0.40778, 0.362727, 0.304114, 0.354446]
    with tempfile.TemporaryDirectory() as tmp:
        suite, answer = copy_case(suite_src, case, tmp)
        results = os.path.join(tmp, "r.json")
        with open(results, "w") as f:
            json.dump({"results": [{"case": case, "plan": {"plan": [
                {"name": "gait-a.csv, longer", "gene_values": genes, "cycles": 2}]}}]}, f)
        r = subprocess.run([sys.executable, SCRIPT, "--suite", suite, "--case", case, "--results",
                            results, "--kept", "--take", "1", "--as", "held_out", "--out-suite",
                            suite, "--bin", bin_dir], capture_output=True, text=True,
                           env={**os.environ, "GAITFORGE_BIN": bin_dir})
        check(r.returncode == 0, f"plan_cases on MuJoCo failed: {r.stderr}")
        out = os.path.join(suite, "cases", case + "-planned-held")
        with open(os.path.join(out, "case.json")) as f:
            c = json.load(f)
        check(c["train"] == ["train/gait-a.csv", "train/gait-b.csv"], f"training set {c['train']}")
        check(c["held_out"] == ["held_out/gait-c.csv", "held_out/planned-1.csv"],
              f"held out {c['held_out']}")
        header, got = read(os.path.join(out, "held_out", "planned-1.csv"))
        gap = got[0, header.index("m2.x")] - got[0, header.index("m1.x")]
        check(0.02 < gap < 0.045, f"first row's m2.x - m1.x = {gap}: not the robot at rest")
        check(got[-1, 0] - got[0, 0] > 0.6, "not two cycles of 0.354 s")
        with open(os.path.join(suite, "answers.sealed.json")) as f:
            planned = json.load(f)[case + "-planned-held"]
        check(planned["rig_effects"] == answer["rig_effects"], f"answer {planned}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin-dir", default=os.path.join(ROOT, "build", "bin"))
    args = ap.parse_args()
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    with tempfile.TemporaryDirectory() as tmp:
        suite, answer = copy_case(SUITE, CASE, tmp)
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
    check_foreign(args.bin_dir, check)
    for f in failures:
        print("FAIL:", f)
    print("plan_cases_test:", "ok" if not failures else f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
