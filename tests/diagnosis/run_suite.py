#!/usr/bin/python3
"""The gap finder on the shipped concealed cases (tests/diagnosis/cases).

Runs `gaitforge diagnose` on each case, and only afterwards opens the sealed answers
(answers.sealed.json) to score: the verdict and effect named, the fitted magnitude against
the concealed one, and the held-out error before and after.

  /usr/bin/python3 tests/diagnosis/run_suite.py [--bin-dir build/bin] [--cases a,b] [--check]
      [--json-out FILE] [--screening N] [--full N] [--suite DIR] [--weighting equal|floor|pooled]

--suite tests/diagnosis/foreign: the cases of an independent simulator
(bench/diagnosis/rig2d.py) with effects in forms of their own; their answers list every
catalog id that counts as right (`accept`).

--check: exit 1 unless every case gets the right verdict and effect, every runner-up
says why it lost, both figures (located.svg, diagnosis.svg) are written and the locating
step finds nothing beyond the noise and the model's numeric spread on the nulls (the ctest
test; meant for this suite, the model's own numerics: on the independent simulator's nulls
the structure differs);
without it the script is the benchmark (confusion matrix, magnitude errors, times).

--rescore A.json,B.json: no diagnosis; score the stored results of earlier runs (their
--json-out files) against this suite's answers, e.g. to print one confusion matrix over
runs made in parts. The verdicts are the stored ones; a case in several files is scored by
its last (a rerun replaces the earlier run).
"""
import argparse
import json
import re
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def spec_text(case_dir, c, screening, full, base="", weighting="", extra=""):
    """The diagnosis spec of a case (its case.json as `c`). It names the files by absolute
    path; the case name stays out of it. A case's own `spec` fields (the arm's error and
    channels) come in unless the command line sets them (`extra`, `base`, `weighting`)."""
    lines = ["name: case", "seed: 1", f"robot: {c.get('robot', 'caterpillar')}",
             "training: [" + ", ".join(os.path.join(case_dir, p) for p in c["train"]) + "]",
             "held_out: [" + ", ".join(os.path.join(case_dir, p) for p in c["held_out"]) + "]",
             f"screening_evaluations: {screening}", f"full_evaluations: {full}"]
    given = {line.split(":")[0] for line in extra.splitlines()}
    given |= {"base_parameters"} if base else set()
    given |= {"weighting"} if weighting else set()
    for key, value in c.get("spec", {}).items():
        if key not in given:
            lines.append(f"{key}: {json.dumps(value)}")  # JSON is YAML
    if weighting:
        lines.append(f"weighting: {weighting}")
    if base:  # NAME:LO:HI,... -> base_parameters, fitted in every study
        lines.append("base_parameters:")
        for item in base.split(","):
            name, lo, hi = item.split(":")
            lines.append(f"  - {{name: {name}, lo: {float(lo)!r}, hi: {float(hi)!r}}}")
    return "\n".join(lines) + "\n"


def stage_seconds(log):
    """Each diagnosis stage's wall time, as the coordinator logged it ("diagnosis NAME:
    STAGE took S s"; services/diagnosis/pipeline.cc); {} without the log."""
    out = {}
    if os.path.exists(log):
        with open(log) as f:
            for m in re.finditer(r"diagnosis \S+: (\w+) took ([0-9.]+) s", f.read()):
                out[m.group(1)] = out.get(m.group(1), 0.0) + float(m.group(2))
    return out


def diagnose(bin_dir, suite, case, screening, full, workers, base="", weighting="", extra=""):
    """`gaitforge diagnose` on a case; `extra`: more spec lines (e.g. `candidates: [...]`)."""
    case_dir = os.path.join(suite, "cases", case)
    with open(os.path.join(case_dir, "case.json")) as f:
        c = json.load(f)
    with tempfile.TemporaryDirectory(prefix=f"gf-diag-{case}-") as d:
        spec = os.path.join(d, "diagnosis.yaml")
        with open(spec, "w") as f:
            f.write(spec_text(case_dir, c, screening, full, base, weighting, extra) + extra)
        t0 = time.monotonic()
        r = subprocess.run([os.path.join(bin_dir, "gaitforge"), "diagnose", spec, "--json",
                            "--workers", str(workers)], cwd=d, capture_output=True, text=True)
        wall = time.monotonic() - t0
        if r.returncode != 0:
            return {"case": case, "error": r.stderr[-2000:], "wall_seconds": wall}
        out = json.loads(r.stdout)
        out["case"] = case
        out["wall_seconds"] = wall
        out["stage_seconds"] = stage_seconds(os.path.join(d, "runs", "logs", "coordinator.log"))
        # The report's figures (located.svg, diagnosis.svg): listed, written, SVG.
        out["figures_missing"] = [name for name in ("located.svg", "diagnosis.svg")
                                  if not any(p.endswith("/" + name) and _is_svg(os.path.join(d, p))
                                             for p in out.get("figures", []))]
        # The plan the diagnosis kept (docs/diagnosis.md, "A diagnosis plans by itself"): what
        # it asks to record next (bench/diagnosis/plan_cases.py --kept --results RESULT.json).
        plan = os.path.join(d, out.get("dir", ""), "plan.json")
        if out.get("dir") and os.path.exists(plan):
            with open(plan) as f:
                out["plan"] = json.load(f)
        return out


def load_results(paths):
    """Stored --json-out results by case, in order; a later file's result of a case
    replaces an earlier one's (a rerun)."""
    by_case = {}
    for path in paths:
        with open(path) as f:
            for r in json.load(f)["results"]:
                by_case.pop(r["case"], None)
                by_case[r["case"]] = r
    return by_case


def _is_svg(path):
    try:
        with open(path) as f:
            return "<svg" in f.read(4096)
    except OSError:
        return False


def structure_only(result, accept, truth):
    """Whether a found or ambiguous verdict names, beside what the case accepts, only the
    model's own structure (the report's `structural` parts: friction, contact softness and
    creep, resolution, damping, stiffness, mass; effects::IsStructural); for an ambiguous
    verdict every explanation it leaves open must be structure only. Issue 25 counts that as
    no physics beyond the structural set: not a wrong name on a null, a miss on an effect
    case, unless the case's truth is itself structural (then another structure is a wrong
    name). Reports from before session 40 carry no `structural`: False."""
    verdict = result.get("verdict")
    if verdict not in ("found", "ambiguous") or not result.get("effects"):
        return False
    named = result["effects"] if verdict == "ambiguous" else result["effects"][:1]
    if any("structural" not in e for e in named):
        return False
    seen = {i for e in result.get("effects", []) + result.get("runners_up", [])
            for i in e.get("structural", [])}
    if truth != "none" and any(a in seen for a in accept):
        return False
    return all(p in e["structural"] for e in named for p in e["id"].split("+")
               if p not in accept)


def score(result, answer):
    truth = answer["effect"]
    # Foreign cases (effects in other forms than the catalog's) may accept more than one id.
    accept = answer.get("accept") or [truth]
    if "error" in result:
        return {"case": result["case"], "truth": truth, "predicted": "error", "correct": False,
                "exact": False}
    verdict = result["verdict"]
    named = [e["id"] for e in result.get("effects", [])]
    if verdict == "none":
        predicted = "none"
    elif verdict == "ambiguous":
        predicted = "ambiguous:" + "|".join(named)
    else:
        predicted = named[0]
    correct = (truth == "none" and verdict == "none") or \
              (truth != "none" and verdict == "found" and
               any(a in named[0].split("+") for a in accept))
    # exact: the effect alone, not inside a pair.
    exact = truth != "none" and verdict == "found" and named[0] in accept
    s = {"case": result["case"], "truth": truth, "predicted": predicted, "correct": correct,
         "exact": exact, "structure": (result.get("structure") or {}).get("id", ""),
         "structure_only": not correct and structure_only(result, accept, truth),
         "wall_seconds": round(result["wall_seconds"], 1)}
    # Where it showed: does the baseline miss beyond the noise and its numeric spread?
    # (located.beyond_spread, since session 10; None in older results.)
    s["beyond_spread"] = (result.get("located") or {}).get("beyond_spread")
    errs = result.get("errors", {})
    if "held_out" in errs and errs.get("baseline_held_out"):
        s["held_out_reduction"] = 1 - errs["held_out"] / errs["baseline_held_out"]
    if truth != "none" and verdict == "found":
        fitted = result["effects"][0]["params"]
        rel, covers = [], []
        for name, value in answer.get("params", {}).items():
            if name in fitted and value:
                rel.append(abs(fitted[name]["value"] - value) / abs(value))
            # The reported range (docs/diagnosis.md): a null end is open on that side.
            rng = fitted.get(name, {}).get("range")
            if rng:
                covers.append((rng[0] is None or rng[0] <= value) and
                              (rng[1] is None or value <= rng[1]))
        if rel:
            s["magnitude_relative_error"] = max(rel)
        if covers:
            s["range_covers_truth"] = all(covers)
    return s


OUTCOMES = ["alone", "in a pair", "ambiguous, truth named", "ambiguous, not", "wrong name",
            "structure only", "none", "error"]


def outcome(s, answer):
    """The confusion matrix's column for one scored case."""
    accept = answer.get("accept") or [s["truth"]]
    p = s["predicted"]
    if p == "error":
        return "error"
    if p == "none":
        return "none"
    if p.startswith("ambiguous:"):
        named = [i for n in p[len("ambiguous:"):].split("|") for i in n.split("+")]
        if any(a in named for a in accept):
            return "ambiguous, truth named"
        return "structure only" if s.get("structure_only") else "ambiguous, not"
    if s["exact"]:
        return "alone"
    if s["correct"]:
        return "in a pair"
    return "structure only" if s.get("structure_only") else "wrong name"


def confusion(scores, answers):
    """Truth (effect id, or none) x outcome, counts."""
    m = {}
    for s in scores:
        row = m.setdefault(s["truth"], {o: 0 for o in OUTCOMES})
        row[outcome(s, answers[s["case"]])] += 1
    return m


def print_confusion(m):
    print("confusion: truth x verdict (alone / in a pair: the truth named; wrong name: an effect "
          "that is not; structure: only the model's own structure named)")
    print(f"{'truth':22s} " + " ".join(f"{o:>10s}" for o in
                                      ["alone", "pair", "amb:truth", "amb:other", "wrong",
                                       "structure", "none", "error"]))
    for truth in sorted(m, key=lambda t: (t == "none", t)):
        print(f"{truth:22s} " + " ".join(f"{m[truth][o]:10d}" for o in OUTCOMES))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--bin-dir", default=os.path.join(HERE, "..", "..", "build", "bin"),
                    help="where gaitforge and its servers are (default: build/bin)")
    ap.add_argument("--cases", default="")
    ap.add_argument("--suite", default=HERE,
                    help="directory with cases/ and answers.sealed.json (default: this one; "
                         "tests/diagnosis/foreign: the independent simulator's cases)")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--json-out", default="")
    ap.add_argument("--screening", type=int, default=120)
    ap.add_argument("--full", type=int, default=480)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--base", default="",
                    help="base parameters fitted in every study, NAME:LO:HI,... (default: none)")
    ap.add_argument("--weighting", default="", choices=["", "equal", "floor", "pooled"],
                    help="the spec's weighting of the training recordings (default: the "
                         "diagnosis's own default)")
    ap.add_argument("--structure", default="", choices=["", "off", "first", "joint"],
                    help="the spec's structure stage (docs/diagnosis.md, \"Structure first\"; "
                         "default: the diagnosis's own default)")
    ap.add_argument("--numerics", default="", choices=["", "off", "first"],
                    help="the spec's numerics stage (docs/diagnosis.md, \"Numerics first\"; "
                         "default: the diagnosis's own default)")
    ap.add_argument("--timestep-ms", type=float, default=0,
                    help="the spec's timestep_ms: run the whole diagnosis at this model step "
                         "(default: the robot's own)")
    ap.add_argument("--rescore", default="",
                    help="score stored diagnoses instead of running: --json-out files of earlier "
                         "runs, comma separated (their cases in this suite's answers)")
    a = ap.parse_args()
    a.bin_dir = os.path.abspath(a.bin_dir)  # each diagnosis runs in its own directory
    a.suite = os.path.abspath(a.suite)
    cases = a.cases.split(",") if a.cases else sorted(os.listdir(os.path.join(a.suite, "cases")))
    t0 = time.monotonic()
    if a.rescore:
        results = list(load_results(a.rescore.split(",")).values())
        if a.cases:
            results = [r for r in results if r["case"] in cases]
    else:
        extra = f"structure: {a.structure}\n" if a.structure else ""
        extra += f"numerics: {a.numerics}\n" if a.numerics else ""
        extra += f"timestep_ms: {a.timestep_ms}\n" if a.timestep_ms else ""
        results = [diagnose(a.bin_dir, a.suite, c, a.screening, a.full, a.workers, a.base,
                            a.weighting, extra) for c in cases]
    # Only now: the answers.
    with open(os.path.join(a.suite, "answers.sealed.json")) as f:
        answers = json.load(f)
    unknown = sorted({r["case"] for r in results if r["case"] not in answers})
    if unknown:
        sys.exit(f"run_suite: no answer for {', '.join(unknown)} in "
                 f"{os.path.join(a.suite, 'answers.sealed.json')} (another suite? --suite)")
    scores = [score(r, answers[r["case"]]) for r in results]
    total = time.monotonic() - t0
    effects = [s for s in scores if s["truth"] != "none"]
    nulls = [s for s in scores if s["truth"] == "none"]
    top1 = sum(s["correct"] for s in effects) / len(effects) if effects else None
    exact = sum(s["exact"] for s in effects) / len(effects) if effects else None
    # A false discovery names physics on a null; the model's own structure is not physics
    # left out (structure_only), counted apart.
    fdr = sum(not s["correct"] and not s.get("structure_only") for s in nulls) / len(nulls) \
        if nulls else None
    structure_nulls = sum(bool(s.get("structure_only")) for s in nulls)
    mags = sorted(s["magnitude_relative_error"] for s in scores if "magnitude_relative_error" in s)
    reds = sorted(s["held_out_reduction"] for s in effects if "held_out_reduction" in s)
    covered = [s["range_covers_truth"] for s in scores if "range_covers_truth" in s]
    summary = {"cases": scores, "top1_rate": top1, "top1_exact_rate": exact,
               "false_discovery_rate": fdr, "nulls_structure_only": structure_nulls,
               "median_magnitude_relative_error": mags[len(mags) // 2] if mags else None,
               "median_held_out_reduction": reds[len(reds) // 2] if reds else None,
               "range_coverage": sum(covered) / len(covered) if covered else None,
               "wall_seconds": round(total, 1), "confusion": confusion(scores, answers)}
    print(f"{'case':14s} {'truth':22s} {'predicted':34s} {'ok':3s} {'|mag err|':>9s} {'held-out':>9s} "
          f"{'s':>6s}  structure")
    for s in scores:
        mag = f"{100 * s['magnitude_relative_error']:.0f}%" if "magnitude_relative_error" in s else "-"
        red = f"-{100 * s['held_out_reduction']:.0f}%" if "held_out_reduction" in s else "-"
        print(f"{s['case']:14s} {s['truth']:22s} {s['predicted']:34s} {'yes' if s['correct'] else 'NO':3s} "
              f"{mag:>9s} {red:>9s} {s.get('wall_seconds', 0):6.0f}  {s.get('structure', '')}")
    print_confusion(summary["confusion"])
    print(f"top-1 correct-effect rate {top1} (alone, not in a pair: {exact}), "
          f"false-discovery rate on nulls {fdr} (structure only on {structure_nulls}), "
          f"median magnitude error {summary['median_magnitude_relative_error']}, "
          f"median held-out reduction {summary['median_held_out_reduction']}, "
          f"truth inside the reported range {sum(covered)} of {len(covered)}, {total:.0f} s")
    located = [s for s in scores if s.get("beyond_spread") is not None]
    if located:
        print("located beyond the noise and the numeric spread: "
              f"{sum(s['beyond_spread'] for s in located if s['truth'] != 'none')} of "
              f"{sum(s['truth'] != 'none' for s in located)} effect cases, "
              f"{sum(s['beyond_spread'] for s in located if s['truth'] == 'none')} of "
              f"{sum(s['truth'] == 'none' for s in located)} nulls")
    for r in results:
        if "error" in r:
            print(f"{r['case']}: diagnose failed:\n{r['error']}", file=sys.stderr)
    if a.json_out:
        with open(a.json_out, "w") as f:
            json.dump({"summary": summary, "results": results}, f, indent=1)
    # The report says why every runner-up lost (the named ones excepted; stored results
    # from before session 6 have no reasons).
    unexplained = [f"{r.get('case', '?')}: {u['id']}" for r in ([] if a.rescore else results)
                   for u in r.get("runners_up", [])
                   if not u.get("why_not") and u["id"] not in {e["id"] for e in r.get("effects", [])}]
    if unexplained:
        print("runners-up without a reason: " + ", ".join(unexplained), file=sys.stderr)
    no_figures = [f"{r['case']}: {', '.join(r['figures_missing'])}"
                  for r in ([] if a.rescore else results) if r.get("figures_missing")]
    if no_figures:
        print("figures missing: " + "; ".join(no_figures), file=sys.stderr)
    # Every named effect's magnitude comes with its range (not stored before session 8).
    no_range = [f"{r['case']}: {e['id']}" for r in ([] if a.rescore else results)
                for e in r.get("effects", [])
                if not any("range" in p for n, p in e["params"].items()
                           if not n.startswith("nuisance."))]
    if no_range:
        print("named effects without a range: " + ", ".join(no_range), file=sys.stderr)
    # The locating step must not call the model's own spread a mismatch: on these nulls
    # (the model's numerics; not the independent simulator's, which differs in structure)
    # it must find nothing beyond it. (An effect case may be within it: effects that barely
    # change the travel show only in the finer calibration error.)
    # Unknown counts as wrong here: a null must be shown to be within the spread.
    mislocated = [s["case"] for s in scores
                  if s["truth"] == "none" and s.get("beyond_spread") is not False]
    if mislocated and a.check and not a.rescore:
        print("located beyond the numeric spread on a null, or not against it: "
              + ", ".join(mislocated), file=sys.stderr)
    if a.check and (unexplained or no_figures or no_range or
                    (mislocated and not a.rescore) or not all(s["correct"] for s in scores)):
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
