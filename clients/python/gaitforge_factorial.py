#!/usr/bin/python3
"""A factorial sweep's statistics (docs/engines.md, "Factorial designs"; paper 002's).

Reads the study's design and members (written by `gaitforge plot`/`report`: factors with
their genes and levels, every member's genes, validity and metrics), and for the response
metric:

- data preparation: invalid runs are left out and counted; within each cell of the first
  two factors (the other factors' levels are its replicates) a run more than 4 robust
  standard deviations (1.4826 MAD) from the cell's median is an outlier, left out and
  listed (the paper's |z| > 4 rule, here per run);
- Welch's t-test (scipy.stats.ttest_ind, equal_var=False) between the first factor's
  levels at each level of the second factor, when the first has two levels;
- a two-way ANOVA of the first two factors with their interaction (statsmodels' OLS and
  anova_lm, type II sums of squares), the other factors' levels as replicates;
- a box plot of the response per level of the second factor, one box per level of the
  first (matplotlib).

Writes PREFIX.json (every figure), PREFIX.txt (a summary) and PREFIX.svg (the box plot).
"""
import argparse
import json
import math
import sys


def cells_of(design):
    """Per member: its level index in each factor (None when its genes match no level)."""
    out = []
    for m in design["members"]:
        levels = []
        for f in design["factors"]:
            hit = None
            for li in range(len(f["levels"])):
                if all(abs(m["genes"][g] - f["values"][k][li]) <= 1e-9 * max(1.0, abs(f["values"][k][li]))
                       for k, g in enumerate(f["genes"])):
                    hit = li
                    break
            levels.append(hit)
        out.append(levels)
    return out


def prepare(design, metric):
    """Rows (levels..., value) of the valid members with the metric, outliers left out."""
    import numpy as np
    rows, invalid, missing = [], 0, 0
    for m, levels in zip(design["members"], cells_of(design)):
        if not m["valid"]:
            invalid += 1
            continue
        v = m["fitness"] if metric == "fitness" else m["metrics"].get(metric)
        if v is None or None in levels or not math.isfinite(v):
            missing += 1
            continue
        rows.append((tuple(levels), float(v)))
    outliers = []
    by_cell = {}
    for cell, v in rows:
        by_cell.setdefault(cell[:2], []).append(v)
    kept = []
    for cell, v in rows:
        values = np.array(by_cell[cell[:2]])
        med = np.median(values)
        mad = 1.4826 * np.median(np.abs(values - med))
        if len(values) >= 3 and mad > 0 and abs(v - med) / mad > 4:
            outliers.append({"cell": list(cell), "value": v})
        else:
            kept.append((cell, v))
    return kept, {"invalid": invalid, "without_metric": missing, "outliers": outliers}


def welch(design, rows):
    """Welch's t-test between factor 0's two levels at each level of factor 1."""
    from scipy import stats
    f0, f1 = design["factors"][0], design["factors"][1]
    if len(f0["levels"]) != 2:
        return []
    out = []
    for l1, name in enumerate(f1["levels"]):
        a = [v for c, v in rows if c[0] == 0 and c[1] == l1]
        b = [v for c, v in rows if c[0] == 1 and c[1] == l1]
        if len(a) < 2 or len(b) < 2:
            out.append({"level": name, "n": [len(a), len(b)], "t": None, "p": None})
            continue
        r = stats.ttest_ind(a, b, equal_var=False)
        out.append({"level": name, "n": [len(a), len(b)], "mean": [sum(a) / len(a), sum(b) / len(b)],
                    "t": float(r.statistic), "p": float(r.pvalue)})
    return out


def anova(design, rows):
    """Two-way ANOVA of factors 0 and 1 with interaction (type II)."""
    import pandas
    import statsmodels.api as sm
    from statsmodels.formula.api import ols
    f0, f1 = design["factors"][0], design["factors"][1]
    df = pandas.DataFrame({"a": [f0["levels"][c[0]] for c, _ in rows],
                           "b": [f1["levels"][c[1]] for c, _ in rows],
                           "y": [v for _, v in rows]})
    table = sm.stats.anova_lm(ols("y ~ C(a) * C(b)", data=df).fit(), typ=2)
    names = {"C(a)": f0["name"], "C(b)": f1["name"], "C(a):C(b)": f0["name"] + " x " + f1["name"],
             "Residual": "residual"}
    return [{"source": names[i], "sum_sq": float(r["sum_sq"]), "df": float(r["df"]),
             "F": None if math.isnan(r["F"]) else float(r["F"]),
             "p": None if math.isnan(r["PR(>F)"]) else float(r["PR(>F)"])}
            for i, r in table.iterrows()]


def box_plot(design, rows, metric, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    f0, f1 = design["factors"][0], design["factors"][1]
    fig, ax = plt.subplots(figsize=(max(6, 1.6 * len(f1["levels"])), 4))
    width = 0.8 / len(f0["levels"])
    for l0, name0 in enumerate(f0["levels"]):
        data = [[v for c, v in rows if c[0] == l0 and c[1] == l1] for l1 in range(len(f1["levels"]))]
        pos = [l1 + (l0 - (len(f0["levels"]) - 1) / 2) * width for l1 in range(len(f1["levels"]))]
        b = ax.boxplot(data, positions=pos, widths=0.9 * width, patch_artist=True, manage_ticks=False)
        colour = "C%d" % l0
        for box in b["boxes"]:
            box.set_facecolor(colour)
            box.set_alpha(0.6)
        ax.plot([], [], "s", color=colour, label="%s %s" % (f0["name"], name0))
    ax.set_xticks(range(len(f1["levels"])))
    ax.set_xticklabels(f1["levels"])
    ax.set_xlabel(f1["name"])
    ax.set_ylabel(metric)
    ax.set_title(title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)


def summary(res):
    lines = ["%s by %s: %d runs kept, %d invalid, %d without the metric, %d outliers" % (
        res["metric"], " x ".join(res["factors"]), res["runs"], res["prep"]["invalid"],
        res["prep"]["without_metric"], len(res["prep"]["outliers"]))]
    for w in res["welch"]:
        if w["t"] is not None:
            lines.append("  Welch at %s %s: means %.4g vs %.4g, t %.3f, p %.3g" % (
                res["factors"][1], w["level"], w["mean"][0], w["mean"][1], w["t"], w["p"]))
    for a in res["anova"]:
        if a["F"] is not None:
            lines.append("  ANOVA %s: F(%g) %.4g, p %.3g" % (a["source"], a["df"], a["F"], a["p"]))
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", required=True, help="the design and members (JSON)")
    ap.add_argument("--metric", default="fitness", help="the response: a metric's name, or fitness")
    ap.add_argument("--out-prefix", required=True)
    ap.add_argument("--title", default="")
    args = ap.parse_args(argv)
    with open(args.data) as f:
        design = json.load(f)
    if len(design["factors"]) < 2:
        print("factorial statistics need two factors; the design has %d" % len(design["factors"]),
              file=sys.stderr)
        return 2
    rows, prep = prepare(design, args.metric)
    res = {"metric": args.metric, "factors": [f["name"] for f in design["factors"]], "runs": len(rows),
           "prep": prep, "welch": welch(design, rows), "anova": anova(design, rows)}
    with open(args.out_prefix + ".json", "w") as f:
        json.dump(res, f, indent=1)
    with open(args.out_prefix + ".txt", "w") as f:
        f.write(summary(res))
    box_plot(design, rows, args.metric, args.out_prefix + ".svg", args.title)
    return 0


if __name__ == "__main__":
    sys.exit(main())
