#!/usr/bin/python3
"""The arm's gap-finder cases under the protocol a user follows: diagnose; when the
diagnosis keeps a plan (it could not decide, nothing explained the held-out mismatch, or
no recording given parts its named effect from the baseline: docs/diagnosis.md, "A
diagnosis plans by itself"), record the plan's first proposal on the case's reference
(plan_cases.py --kept) and diagnose again with it in training. Which cases get a second
recording is the diagnosis's choice, never the answers'; they are opened only to score.

    /usr/bin/python3 bench/diagnosis/plan_protocol.py [--cases a,b] --json-out OUT.json
        [--suite tests/diagnosis/robots/continuum_arm] [--screening 96] [--full 480]

OUT.json: {"results": [...]} with every diagnosis run (a case and, where it asked, its
"-planned" case), so `tests/diagnosis/run_suite.py --rescore OUT.json` scores either
stage; printed: per case the first verdict, whether it asked, the final verdict.
"""
import argparse
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tests", "diagnosis"))
import run_suite  # noqa: E402


def verdict(r):
    return r.get("error") and "error" or r["verdict"] + " " + "+".join(e["id"] for e in r["effects"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--suite", default=os.path.join(ROOT, "tests", "diagnosis", "robots", "continuum_arm"))
    ap.add_argument("--cases", default="", help="comma separated (default: every case not -planned)")
    ap.add_argument("--bin-dir", default=os.path.join(ROOT, "build", "bin"))
    ap.add_argument("--screening", type=int, default=96)
    ap.add_argument("--full", type=int, default=480)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--as", dest="split", default="train", choices=["train", "held_out"],
                    help="where the recorded proposal goes (plan_cases.py --as)")
    ap.add_argument("--json-out", required=True)
    args = ap.parse_args()
    names = args.cases.split(",") if args.cases else sorted(
        c for c in os.listdir(os.path.join(args.suite, "cases")) if "-planned" not in c)
    results, rows = [], []
    for case in names:
        first = run_suite.diagnose(args.bin_dir, args.suite, case, args.screening, args.full, args.workers)
        results.append(first)
        save(args.json_out, results)
        final = first
        if first.get("plan"):
            # The result just saved holds the plan the diagnosis kept.
            recorded = subprocess.run([sys.executable, os.path.join(HERE, "plan_cases.py"), "--suite",
                                       args.suite, "--case", case, "--results", args.json_out,
                                       "--kept", "--take", "1", "--as", args.split,
                                       "--out-suite", args.suite,
                                       "--bin", args.bin_dir])
            if recorded.returncode != 0:
                rows.append((case, verdict(first), "yes", "not recorded (plan_cases.py failed)"))
                print("%-18s %-40s asked: %-3s -> %s" % rows[-1], flush=True)
                continue
            suffix = "-planned" if args.split == "train" else "-planned-held"
            final = run_suite.diagnose(args.bin_dir, args.suite, case + suffix, args.screening,
                                       args.full, args.workers)
            results.append(final)
        rows.append((case, verdict(first), "yes" if first.get("plan") else "no", verdict(final)))
        print("%-18s %-40s asked: %-3s -> %s" % rows[-1], flush=True)
        save(args.json_out, results)
    return 0


def save(path, results):
    with open(path, "w") as f:
        json.dump({"results": results}, f, indent=1)


if __name__ == "__main__":
    sys.exit(main())
