#!/usr/bin/python3
"""Gap-finder cases as another lab's capture would hold them: fewer markers, a lower rate.

Copies shipped cases (tests/diagnosis or tests/diagnosis/foreign) into a new suite
directory, every recording cut to some markers and to a coarser time grid: by default
markers m1, m3 and m6 (x and z) at 50 Hz instead of all six at 100 Hz. The values are the
shipped ones, untouched; rows the source dropped stay dropped. The answers are copied into
the new suite's answers.sealed.json with `derived_from` and the cut. The question: does
the verdict survive a sparser capture (the null silent, the effect still named)?

    /usr/bin/python3 bench/diagnosis/sparse_cases.py --out /tmp/sparse --cases null-a,tether-hose
    /usr/bin/python3 tests/diagnosis/run_suite.py --suite /tmp/sparse

Deterministic (no randomness). Writes nothing into the repository unless --out points there.
"""
import argparse
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "diagnosis"))
from locate_test import cut  # noqa: E402  (the one cutter, tested there)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--suite", default=os.path.join(ROOT, "tests", "diagnosis"),
                    help="the source suite (default: the shipped cases)")
    ap.add_argument("--out", required=True, help="the new suite's directory")
    ap.add_argument("--cases", required=True, help="source cases, comma separated")
    ap.add_argument("--markers", default="m1,m3,m6", help="markers kept (x and z of each)")
    ap.add_argument("--every", type=int, default=2,
                    help="keep the rows on a grid of this many 10 ms intervals (2: 50 Hz)")
    ap.add_argument("--suffix", default="-sparse", help="appended to each case's name")
    a = ap.parse_args()
    with open(os.path.join(a.suite, "answers.sealed.json")) as f:
        answers = json.load(f)
    channels = [f"{m}.{axis}" for m in a.markers.split(",") for axis in ("x", "z")]
    out_answers = {}
    for case in a.cases.split(","):
        if case not in answers:
            print(f"sparse_cases: no case '{case}' in {a.suite}", file=sys.stderr)
            return 2
        src_dir = os.path.join(a.suite, "cases", case)
        dst_case = case + a.suffix
        dst_dir = os.path.join(a.out, "cases", dst_case)
        with open(os.path.join(src_dir, "case.json")) as f:
            spec = json.load(f)
        for rel in spec["train"] + spec["held_out"]:
            os.makedirs(os.path.dirname(os.path.join(dst_dir, rel)), exist_ok=True)
            cut(os.path.join(src_dir, rel), os.path.join(dst_dir, rel), channels, a.every)
        with open(os.path.join(dst_dir, "case.json"), "w") as f:
            json.dump(spec, f, indent=1)
        out_answers[dst_case] = dict(answers[case], derived_from=case,
                                     cut={"channels": channels, "rate_hz": 100 / a.every})
        print(f"{dst_case}: {len(spec['train']) + len(spec['held_out'])} recordings, "
              f"{', '.join(channels)} at {100 / a.every:g} Hz")
    with open(os.path.join(a.out, "answers.sealed.json"), "w") as f:
        json.dump(out_answers, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
