"""The gap finder's figure (`gaitforge diagnose`, docs/diagnosis.md "Report"): does the named
effect make the model predict the held-out recordings better, and by more than the noise?

Top: the held-out error of the baseline and of every full fit (bar: the mean over the six
numerically irrelevant variants; dots: each variant, the noise floor), the named
explanation in red, the rule's line (the baseline's error less 15%).
Below, for each held-out recording: the recorded markers against the calibrated baseline
and against the named explanation (or, when nothing was named, the fit that came closest
held out, to show why it was not enough), markers m1 (tail) and m6 (head) forward and m3
vertical.

Input: the diagnosis JSON, whose `overlay` names the `gaitforge-sim calibration-eval
--out-dir` results of both models on the held-out recordings.
"""
import json

import matplotlib.pyplot as plt

from gaitforge_plot import aligned, read_csv

CHANNELS = ["m1.x", "m6.x", "m3.z"]


def _fits(rep):
    """(label, mean, variants, named) for the baseline and every full fit, best first."""
    err = rep["errors"]
    named = {e["id"] for e in rep["effects"]}
    rows = [(f["id"], f["held_out"], f["held_out_variants"], f["id"] in named)
            for f in rep["effects"] + rep["runners_up"] if f.get("held_out") is not None]
    rows.sort(key=lambda r: r[1])
    base = err.get("baseline_held_out")
    return [("baseline", float("nan") if base is None else base,
             err.get("baseline_held_out_variants") or [], False)] + rows


def _error_panel(ax, rep):
    fits = _fits(rep)
    for i, (label, mean, variants, named) in enumerate(fits):
        color = "tab:red" if named else ("tab:blue" if label == "baseline" else "0.7")
        ax.bar(i, 1000 * mean, 0.6, color=color)
        dots = [1000 * v for v in variants if v is not None]  # null: a variant that failed
        ax.plot([i] * len(dots), dots, "k.", ms=3)
    line = 1000 * (1 - rep.get("rule", {}).get("held_out_gain", 0.15)) * fits[0][1]
    ax.axhline(line, color="tab:red", ls="--", lw=1, label="baseline less 15% (the rule)")
    ax.set_xticks(range(len(fits)))
    ax.set_xticklabels([f[0].replace("+", "+\n") for f in fits], fontsize=6, rotation=30,
                       ha="right")
    ax.set_ylabel("held-out error (mm)", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.legend(fontsize=7)
    verdict = rep["verdict"]
    what = " and ".join(e["id"] for e in rep["effects"]) or "no missing physics"
    title = f"{rep['name']}: {verdict} ({what}); dots: the numeric variants"
    if _magnitudes(rep):
        title += "\n" + _magnitudes(rep)
    ax.set_title(title, fontsize=9)


def _magnitudes(rep):
    """The named effects' fitted values with their ranges (docs/diagnosis.md), one line."""
    def end(v):
        return "open" if v is None else f"{v:.3g}"
    parts = []
    for e in rep["effects"]:
        for name, p in e["params"].items():
            if "range" in p:
                lo, hi = p["range"]
                loose = ", not pinned" if (p.get("range_share") or 0) >= 0.9 else ""
                parts.append(f"{name.replace('effect.', '')} {p['value']:.3g} "
                             f"(range {end(lo)}..{end(hi)}{loose})")
    return "; ".join(parts)


def _overlay_rows(fig, grid, rep, first_row):
    ov = rep.get("overlay") or {}
    with open(ov["baseline_eval"]) as f:
        base = json.load(f)["recordings"]
    other = []
    if ov.get("other_eval"):
        with open(ov["other_eval"]) as f:
            other = json.load(f)["recordings"]
    label = ov.get("other", "")
    for row, b in enumerate(base):
        if not b.get("valid") or not b.get("sim"):
            continue
        real = read_csv(b["file"])
        for col, ch in enumerate(CHANNELS):
            ax = fig.add_subplot(grid[first_row + row, col])
            if ch not in real:
                ax.set_visible(False)
                continue
            ax.plot(real["t"], [1000 * v for v in real[ch]], color="k", lw=1.2, label="recorded")
            for res, color, ls, name in ((b, "tab:blue", "--", "baseline"),
                                         (other[row] if row < len(other) else None, "tab:red",
                                          "-", label)):
                if not res or not res.get("valid") or not res.get("sim"):
                    continue
                shift = res["metrics"].get("time_shift_s_0", 0.0) + res.get("time_offset_s", 0.0)
                ax.plot(real["t"], [1000 * v for v in aligned(real, res["sim"], ch, shift)],
                        color=color, ls=ls, lw=0.9, label=name)
            ax.set_title(f"held-out {row}: {ch} (mm)", fontsize=8)
            ax.tick_params(labelsize=7)
            if row == len(base) - 1:
                ax.set_xlabel("t (s)", fontsize=8)
            if row == 0 and col == 0:
                ax.legend(fontsize=6)
    return len(base)


def draw(report_path, out):
    with open(report_path) as f:
        rep = json.load(f)
    held = 0
    if (rep.get("overlay") or {}).get("baseline_eval"):
        with open(rep["overlay"]["baseline_eval"]) as f:
            held = len(json.load(f)["recordings"])
    fig = plt.figure(figsize=(10, 3.2 + 2.3 * held))
    grid = fig.add_gridspec(1 + held, len(CHANNELS), height_ratios=[1.4] + [1] * held)
    _error_panel(fig.add_subplot(grid[0, :]), rep)
    if held:
        _overlay_rows(fig, grid, rep, 1)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
    return out
