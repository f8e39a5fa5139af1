#!/usr/bin/python3
"""Would a new catalog candidate change a stored verdict? Screens one effect on every case.

When an effect joins the catalog (workers/effects), every diagnosis screens it beside the
others, and it can change a verdict only by entering the leaders that are refitted (the
`top` best screening errors, default 3): every fit is its own study, named after its
candidate and seeded by the spec, so the other fits come out bit for bit as before.
This script runs, per case, the diagnosis restricted to that one candidate (the same spec
as run_suite.py otherwise, so its screening fit is the very study a full diagnosis makes),
and compares its screening error with the stored result of that case: the rank it would
take, and whether it would be refitted. Cases where it would must be run again in full.

  /usr/bin/python3 bench/diagnosis/screen_candidate.py --effect damping.scale \\
      --stored tests/diagnosis/results/suite-rescore-session10-20261122.json [--suite DIR]
      [--cases a,b] [--json-out FILE]

--stored: run_suite.py --json-out files, comma separated; a later file's case replaces an
earlier one's. Its screening lists and `refitted_singles` (else the default top, 3) give
the leaders to compare with.
"""
import argparse
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "diagnosis"))
import run_suite  # noqa: E402  (the spec every shipped result was made with)


def screen(bin_dir, suite, case, effect, workers):
    """The diagnosis of `case` with `effect` as its only candidate; its JSON report."""
    out = run_suite.diagnose(bin_dir, suite, case, 120, 480, workers,
                             extra=f"candidates: [{effect}]\ntop: 1\ntry_pairs: false\n")
    if "error" in out:
        sys.exit(f"screen_candidate: {case}: gaitforge diagnose failed: {out['error']}")
    return out


def compare(new, old, effect):
    """Where `effect`'s screening error falls among the stored case's candidates."""
    mine = [s for s in new["screening"] if s["id"] == effect]
    if not mine or mine[0].get("train") is None:
        return {"ok": False}
    err = mine[0]["train"]
    others = sorted(s["train"] for s in old["screening"]
                    if s.get("train") is not None and s["id"] != effect)
    top = old.get("refitted_singles") or 3  # how many were refitted (3: the default top)
    rank = 1 + sum(1 for e in others if e <= err)
    last_leader = others[top - 1] if len(others) >= top else float("inf")
    # The same baseline as stored: the pipeline reproduces the stored run (the comparison
    # with its other screening errors is then exact, not approximate).
    same_base = new["errors"]["baseline_train"] == old["errors"]["baseline_train"]
    return {"ok": True, "train": err, "rank": rank, "of": len(others) + 1, "top": top,
            "baseline_reproduced": same_base,
            "last_leader": last_leader, "refitted": err < last_leader,
            "stored_verdict": old["verdict"],
            "stored_named": [e["id"] for e in old.get("effects", [])]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--effect", required=True, help="the catalog id to screen")
    ap.add_argument("--stored", required=True,
                    help="run_suite.py --json-out files with each case's full diagnosis")
    ap.add_argument("--suite", default=os.path.join(ROOT, "tests", "diagnosis"))
    ap.add_argument("--bin-dir", default=os.path.join(ROOT, "build", "bin"))
    ap.add_argument("--cases", default="", help="only these (default: every stored case)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--json-out", default="")
    args = ap.parse_args()
    args.suite = os.path.abspath(args.suite)  # the spec names the case files from it
    old = {c: r for c, r in run_suite.load_results(args.stored.split(",")).items()
           if "screening" in r}
    cases = [c for c in args.cases.split(",") if c] or sorted(old)
    rows = []
    print(f"{args.effect} screened on {len(cases)} cases (stored leaders: the `top` best)")
    print(f"{'case':22s} {'train mm':>9s} {'rank':>7s} {'last leader':>11s} refitted  stored verdict")
    for case in cases:
        if case not in old:
            sys.exit(f"screen_candidate: {case}: no stored result in --stored")
        new = screen(args.bin_dir, args.suite, case, args.effect, args.workers)
        row = {"case": case, "wall_seconds": new["wall_seconds"], **compare(new, old[case], args.effect)}
        rows.append(row)
        if not row["ok"]:
            print(f"{case:22s} the screening fit failed")
            continue
        named = "+".join(row["stored_named"]) or "-"
        print(f"{case:22s} {1000 * row['train']:9.3f} {row['rank']:3d}/{row['of']:<3d} "
              f"{1000 * row['last_leader']:11.3f} {'YES' if row['refitted'] else 'no':8s} "
              f"{row['stored_verdict']} {named}   ({row['wall_seconds']:.0f} s"
              f"{'' if row['baseline_reproduced'] else '; baseline differs from the stored one'})",
              flush=True)
    entered = [r["case"] for r in rows if r.get("refitted")]
    print(f"enters the refitted leaders on {len(entered)} of {len(rows)} cases"
          + (": " + ", ".join(entered) if entered else ""))
    same = sum(1 for r in rows if r.get("baseline_reproduced"))
    print(f"the stored baseline reproduced bit for bit on {same} of {len(rows)} cases")
    if args.json_out:
        with open(args.json_out, "w") as f:
            json.dump({"effect": args.effect, "rows": rows}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
