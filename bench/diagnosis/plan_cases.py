#!/usr/bin/python3
"""The experiment that decides, closed on concealed cases: for a diagnosed case of a robot
suite (bench/diagnosis/make_robot_cases.py, make_arm_cases.py), take the recordings that
would separate the diagnosis's explanations (the plan the diagnosis kept, --kept, or a
new one from `gaitforge diagnose plan`), record them on the case's own reference (the
sealed answer's effect and numerics: the stand-in for the real robot running the proposed
experiment; for the independent builds' suites, tests/diagnosis/foreign and foreign-mujoco,
that build with its own form of the effect), and write a new case that trains on the old
recordings plus the proposed ones and holds out the same (--as held_out: holds them out
too, CASE-planned-held; on the MuJoCo suite only that decided, foreign-mujoco/README.md).
Then diagnose it as any case (tests/diagnosis/run_suite.py --cases CASE-planned);
bench/diagnosis/plan_protocol.py does both for a whole suite.

    /usr/bin/python3 bench/diagnosis/plan_cases.py --suite tests/diagnosis/robots/walker \\
        --case anisotropic-1 --results tests/diagnosis/robots/results/walker-h05b-session22.json \\
        --timestep-ms 0.5 [--propose 2] [--random 12] [--out-suite DIR]
    /usr/bin/python3 bench/diagnosis/plan_cases.py --suite tests/diagnosis/robots/continuum_arm \\
        --case null-2 --results RESULT.json --kept --take 1 --out-suite tests/diagnosis/robots/continuum_arm

The report is the case's entry in --results (run_suite.py --json-out, which keeps the plan
a diagnosis made as its "plan"). The new case goes to --out-suite (default: a temporary
suite, printed) as cases/CASE-planned, with its answer (and `planned_from`: the case and the
proposals recorded) in that suite's answers.sealed.json; the plan itself as plan.json in
it. Deterministic: each planned recording's noise is seeded by the new case's name.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_arm_cases  # noqa: E402
import make_foreign_cases  # noqa: E402
from make_cases import read_csv  # noqa: E402
from make_robot_cases import ROBOTS, disguise, simulate, overrides_text  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "diagnosis"))
from run_suite import spec_text  # noqa: E402


def seed_of(name, k):
    return int(np.frombuffer(name.encode(), dtype=np.uint8).sum()) * 10 + k


def report_of(results, case):
    with open(results) as f:
        for r in json.load(f)["results"]:
            if r.get("case") == case:
                return r
    sys.exit(f"plan_cases: no result for case {case} in {results}")


def plan(bin_dir, suite, case, report, a, work):
    """Runs gaitforge diagnose plan on the case's spec; returns the plan's JSON."""
    case_dir = os.path.join(suite, "cases", case)
    with open(os.path.join(case_dir, "case.json")) as f:
        c = json.load(f)
    extra = f"timestep_ms: {a.timestep_ms}\n" if a.timestep_ms else ""
    spec = os.path.join(work, "diagnosis.yaml")
    with open(spec, "w") as f:  # the budgets do not matter to a plan
        f.write(spec_text(os.path.abspath(case_dir), c, 60, 240, extra=extra) + extra)
    report_path = os.path.join(work, "diagnosis.json")
    with open(report_path, "w") as f:
        json.dump(report, f)
    cmd = [os.path.join(bin_dir, "gaitforge"), "diagnose", "plan", spec, "--report", report_path,
           "--propose", str(a.propose), "--random", str(a.random), "--workers", str(a.workers)]
    words = subprocess.run(cmd, capture_output=True, text=True)
    if words.returncode != 0:
        sys.exit(f"plan_cases: {' '.join(cmd)} failed: {words.stderr.strip()}")
    print(words.stdout, end="")
    with open(os.path.join(work, "plan.json")) as f:
        return c, json.load(f)


def varied_inputs(src_csv, inputs, out_csv):
    """A playback's recorded inputs (its rod columns) varied as the plan says (plan.h,
    InputVariant): scaled, time stretched, all 0 from release_at_s on."""
    header, data = read_csv(src_csv)
    cols = [j for j, h in enumerate(header) if h.startswith("rod")]
    t = data[:, 0] * inputs["time_scale"]
    release = inputs["release_at_s"] if inputs["release_at_s"] is not None else float("inf")
    with open(out_csv, "w") as f:
        f.write(",".join(["t"] + [header[j] for j in cols]) + "\n")
        for i in range(len(t)):
            vals = [inputs["scale"] * data[i, j] if t[i] < release else 0.0 for j in cols]
            f.write(f"{t[i]:.6f}," + ",".join(f"{v:.9g}" for v in vals) + "\n")


def record(bin_dir, robot, answer, proposal, dst, seed, case_dir=""):
    """The proposed gait (or varied playback) recorded on the case's reference, disguised as
    the suite's are."""
    if proposal.get("inputs"):  # the arm: make_arm_cases' reference and disguise
        # A diagnosis's own plan names its local copies of the recordings HASH-NAME.
        name = re.sub(r"^[0-9a-f]{16}-", "", proposal["inputs"]["from"])
        src = next((os.path.join(case_dir, split, name) for split in ("train", "held_out")
                    if os.path.exists(os.path.join(case_dir, split, name))), None)
        if src is None:
            sys.exit(f"plan_cases: the plan plays '{name}', which case {case_dir} does not hold")
        with tempfile.TemporaryDirectory() as tmp:
            inputs, raw = os.path.join(tmp, "in.csv"), os.path.join(tmp, "raw.csv")
            varied_inputs(src, proposal["inputs"], inputs)
            make_arm_cases.simulate(os.path.join(bin_dir, "gaitforge-sim"), inputs, answer["params"], raw)
            make_arm_cases.disguise(raw, dst, seed)
        return
    build = make_foreign_cases.build_of(answer)
    if build:  # an independent build (rig2d, MuJoCo): its own form of the concealed effect
        make_foreign_cases.record_gait(build, proposal["gene_values"], answer["rig_effects"], dst,
                                       seed, settle=0, cycles=proposal["cycles"])
        return
    spec = dict(ROBOTS[robot], settle=0, cycles=proposal["cycles"])
    genes = ",".join(repr(g) for g in proposal["gene_values"])
    sets = ",".join(x for x in (answer["reference"], overrides_text(answer["params"])) if x)
    with tempfile.TemporaryDirectory() as tmp:
        raw = os.path.join(tmp, "raw.csv")
        simulate(os.path.join(bin_dir, "gaitforge-sim"), robot, spec, genes, sets, raw)
        disguise(raw, dst, seed, ROBOTS[robot].get("record", ()))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--suite", required=True)
    ap.add_argument("--case", required=True)
    ap.add_argument("--results", required=True, help="run_suite.py --json-out holding the case")
    ap.add_argument("--kept", action="store_true",
                    help="record the plan the diagnosis kept (the result's plan) instead of planning anew")
    ap.add_argument("--take", type=int, default=0, help="record only the first N proposals (0: all)")
    ap.add_argument("--timestep-ms", type=float, default=0, help="the diagnosis's timestep_ms")
    ap.add_argument("--propose", type=int, default=2)
    ap.add_argument("--random", type=int, default=12)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--as", dest="split", default="train", choices=["train", "held_out"],
                    help="where the recorded proposals go: training (fitted, the default) or "
                         "held out (they decide: the fits' predictions of them are compared); "
                         "the new case is CASE-planned or CASE-planned-held")
    ap.add_argument("--out-suite", default="")
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "bin"))
    a = ap.parse_args()
    with open(os.path.join(a.suite, "answers.sealed.json")) as f:
        answer = json.load(f)[a.case]
    case_dir = os.path.join(a.suite, "cases", a.case)
    report = report_of(a.results, a.case)
    with open(os.path.join(case_dir, "case.json")) as f:
        c = json.load(f)
    if a.kept:
        if not report.get("plan"):
            sys.exit(f"plan_cases: the diagnosis of {a.case} in {a.results} kept no plan")
        p = report["plan"]
    else:
        with tempfile.TemporaryDirectory() as work:
            c, p = plan(a.bin, a.suite, a.case, report, a, work)
    proposals = p["plan"][: a.take] if a.take > 0 else p["plan"]
    out_suite = a.out_suite or tempfile.mkdtemp(prefix="gf-plan-suite-")
    new_case = a.case + ("-planned" if a.split == "train" else "-planned-held")
    new_dir = os.path.join(out_suite, "cases", new_case)
    shutil.rmtree(new_dir, ignore_errors=True)
    for split in ("train", "held_out"):
        for rel in c[split]:
            os.makedirs(os.path.dirname(os.path.join(new_dir, rel)), exist_ok=True)
            for ext in ("", ".json"):
                shutil.copy(os.path.join(case_dir, rel + ext), os.path.join(new_dir, rel + ext))
    with open(os.path.join(new_dir, "plan.json"), "w") as f:
        json.dump(p, f, indent=1)
    added = []
    for k, proposal in enumerate(proposals):
        rel = f"{a.split}/planned-{k + 1}.csv"
        record(a.bin, c["robot"], answer, proposal, os.path.join(new_dir, rel), seed_of(new_case, k),
               case_dir)
        c[a.split].append(rel)
        added.append({"file": rel, "candidate": proposal["name"], "inputs": proposal.get("inputs")})
    with open(os.path.join(new_dir, "case.json"), "w") as f:
        f.write(json.dumps(c, indent=2) + "\n")
    answers_path = os.path.join(out_suite, "answers.sealed.json")
    answers = json.load(open(answers_path)) if os.path.exists(answers_path) else {}
    answers[new_case] = {**answer, "planned_from": {"case": a.case, "recordings": added}}
    with open(answers_path, "w") as f:
        f.write(json.dumps(answers, indent=2) + "\n")
    print(f"wrote {os.path.relpath(new_dir)}: {len(c['train'])} training recordings, "
          f"{len(c['held_out'])} held out ({len(added)} planned, {a.split})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
