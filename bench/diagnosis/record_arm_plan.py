#!/usr/bin/python3
"""Record what a diagnosis's plan proposes, on the arm's reference (issue 29's cases): the
step a user takes after `gaitforge diagnose` says which recording would decide.

The plan (`plan.json`, written by a diagnosis that could not decide or by `gaitforge
diagnose plan`) proposes playbacks: one of the case's recordings' rod forces, scaled,
slowed or let go half-way (docs/diagnosis.md, "Plan the experiment that decides"). This
script plays each proposed input on the same reference that made the case (the arm at 12
lumps and 0.25 ms with the case's concealed effect, bench/diagnosis/make_arm_cases.py:
the stand-in for the hardware), disguises it like the case's other recordings (tip only,
noise, marker offsets) and writes a new case: the old one with the proposed recordings
added to its training set. The held-out recordings stay as they were, so the new case is
judged on the same prediction.

    /usr/bin/python3 bench/diagnosis/record_arm_plan.py --case damping-growth-1 \\
        --plan plan.json [--take 1] [--suite tests/diagnosis/robots/continuum_arm]

--plan may also be a run_suite.py result (--json-out): the plan its diagnosis kept.

Writes cases/<case>-planned/ and adds its entry to answers.sealed.json (the same concealed
effect; `planned_from` names the case and the plan's recordings). The concealed values are
read only to drive the reference, as the hardware would carry them; the diagnosis never
sees them.
"""
import argparse
import json
import os
import shutil
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_arm_cases import ROOT, SIM, disguise, simulate  # noqa: E402
from make_cases import read_csv  # noqa: E402

INPUTS = ("rod1.force", "rod2.force", "rod3.force")


def varied_inputs(recording_csv, inputs, out_csv):
    """The recording's rod forces as the plan varies them (workers/tools/sim_plan.cc,
    Varied): time stretched by time_scale, forces scaled, zero from release_at_s on."""
    header, data = read_csv(recording_csv)
    cols = [header.index(name) for name in INPUTS]
    t = data[:, 0] * inputs["time_scale"]
    release = inputs.get("release_at_s")
    with open(out_csv, "w") as f:
        f.write("t," + ",".join(INPUTS) + "\n")
        for k in range(len(t)):
            on = release is None or t[k] < release
            values = [inputs["scale"] * data[k, c] if on else 0.0 for c in cols]
            f.write("%.6f," % t[k] + ",".join("%.9g" % v for v in values) + "\n")


def load_plan(path, case):
    """A plan.json, or a run_suite.py result (--json-out) holding the case's diagnosis with
    the plan it kept."""
    with open(path) as f:
        data = json.load(f)
    if "results" not in data:
        return data
    for r in data["results"]:
        if r.get("case") == case and r.get("plan"):
            return r["plan"]
    sys.exit(f"record_arm_plan: {path} holds no plan of case {case} (its diagnosis asked for none)")


def find_recording(case_dir, case, name):
    for rel in case["train"] + case["held_out"]:
        if os.path.basename(rel) == name or os.path.splitext(os.path.basename(rel))[0] == name:
            return os.path.join(case_dir, rel)
    sys.exit(f"record_arm_plan: the plan plays '{name}', which case {case_dir} does not hold")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--suite", default=os.path.join(ROOT, "tests", "diagnosis", "robots", "continuum_arm"))
    ap.add_argument("--case", required=True)
    ap.add_argument("--plan", required=True,
                    help="plan.json of the case's diagnosis, or run_suite.py's result holding it")
    ap.add_argument("--take", type=int, default=1, help="how many of the proposed recordings (in order)")
    ap.add_argument("--sim", default=SIM)
    args = ap.parse_args()
    case_dir = os.path.join(args.suite, "cases", args.case)
    with open(os.path.join(case_dir, "case.json")) as f:
        case = json.load(f)
    proposed = [c for c in load_plan(args.plan, args.case)["plan"] if c.get("inputs")][: args.take]
    if not proposed:
        sys.exit(f"record_arm_plan: {args.plan} proposes no playback")
    answers_path = os.path.join(args.suite, "answers.sealed.json")
    with open(answers_path) as f:
        answers = json.load(f)
    truth = answers[args.case]
    name = args.case + "-planned"
    out_dir = os.path.join(args.suite, "cases", name)
    shutil.rmtree(out_dir, ignore_errors=True)
    shutil.copytree(case_dir, out_dir)
    added = []
    with tempfile.TemporaryDirectory() as tmp:
        for i, c in enumerate(proposed):
            src = find_recording(case_dir, case, c["inputs"]["from"])
            inputs, raw = os.path.join(tmp, f"in-{i}.csv"), os.path.join(tmp, "raw.csv")
            varied_inputs(src, c["inputs"], inputs)
            simulate(args.sim, inputs, truth["params"], raw)
            rel = f"train/planned-{i + 1}.csv"
            seed = int(np.frombuffer(name.encode(), dtype=np.uint8).sum()) * 10 + i
            disguise(raw, os.path.join(out_dir, rel), seed)
            case["train"].append(rel)
            added.append({"file": rel, "candidate": c["name"], "inputs": c["inputs"]})
    with open(os.path.join(out_dir, "case.json"), "w") as f:
        f.write(json.dumps(case, indent=2) + "\n")
    answers[name] = {**truth, "planned_from": {"case": args.case, "recordings": added}}
    with open(answers_path, "w") as f:
        f.write(json.dumps(answers, indent=2) + "\n")
    print(f"wrote {os.path.relpath(out_dir)}: {len(added)} planned recording(s) added to training")
    return 0


if __name__ == "__main__":
    sys.exit(main())
