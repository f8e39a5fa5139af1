#!/usr/bin/python3
"""clients/python/gaitforge_factorial.py against the textbook's formulas.

A balanced 2 x 3 design with 4 replicates: the two-way ANOVA's sums of squares, degrees of
freedom, F and p (scipy's F distribution) computed from their definitions must equal the
report's (statsmodels); Welch's t between the first factor's levels at each level of the
second must equal (m1 - m2) / sqrt(s1^2/n1 + s2^2/n2) with its Welch-Satterthwaite p; a run
far outside its cell is an outlier, an invalid one is counted, and the box plot is drawn.
"""
import json
import math
import os
import sys
import tempfile
import unittest

import numpy as np
from scipy import stats

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "..", "clients", "python"))
import gaitforge_factorial as fact  # noqa: E402

# Response per (a, b) cell, 4 replicates each (a made-up experiment with clear effects).
DATA = {(0, 0): [6.1, 6.4, 5.9, 6.3], (0, 1): [4.6, 4.4, 4.9, 4.7], (0, 2): [3.9, 4.2, 4.0, 4.3],
        (1, 0): [1.1, 1.0, 1.3, 1.2], (1, 1): [1.0, 0.9, 1.1, 0.8], (1, 2): [0.8, 0.9, 0.7, 1.0]}


def design(extra=()):
    members = []
    for (a, b), ys in DATA.items():
        for r, y in enumerate(ys):
            members.append({"genes": [0.6 if a == 0 else 0.8, [0.16, 0.22, 0.28][b], r], "valid": True,
                            "fitness": -y, "metrics": {"cot": y}})
    members.extend(extra)
    return {"factors": [{"name": "gait", "levels": ["trot", "slide"], "genes": [0], "values": [[0.6, 0.8]]},
                        {"name": "speed", "levels": ["0.16", "0.22", "0.28"], "genes": [1],
                         "values": [[0.16, 0.22, 0.28]]},
                        {"name": "repeat", "levels": ["1", "2", "3", "4"], "genes": [2],
                         "values": [[0, 1, 2, 3]]}],
            "members": members}


def run(d):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "d.json")
        with open(path, "w") as f:
            json.dump(d, f)
        assert fact.main(["--data", path, "--metric", "cot", "--out-prefix", os.path.join(tmp, "r")]) == 0
        with open(os.path.join(tmp, "r.json")) as f:
            res = json.load(f)
        svg = os.path.getsize(os.path.join(tmp, "r.svg"))
    return res, svg


class FactorialTest(unittest.TestCase):
    def test_two_way_anova_matches_the_sums_of_squares(self):
        res, svg = run(design())
        self.assertGreater(svg, 1000)
        y = {k: np.array(v) for k, v in DATA.items()}
        grand = np.mean(np.concatenate(list(y.values())))
        a_mean = [np.mean(np.concatenate([y[(a, b)] for b in range(3)])) for a in range(2)]
        b_mean = [np.mean(np.concatenate([y[(a, b)] for a in range(2)])) for b in range(3)]
        n = 4
        ss_a = 3 * n * sum((m - grand) ** 2 for m in a_mean)
        ss_b = 2 * n * sum((m - grand) ** 2 for m in b_mean)
        ss_ab = n * sum((y[(a, b)].mean() - a_mean[a] - b_mean[b] + grand) ** 2 for a in range(2) for b in range(3))
        ss_e = sum(((v - v.mean()) ** 2).sum() for v in y.values())
        df_e = 2 * 3 * (n - 1)
        expected = {"gait": (ss_a, 1), "speed": (ss_b, 2), "gait x speed": (ss_ab, 2)}
        rows = {r["source"]: r for r in res["anova"]}
        self.assertAlmostEqual(rows["residual"]["sum_sq"], ss_e, places=9)
        for name, (ss, df) in expected.items():
            f = (ss / df) / (ss_e / df_e)
            self.assertAlmostEqual(rows[name]["sum_sq"], ss, places=9)
            self.assertEqual(rows[name]["df"], df)
            self.assertAlmostEqual(rows[name]["F"], f, places=6)
            self.assertAlmostEqual(rows[name]["p"], stats.f.sf(f, df, df_e), places=12)

    def test_welch_per_level_matches_its_formula(self):
        res, _ = run(design())
        for b, w in enumerate(res["welch"]):
            x, z = np.array(DATA[(0, b)]), np.array(DATA[(1, b)])
            vx, vz = x.var(ddof=1) / len(x), z.var(ddof=1) / len(z)
            t = (x.mean() - z.mean()) / math.sqrt(vx + vz)
            df = (vx + vz) ** 2 / (vx ** 2 / (len(x) - 1) + vz ** 2 / (len(z) - 1))
            self.assertAlmostEqual(w["t"], t, places=9)
            self.assertAlmostEqual(w["p"], 2 * stats.t.sf(abs(t), df), places=9)
            self.assertEqual(w["n"], [4, 4])

    def test_outliers_and_invalid_runs_are_left_out_and_counted(self):
        extra = [{"genes": [0.8, 0.16, 0], "valid": True, "fitness": -40, "metrics": {"cot": 40.0}},
                 {"genes": [0.6, 0.22, 1], "valid": False, "fitness": 0, "metrics": {}}]
        res, _ = run(design(extra))
        self.assertEqual(res["prep"]["invalid"], 1)
        self.assertEqual(res["prep"]["outliers"], [{"cell": [1, 0, 0], "value": 40.0}])
        self.assertEqual(res["runs"], 24)


if __name__ == "__main__":
    unittest.main()
