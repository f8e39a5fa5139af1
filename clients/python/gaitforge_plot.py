#!/usr/bin/python3
"""Figures of gaitforge studies, drawn with matplotlib.

  fitness      best and mean fitness per generation (with the population's spread) from the
               JSON of `gaitforge history ID --json`.
  paper-gait   paper 000's gait figures from the JSON `gaitforge report` writes:
               gait diagrams of the best gaits (paper 000 Fig. 8), distance per cycle as
               their period is scaled (Fig. 13), and the travelling-wave baseline (Fig. 14).
  calibration  a calibration study's overlays, errors and distance ratios (`gaitforge report`).
  diagnosis    the gap finder's held-out errors and overlays (gaitforge_diagnosis_figure.py).
  tracking     a tracking study's path and tip under each controller, and their errors over
               time (gaitforge_tracking_figure.py; `gaitforge report` on robot.tracking).
  sweep        a sweep study's grid as a heat map over its two most finely gridded genes (best
               over the others), with the Nelder-Mead searches' points and the path of the
               best so far (paper 001's figures; `gaitforge plot` writes the data).

Usage:
  gaitforge_plot.py fitness --history HISTORY.json --out FILE.svg [--title TEXT]
  gaitforge_plot.py paper-gait --report REPORT.json --out-prefix PREFIX
  gaitforge_plot.py calibration --report CALIBRATION.json --out-prefix PREFIX
  gaitforge_plot.py diagnosis --report DIAGNOSIS.json --out FILE.svg
  gaitforge_plot.py sweep --data SWEEP.json --out FILE.svg [--title TEXT]
  gaitforge_plot.py tracking --run LABEL=TICKS.csv [--run ...] --out FILE.svg [--title TEXT]

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


ACTUATORS = ["T1", "T2", "T3", "B1", "B2", "B3"]


def on_windows(a, d):
    """Phase intervals in [0, 1) where an actuator is ON: [a, d), wrapping when d < a."""
    a, d = a % 1.0, d % 1.0
    if a == d:
        return []
    if a < d:
        return [(a, d - a)]
    return [(a, 1.0 - a), (0.0, d)]


def gait_diagrams(report, out):
    gaits = report["gaits"]
    fig, axes = plt.subplots(len(gaits), 1, figsize=(7, 1.9 * len(gaits) + 0.4), squeeze=False)
    for ax, gait in zip(axes[:, 0], gaits):
        genes = gait["genes"]
        for j in range(6):
            ax.broken_barh(on_windows(genes[j], genes[6 + j]), (5 - j - 0.35, 0.7),
                           color="tab:red" if j < 3 else "tab:blue")
        ax.set_yticks(range(6))
        ax.set_yticklabels(ACTUATORS[::-1])
        ax.set_xlim(0, 1)
        ax.set_ylim(-0.6, 5.6)
        ax.grid(axis="x", alpha=0.3)
        ax.set_title(f"rank {gait['rank']}: {100 * gait['fitness']:.2f} cm/cycle, "
                     f"T = {genes[12]:.3f} s (from generation {gait['generation']})", fontsize=9)
    axes[-1, 0].set_xlabel("phase of the gait period")
    fig.suptitle("best gaits: actuators ON (cf. paper 000 Fig. 8)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out)


def period_sweep(report, out):
    fig, ax = plt.subplots(figsize=(7, 4))
    marks = {0.5: ("s", "h/2"), 0.25: ("^", "h/4")}
    for gait in report["gaits"]:
        pts = [p for p in gait["period_sweep"] if p["valid"]]
        line, = ax.plot([p["scale"] for p in pts], [100 * p["distance_per_cycle_m"] for p in pts],
                        marker="o", ms=3, label=f"rank {gait['rank']} (T = {gait['genes'][12]:.2f} s)")
        # The same gait at its own period with a finer step (older reports have none): how
        # much of its travel survives numerically irrelevant changes.
        checks = gait.get("timestep_check", [])
        if checks:
            h = checks[0]["timestep_s"]
            for c in checks[1:]:
                r = c["result"][0] if c["result"] else None
                if not r or not r["valid"]:
                    continue
                m = marks.get(round(c["timestep_s"] / h, 3), ("x", ""))[0]
                ax.plot([1.0], [100 * r["distance_per_cycle_m"]], ls="none", marker=m, ms=7,
                        mfc="none", color=line.get_color())
    for m, name in marks.values():
        ax.plot([], [], ls="none", marker=m, mfc="none", color="grey",
                label=f"at period 1: timestep {name}")
    ax.axvline(1.0, color="grey", ls="--", lw=1)
    ax.set_xscale("log", base=2)
    ax.set_xlabel("period / evolved period")
    ax.set_ylabel("distance per cycle (cm), mean of 10 cycles")
    ax.set_title("period sweep of the best gaits (cf. paper 000 Fig. 13)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out)


def wave(report, out):
    """The travelling-wave baseline: every intuitive wave shape over its periods (older
    reports have one unnamed wave); the best shape in colour, the others grey."""
    shapes = {}
    for p in report["wave"]:
        if p["valid"]:
            shapes.setdefault(p.get("shape", "travelling wave"), []).append(p)
    fig, ax = plt.subplots(figsize=(7, 4))
    best = None
    for pts in shapes.values():
        top = max(pts, key=lambda p: p["distance_per_cycle_m"])
        if best is None or top["distance_per_cycle_m"] > best["distance_per_cycle_m"]:
            best = top
    for name, pts in shapes.items():
        is_best = best is not None and name == best.get("shape", "travelling wave")
        ax.plot([p["period_s"] for p in pts], [100 * p["distance_per_cycle_m"] for p in pts],
                marker="o" if is_best else None, ms=3, lw=1.5 if is_best else 0.8,
                color="tab:green" if is_best else "0.7", zorder=3 if is_best else 2,
                label=f"wave: {name}" if is_best else None)
    if len(shapes) > 1:
        ax.plot([], [], color="0.7", lw=0.8, label=f"{len(shapes) - 1} other wave shapes")
    if best is not None:
        ax.plot([best["period_s"]], [100 * best["distance_per_cycle_m"]], "k*", ms=10, zorder=4,
                label=f"best wave: {100 * best['distance_per_cycle_m']:.2f} cm at "
                      f"T = {best['period_s']:.2f} s")
    if report["gaits"]:
        g = report["gaits"][0]
        ax.axhline(100 * g["fitness"], color="tab:red", ls="--",
                   label=f"best evolved gait: {100 * g['fitness']:.2f} cm")
    ax.set_xlabel("period T (s)")
    ax.set_ylabel("distance per cycle (cm), mean of 10 cycles")
    ax.set_title("travelling-wave baseline (cf. paper 000 Fig. 14)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out)


def paper_gait(args):
    with open(args.report) as f:
        report = json.load(f)
    for name, draw in (("gaits", gait_diagrams), ("period-sweep", period_sweep), ("wave", wave)):
        out = f"{args.out_prefix}-{name}.svg"
        draw(report, out)
        print(out)
    return 0


def read_csv(path):
    """Columns as lists; occluded (empty or NaN) cells bridged as gaitforge_locate does."""
    import gaitforge_locate
    return {h: v.tolist() for h, v in gaitforge_locate.read_csv(path).items()}


def interp(xs, ys, x):
    import bisect
    i = bisect.bisect_left(xs, x)
    if i <= 0:
        return ys[0]
    if i >= len(xs):
        return ys[-1]
    f = (x - xs[i - 1]) / (xs[i] - xs[i - 1])
    return ys[i - 1] + f * (ys[i] - ys[i - 1])


def aligned(real, sim_path, channel, shift_s):
    """Simulated channel at the recorded times (+ the fit's time shift), its constant offset
    to the recording removed, as the error does."""
    sim = read_csv(sim_path)
    s = [interp(sim["t"], sim[channel], t + shift_s) for t in real["t"]]
    off = sum(r - x for r, x in zip(real[channel], s)) / len(s)
    return [x + off for x in s]


def overlay_channels(report, recording):
    """Up to four channels to overlay: the study's compared channels (its channels option);
    else, for markers, the first and last markers' x and a middle and the last marker's z
    (travel and lift); else the recording's first four channels."""
    chosen = [c for c in report.get("channels", "").split(",") if c]
    if not chosen:
        xs = [c for c in recording if c.endswith(".x")]
        zs = [c for c in recording if c.endswith(".z")]
        if xs and zs:
            chosen = [xs[0], xs[-1], zs[(len(zs) - 1) // 2], zs[-1]]
        else:
            chosen = [c for c in recording if c != "t"]
    return list(dict.fromkeys(chosen))[:4]


# The Savitzky-Golay second derivative of the acceleration error (9 samples, cubic;
# workers/objectives/acceleration_error.h), NaN where the window does not fit.
SG_WEIGHTS = [28, 7, -8, -17, -20, -17, -8, 7, 28]


def second_derivative(x, dt):
    h = len(SG_WEIGHTS) // 2
    out = [float("nan")] * len(x)
    for k in range(h, len(x) - h):
        out[k] = sum(w * x[k + i - h] for i, w in enumerate(SG_WEIGHTS)) / 462 / dt ** 2
    return out


def overlay_grid(sets, channels, transform, unit, title, out):
    """One row per recording, one column per channel: the recorded channel (black), the
    model before the fit (dashed) and after it (solid), at the recorded times plus the fit's
    time shift with the mean offset removed, each through transform(x, dt)."""
    fig, axes = plt.subplots(len(sets), len(channels), figsize=(3.2 * len(channels), 2.4 * len(sets)),
                             squeeze=False)
    for row, (kind, before, after) in enumerate(sets):
        real = read_csv(before["file"])
        dt = real["t"][1] - real["t"][0]
        for col, ch in enumerate(channels):
            ax = axes[row, col]
            if ch not in real:
                ax.set_visible(False)
                continue
            ax.plot(real["t"], transform(real[ch], dt), color="k", lw=1.2, label="recorded")
            for res, color, name in ((before, "tab:blue", "before"), (after, "tab:red", "after")):
                if res.get("sim"):
                    shift = res["metrics"].get("time_shift_s_0", 0.0) + res.get("time_offset_s", 0.0)
                    ax.plot(real["t"], transform(aligned(real, res["sim"], ch, shift), dt),
                            color=color, lw=0.9, ls="--" if name == "before" else "-",
                            label=f"model {name} fit")
            ax.set_title(f"{kind} {row}: {ch}{unit}", fontsize=8)
            ax.tick_params(labelsize=7)
            if row == len(sets) - 1:
                ax.set_xlabel("t (s)", fontsize=8)
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(out)
    print(out)


def accelerations(args, sets, channels):
    """Recorded and simulated accelerations of the compared channels (the error's filter on
    both), before and after the fit: what error = acceleration compares."""
    overlay_grid(sets, channels, second_derivative, "'' (m/s^2)",
                 "recorded vs simulated accelerations (Savitzky-Golay, 9 samples), before and "
                 "after the fit (cf. paper 004's estimation)", f"{args.out_prefix}-accelerations.svg")
    return 0


def calibration(args):
    with open(args.report) as f:
        rep = json.load(f)
    train_b, train_a = rep["train_before"]["recordings"], rep["train_after"]["recordings"]
    held_b, held_a = rep["held_out_before"]["recordings"], rep["held_out_after"]["recordings"]
    sets = [("train", b, a) for b, a in zip(train_b, train_a)] + \
           [("held-out", b, a) for b, a in zip(held_b, held_a)]
    channels = overlay_channels(rep, read_csv(sets[0][1]["file"]) if sets else {})
    overlay_grid(sets, channels, lambda x, dt: x, "",
                 "recorded vs simulated channels, before and after the fit "
                 "(cf. paper 000 Figs. 11, 12; paper 003 Fig. 5)", f"{args.out_prefix}-overlays.svg")

    def err(rs):
        vals = [r["metrics"].get("error", float("nan")) for r in rs if r["valid"]]
        return sum(vals) / len(vals) if vals else float("nan")
    acceleration = any("acceleration_fitness" in r["metrics"] for _, b, a in sets for r in (b, a))
    fig, ax = plt.subplots(figsize=(6, 3.6))
    labels = ["training", "held-out"]
    before = [err(train_b), err(held_b)]
    after = [err(train_a), err(held_a)]
    # Paper 004's F = 1 - error for the acceleration error; else the error x 1000.
    show = (lambda v: 1 - v) if acceleration else (lambda v: 1000 * v)
    x = range(len(labels))
    ax.bar([i - 0.2 for i in x], [show(v) for v in before], 0.4, label="before (the robot's descriptor)")
    ax.bar([i + 0.2 for i in x], [show(v) for v in after], 0.4, label="after the fit")
    ax.set_xticks(list(x))
    ax.set_xticklabels(labels)
    ax.set_ylabel("paper 004's F = 1 - |a_sim - a_rec| / |a_rec|" if acceleration else
                  "error x 1000 (mm or mrad; relative for error = stats)")
    ax.set_title("calibration %s before and after" % ("fitness F" if acceleration else "error"),
                 fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    out = f"{args.out_prefix}-errors.svg"
    fig.savefig(out)
    print(out)
    if acceleration:
        return accelerations(args, sets, channels)

    fig, ax = plt.subplots(figsize=(6, 3.6))
    names, rb, ra = [], [], []
    for kind, b, a in sets:
        names.append(f"{kind} {len(names)}")
        rb.append(b["metrics"].get("distance_ratio_0", float("nan")))
        ra.append(a["metrics"].get("distance_ratio_0", float("nan")))
    x = range(len(names))
    ax.bar([i - 0.2 for i in x], rb, 0.4, label="before")
    ax.bar([i + 0.2 for i in x], ra, 0.4, label="after")
    ax.axhline(1.0, color="grey", ls="--", lw=1)
    ax.set_xticks(list(x))
    ax.set_xticklabels(names, fontsize=8)
    ax.set_ylabel("real / simulated distance per cycle")
    ax.set_title("distance ratio per recording (cf. paper 000 Fig. 9)", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    out = f"{args.out_prefix}-distance-ratio.svg"
    fig.savefig(out)
    print(out)
    return 0


def sweep(args):
    """Heat map of the grid (generation 0) over its two most finely gridded genes, best over
    the others, with the Nelder-Mead searches' points and the path of the best so far."""
    import numpy as np
    with open(args.data) as f:
        data = json.load(f)
    genes, members = data["genes"], data["members"]
    if not members:
        print(f"gaitforge_plot: {args.data}: no member evaluated yet", file=sys.stderr)
        return 2
    axes = sorted(range(len(genes)), key=lambda i: (-genes[i][3], i))[:2]
    if len(axes) < 2 or genes[axes[1]][3] < 2:
        axes = [axes[0], axes[0]]
    ix, iy = axes
    grid = [m for m in members if m[0] == 0]
    # Deb's rule as the engines: feasible before infeasible, then fitness.
    key = lambda m: (m[1] is not None, -m[2] if m[1] is not None else -math.inf,
                     m[1] if m[1] is not None else -math.inf)
    def levels(i):
        name, lo, hi, p = genes[i]
        return np.array([0.5 * (lo + hi)]) if p == 1 else np.linspace(lo, hi, int(p))
    xs, ys = levels(ix), levels(iy)
    z = np.full((len(ys), len(xs)), np.nan)
    for m in grid:
        if m[1] is None or m[2] > 0:
            continue
        a = int(np.argmin(abs(xs - m[3 + ix])))
        b = int(np.argmin(abs(ys - m[3 + iy])))
        z[b, a] = m[1] if np.isnan(z[b, a]) else max(z[b, a], m[1])
    fig, ax = plt.subplots(figsize=(7, 5))
    def edges(v, i):
        if len(v) == 1:
            return np.array([genes[i][1], genes[i][2]])
        step = v[1] - v[0]
        return np.concatenate([v - step / 2, [v[-1] + step / 2]])
    mesh = ax.pcolormesh(edges(xs, ix), edges(ys, iy), np.ma.masked_invalid(z), cmap="viridis",
                         shading="flat")
    fig.colorbar(mesh, ax=ax, label="best fitness on the grid (feasible)")
    later = [m for m in members if m[0] > 0]
    if later:
        ax.scatter([m[3 + ix] for m in later], [m[3 + iy] for m in later], s=6, c="white",
                   edgecolors="black", linewidths=0.3, label="Nelder-Mead points", zorder=3)
    # From the grid's best point, each better point the searches found.
    best = max(grid, key=key) if grid else None
    path = [(best[3 + ix], best[3 + iy])] if best else []
    for m in sorted(later, key=lambda m: m[0]):
        if best is None or key(m) > key(best):
            best = m
            path.append((m[3 + ix], m[3 + iy]))
    if path:
        px, py = zip(*path)
        ax.plot(px, py, "-o", color="tab:red", ms=3, lw=1.2, label="best so far", zorder=4)
        ax.plot(px[-1], py[-1], "*", color="tab:red", ms=14, mec="black", zorder=5,
                label=f"best: {best[1]:.4g}")
    ax.set_xlabel(genes[ix][0])
    ax.set_ylabel(genes[iy][0])
    ax.set_title(args.title)
    ax.legend(loc="upper left", fontsize=8, framealpha=0.8)
    fig.tight_layout()
    fig.savefig(args.out)
    print(args.out)
    return 0


def pareto(args):
    """Every evaluated member in the plane of the first two objectives, coloured by
    generation, and the final front (the engine's hall of fame) joined in order."""
    with open(args.data) as f:
        data = json.load(f)
    objectives, members = data["objectives"], data["members"]
    names = [o["metric"] for o in objectives[:2]]
    have = [m for m in members if m["valid"] and all(n in m["metrics"] for n in names)]
    if not have:
        print(f"gaitforge_plot: {args.data}: no valid member reports {', '.join(names)}",
              file=sys.stderr)
        return 2
    front_keys = {tuple(k) for k in data["front"]}
    xy = lambda m: (m["metrics"][names[0]], m["metrics"][names[1]])
    fig, ax = plt.subplots(figsize=(7, 5))
    points = ax.scatter([xy(m)[0] for m in have], [xy(m)[1] for m in have], s=10,
                        c=[m["generation"] for m in have], cmap="viridis", alpha=0.7,
                        label="evaluated members")
    fig.colorbar(points, ax=ax, label="generation")
    front = sorted((xy(m) for m in have if (m["generation"], m["member"]) in front_keys))
    if front:
        fx, fy = zip(*front)
        ax.plot(fx, fy, "-o", color="tab:red", ms=5, mec="black", lw=1.2, zorder=4,
                label=f"Pareto front ({len(front)} members)")
    # An axis whose positive values span more than 30 times is drawn logarithmic: a few
    # gaits that barely move cost hundreds of times the front's energy.
    for values, scale in (([xy(m)[0] for m in have], ax.set_xscale),
                          ([xy(m)[1] for m in have], ax.set_yscale)):
        if min(values) > 0 and max(values) > 30 * min(values):
            scale("log")
    arrow = {"maximize": "higher is better", "minimize": "lower is better"}
    ax.set_xlabel(f"{names[0]} ({arrow[objectives[0]['sense']]})")
    ax.set_ylabel(f"{names[1]} ({arrow[objectives[1]['sense']]})")
    more = f"; objectives beyond these two: {len(objectives) - 2}" if len(objectives) > 2 else ""
    ax.set_title(f"{args.title}: {len(have)} valid of {len(members)} members{more}", fontsize=10)
    ax.legend(loc="best", fontsize=8, framealpha=0.8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.out)
    print(args.out)
    return 0


def diagnosis(args):
    import gaitforge_diagnosis_figure
    print(gaitforge_diagnosis_figure.draw(args.report, args.out))
    return 0


def tracking(args):
    import gaitforge_tracking_figure
    runs = [run.partition("=")[::2] for run in args.runs]
    print(gaitforge_tracking_figure.draw(runs, args.out, args.title))
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
    c = sub.add_parser("paper-gait", help="paper 000's gait figures from a report JSON")
    c.add_argument("--report", required=True, help="the JSON `gaitforge report` writes")
    c.add_argument("--out-prefix", required=True, help="files PREFIX-gaits.svg etc.")
    c.set_defaults(run=paper_gait)
    k = sub.add_parser("calibration", help="a calibration study's figures from its report JSON")
    k.add_argument("--report", required=True, help="the JSON `gaitforge report` writes")
    k.add_argument("--out-prefix", required=True, help="files PREFIX-overlays.svg etc.")
    k.set_defaults(run=calibration)
    w = sub.add_parser("sweep", help="a sweep study's grid as a heat map, with its searches")
    w.add_argument("--data", required=True, help="the JSON `gaitforge plot` writes for a sweep")
    w.add_argument("--out", required=True, help="image file (.svg or .png)")
    w.add_argument("--title", default="sweep")
    w.set_defaults(run=sweep)
    g = sub.add_parser("diagnosis", help="the gap finder's figure from its diagnosis.json")
    g.add_argument("--report", required=True, help="the diagnosis.json `gaitforge diagnose` writes")
    g.add_argument("--out", required=True, help="image file (.svg or .png)")
    g.set_defaults(run=diagnosis)
    q = sub.add_parser("pareto", help="an nsga2 study's members and Pareto front")
    q.add_argument("--data", required=True, help="the -pareto.json `gaitforge plot` writes")
    q.add_argument("--out", required=True, help="image file (.svg or .png)")
    q.add_argument("--title", default="Pareto front")
    q.set_defaults(run=pareto)
    t = sub.add_parser("tracking", help="a path and the tip under each controller, and their errors")
    t.add_argument("--run", dest="runs", action="append", required=True,
                   help="LABEL=TICKS.csv (gaitforge-sim track --out)")
    t.add_argument("--out", required=True, help="image file (.svg or .png)")
    t.add_argument("--title", default="tracking")
    t.set_defaults(run=tracking)
    args = ap.parse_args()
    return args.run(args)


if __name__ == "__main__":
    sys.exit(main())
