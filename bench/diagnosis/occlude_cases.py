#!/usr/bin/python3
"""Gap-finder cases whose markers are occluded at times, as motion capture loses them.

Each occluded case is a copy of a shipped case (made by make_cases.py or
make_foreign_cases.py) in which whole markers disappear for runs of rows: all three cells
of the marker (x, y, z) left empty, or written NaN, for 1 to 15 rows (10 to 150 ms at
100 Hz), about 6% of the marker samples in all. The recording parser bridges such cells in
time (docs/recording-format.md, "Missing cells"); the question these cases ask is whether
the gap finder's verdict survives it: the null must stay silent, the effect must still be
named.

The source case's answer is copied into the suite's answers.sealed.json with the
occlusion added (`occlusion`: cells, fraction, and `derived_from`); make_cases.py keeps
such derived answers when it rewrites the file. Deterministic: numpy's default_rng seeded
per case and file, so the output is the same bytes on every run.

Run from the repository root, after the source cases exist:
    /usr/bin/python3 bench/diagnosis/occlude_cases.py [--suite tests/diagnosis]
"""
import argparse
import json
import os
import shutil
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# (new case, source case, seed)
OCCLUDED = [
    ("null-a-occluded", "null-a", 201),
    ("tether-hose-occluded", "tether-hose", 202),
]
TARGET_FRACTION = 0.06  # of the marker samples
MAX_RUN_ROWS = 15


def occlude(src_csv, dst_csv, seed):
    """Copies src_csv to dst_csv with runs of occluded markers; returns what it hid."""
    rng = np.random.default_rng(seed)
    with open(src_csv) as f:
        lines = f.read().splitlines()
    header = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:]]
    markers = sorted({h.split(".")[0] for h in header[1:]})
    columns = {m: [i for i, h in enumerate(header) if h.startswith(m + ".")] for m in markers}
    hidden = np.zeros((len(rows), len(markers)), dtype=bool)
    target = TARGET_FRACTION * hidden.size
    while hidden.sum() < target:
        m = int(rng.integers(len(markers)))
        start = int(rng.integers(len(rows)))
        length = int(rng.integers(1, MAX_RUN_ROWS + 1))
        hidden[start:start + length, m] = True
    # No marker is hidden in every row (the parser refuses a channel with no value).
    for m in range(len(markers)):
        if hidden[:, m].all():
            hidden[0, m] = False
    cells = 0
    nan_runs = rng.random(hidden.shape) < 0.5  # per row and marker: NaN or empty
    for r, row in enumerate(rows):
        for m, name in enumerate(markers):
            if hidden[r, m]:
                for c in columns[name]:
                    row[c] = "NaN" if nan_runs[r, m] else ""
                    cells += 1
    with open(dst_csv, "w") as f:
        f.write(",".join(header) + "\n")
        for row in rows:
            f.write(",".join(row) + "\n")
    return {"cells": cells, "fraction": round(cells / (len(rows) * (len(header) - 1)), 4)}


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--suite", default=os.path.join(ROOT, "tests", "diagnosis"))
    a = ap.parse_args()
    answers_path = os.path.join(a.suite, "answers.sealed.json")
    with open(answers_path) as f:
        answers = json.load(f)
    for case, source, seed in OCCLUDED:
        src_dir = os.path.join(a.suite, "cases", source)
        dst_dir = os.path.join(a.suite, "cases", case)
        if not os.path.isdir(src_dir) or source not in answers:
            sys.exit(f"occlude_cases: no source case {source} in {a.suite}")
        with open(os.path.join(src_dir, "case.json")) as f:
            spec = json.load(f)
        shutil.rmtree(dst_dir, ignore_errors=True)
        occlusion = {}
        for i, rel in enumerate(spec["train"] + spec["held_out"]):
            os.makedirs(os.path.dirname(os.path.join(dst_dir, rel)), exist_ok=True)
            occlusion[rel] = occlude(os.path.join(src_dir, rel), os.path.join(dst_dir, rel),
                                     seed * 10 + i)
            shutil.copyfile(os.path.join(src_dir, rel + ".json"),
                            os.path.join(dst_dir, rel + ".json"))
        shutil.copyfile(os.path.join(src_dir, "case.json"), os.path.join(dst_dir, "case.json"))
        answer = json.loads(json.dumps(answers[source]))
        answer["derived_from"] = source
        answer["occlusion"] = occlusion
        answers[case] = answer
        print(f"{case}: {source} with occluded markers: " +
              ", ".join(f"{rel} {o['cells']} cells ({100 * o['fraction']:.1f}%)"
                        for rel, o in occlusion.items()))
    with open(answers_path, "w") as f:
        f.write(json.dumps(answers, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
