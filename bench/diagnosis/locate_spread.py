#!/usr/bin/python3
"""How the locating step reads each case against the model's numeric spread
(docs/diagnosis.md step 3): for every case of a suite, the uncalibrated model (the cases'
time offset, -0.02 s) is simulated on the training and on the held-out recordings under the
six numeric variants, and gaitforge_locate.py --variants says whether each set shows a
mismatch beyond the noise and that spread. A benchmark of the locating step alone: no fit.

  /usr/bin/python3 bench/diagnosis/locate_spread.py [--bin-dir build/bin]
      [--suite tests/diagnosis] [--cases a,b] [--json-out FILE]

Prints per case: the truth (read after locating), training and held-out beyond the spread
(yes/no) and how many sds of the variants' travel each recording's travel lies off.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tests", "diagnosis"))
import locate_test  # noqa: E402  (the same evaluation and locate calls as the test)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--bin-dir", default=os.path.join(ROOT, "build", "bin"))
    ap.add_argument("--suite", default=os.path.join(ROOT, "tests", "diagnosis"))
    ap.add_argument("--cases", default="")
    ap.add_argument("--json-out", default="")
    a = ap.parse_args()
    locate_test.BIN = os.path.abspath(a.bin_dir)
    locate_test.HERE = os.path.abspath(a.suite)
    cases = a.cases.split(",") if a.cases else sorted(os.listdir(os.path.join(a.suite, "cases")))
    rows = []
    with tempfile.TemporaryDirectory(prefix="gf-locate-bench-") as tmp:
        for case in cases:
            with open(os.path.join(a.suite, "cases", case, "case.json")) as f:
                c = json.load(f)
            row = {"case": case}
            for part in ("train", "held_out"):
                evals = locate_test.evaluate(case, os.path.join(tmp, part), tuple(c[part]))
                r, got = locate_test.locate(evals, os.path.join(tmp, f"{case}-{part}.json"))
                if r.returncode != 0:
                    row[part] = {"error": r.stderr[-500:]}
                    continue
                row[part] = {"beyond_spread": got["beyond_spread"],
                             "recorded_sds": {os.path.basename(s["file"]):
                                              s["numeric_spread"]["recorded_sds"]
                                              for s in got["slices"]["recordings"]},
                             "summary": got["summary"]}
            rows.append(row)
            print(f"located {case}", file=sys.stderr, flush=True)
    with open(os.path.join(a.suite, "answers.sealed.json")) as f:
        answers = json.load(f)
    print(f"{'case':22s} {'truth':22s} {'train':6s} {'held':6s} recorded travel, sds off the variants' mean")
    for row in rows:
        row["truth"] = answers[row["case"]]["effect"]
        cells = []
        for part in ("train", "held_out"):
            p = row[part]
            cells.append("error" if "error" in p else ("beyond" if p["beyond_spread"] else "within"))
        sds = ", ".join(f"{n} {v:+.1f}" for part in ("train", "held_out")
                        for n, v in row[part].get("recorded_sds", {}).items() if v is not None)
        print(f"{row['case']:22s} {row['truth']:22s} {cells[0]:6s} {cells[1]:6s} {sds}")
    if a.json_out:
        with open(a.json_out, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
