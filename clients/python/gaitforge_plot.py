#!/usr/bin/python3
"""Figures of gaitforge studies, drawn with matplotlib.

  fitness   best and mean fitness per generation (with the population's spread) from the
            JSON of `gaitforge history ID --json`.

Usage:
  gaitforge_plot.py fitness --history HISTORY.json --out FILE.svg [--title TEXT]

The `gaitforge plot ID` command calls this script; run it under /usr/bin/python3 (Debian's
python3-matplotlib).
"""
import argparse
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def fitness(args):
    with open(args.history) as f:
        gens = json.load(f).get("generations", [])
    if not gens:
        print(f"gaitforge_plot: {args.history}: no generation committed yet", file=sys.stderr)
        return 2
    g = [int(x.get("generation", 0)) for x in gens]
    best = [float(x.get("best", math.nan)) for x in gens]
    mean = [float(x.get("mean", math.nan)) for x in gens]
    sd = [float(x.get("stddev", 0.0)) for x in gens]
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.fill_between(g, [m - s for m, s in zip(mean, sd)], [m + s for m, s in zip(mean, sd)],
                    color="tab:blue", alpha=0.15, label="mean ± sd")
    ax.plot(g, mean, color="tab:blue", label="mean")
    ax.plot(g, best, color="tab:red", label="best")
    ax.set_xlabel("generation")
    ax.set_ylabel(args.ylabel)
    ax.set_title(args.title)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(args.out)
    print(args.out)
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    sub = ap.add_subparsers(dest="figure", required=True)
    f = sub.add_parser("fitness", help="best and mean fitness per generation")
    f.add_argument("--history", required=True, help="output of `gaitforge history ID --json`")
    f.add_argument("--out", required=True, help="image file (.svg or .png)")
    f.add_argument("--title", default="fitness per generation")
    f.add_argument("--ylabel", default="fitness (higher is better)")
    f.set_defaults(run=fitness)
    args = ap.parse_args()
    return args.run(args)


if __name__ == "__main__":
    sys.exit(main())
