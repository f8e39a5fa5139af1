#!/usr/bin/python3
"""Where does the model miss the recordings? Slices of the residual (recorded - simulated
markers) of a `gaitforge-sim calibration-eval` run, for the gap finder (issue 8).

Input: the JSON of
    gaitforge-sim calibration-eval --recordings A.csv,B.csv [--set FIT] --out-dir DIR
({"recordings": [{"file", "time_offset_s", "valid", "metrics": {"time_shift_s_0", ...},
"sim": "DIR/sim-i.csv"}]}). Each valid recording is compared with its simulated markers:

  alignment   the simulation is read at simulated time ts = t + time_offset_s +
              time_shift_s_0 (linear interpolation), as the calibration error pairs them;
              samples before the 2 settle cycles (ts < 2 T) or outside the simulation are left
              out; each channel's constant offset (its mean residual) is removed.
  noise_m     the sensor noise floor: the robust sd (1.4826 x median absolute deviation) of
              the residual's differences between consecutive samples (steps of one interval;
              dropped rows skipped), / sqrt 2, the median over the x and z channels. The
              plain sd of the differences is `noise_sd_diff_m` (larger: it also holds the
              model's fast mismatches, e.g. hop timing).
  slices      per recording (T = the gait period the comparison used, period_s_0; cycles =
              span / T; a recording without a gait, a playback, has period 0: it is compared
              from its start and T is a quarter of its span, four windows in place of cycles):
    axis      RMS of the residual per axis over the 6 markers, and its excess over the noise
              sqrt(max(0, rms^2 - noise^2)); y is checked to be 0 in both.
    trend     each channel's least-squares slope over time, m/s and m per cycle; the mean
              over the 6 x (z) channels; the drift over the recording (slope x span); the x
              slope of the first and of the second half (a deficit growing along the run).
    travel    distance per cycle of the recorded and the simulated centroid (mean of m*.x;
              slopes x T) and the fraction of the simulated travel missing,
              1 - recorded / simulated; the regression of the centroid's x residual on the
              recorded centroid displacement (slope, r^2) and on the simulated one (its
              slope is minus the missing fraction when the deficit follows the travel).
    phase     10 bins of the gait phase (ts mod T) / T: RMS of the detrended residual (each
              channel's trend removed) per bin, x and z, over the 6 markers.
    contact   a marker is on the ground when its recorded z is within 1.5 mm of its minimum
              (the 1st percentile, robust to the noise), airborne otherwise: the share of
              samples, the RMS of the detrended x and z residual, and the x drift that
              accrues in each state (sum of the x residual's steps, m per cycle).
    velocity  the sign of the recorded x velocity of each marker (central difference
              over +-2 samples): forward (v > 0) or backward (v <= 0); the same numbers as
              contact for each.
  Any subset of markers and axes: contact uses the markers with x and z, velocity those
  with x; a slice the recording cannot give is null (no z: no contact, no x: no travel,
  drift or velocity) and the findings say the axis is not recorded, never that it matches.
  The noise floor is taken between consecutive samples: at low rates (50 Hz and below) it
  also holds the model's fast mismatches and grows, which makes the step more cautious.
  numeric_spread  (with --variants: the same fit evaluated under numerically irrelevant
              variants, timestep and contact softness) per recording: the simulated travel
              per cycle under each variant (the first is the main eval), their mean and sd,
              how many sds the recorded travel lies off (recorded_sds), and
              per axis the RMS of the detrended difference between each variant's residual
              and the main one (shape_per_variant_m) and the largest (shape_m): the model's
              own spread. A hopping robot's travel moves by tens of percent under such variants:
              a drift is a mismatch only
              when the recorded travel lies more than 3 sds (+ the drift threshold per cycle)
              from the variants' mean travel, a shape excess only beyond
              sqrt(noise^2 + shape_m^2).
  findings    sentences for the effects larger than 3 x noise_m and beyond the numeric spread
              (drifts over the whole recording, RMS excesses, phase peaks, and where the drift
              accrues), and for those within the spread only; a summary; beyond_spread: any
              mismatch beyond noise and spread.

Output: --out FILE.json {"noise_m", "noise_sd_diff_m", "variants", "beyond_spread",
"beyond_recordings" (the files with a finding beyond noise and spread; both null without
--variants), "slices":
{"recordings": [...], "pooled": {...}}, "findings": [...], "summary": "..."}; --figure
FILE.svg: per recording the x and z residuals against time (one panel each; the variants'
centroid x residuals in grey) and their RMS by gait phase.

Usage:
    gaitforge_locate.py --eval EVAL.json --out LOCATE.json [--figure LOCATE.svg]
                        [--variants EVAL_V1.json,EVAL_V2.json,...]
Run under /usr/bin/python3 (numpy, matplotlib).
"""
import argparse
import json
import math
import os
import re
import sys

import numpy as np

def marker_names(columns):
    """The markers among recording columns, in column order: every NAME with a NAME.x, NAME.y
    or NAME.z column (any robot's named markers)."""
    names = []
    for c in columns:
        base, _, axis = c.rpartition(".")
        if base and axis in ("x", "y", "z") and base not in names:
            names.append(base)
    return names
SETTLE_CYCLES = 2
PLAYBACK_WINDOWS = 4  # the "cycles" of a recording without a gait (a playback)
PHASE_BINS = 10
CONTACT_BAND_M = 1.5e-3
SIGNIFICANT = 3.0  # findings need an effect larger than this many noise_m
SPREAD_SDS = 3.0  # ... and a travel this many sds of the numeric variants' travel away
STATE_TEXT = {"ground": "on the ground", "airborne": "airborne", "forward": "moving forward",
              "backward": "moving backward or still"}


def read_csv(path):
    """Columns of a recording (or simulated markers) CSV. Empty or NaN channel cells
    (occluded markers) are bridged linearly in time between the channel's neighbours, ends
    held, as gaitforge's parser does (docs/recording-format.md, "Missing cells")."""
    with open(path) as f:
        header = [h.strip() for h in f.readline().lstrip("\ufeff").strip().split(",")]
        rows = [line.strip().split(",") for line in f if line.strip()]
    data = np.array([[float(c) if c.strip() else np.nan for c in row] for row in rows],
                    dtype=float)
    cols = {h: data[:, i] for i, h in enumerate(header)}
    t = cols.get("t")
    for h, v in cols.items():
        gap = np.isnan(v)
        if h != "t" and t is not None and gap.any() and not gap.all():
            v[gap] = np.interp(t[gap], t[~gap], v[~gap])
    return cols


def resolve(path, base):
    if os.path.isabs(path) or os.path.exists(path):
        return path
    alt = os.path.join(base, path)
    return alt if os.path.exists(alt) else path


def own_name(path):
    """A recording's own file name: without the HASH16- prefix of a copy that `gaitforge
    diagnose` downloaded from the coordinator."""
    name = os.path.basename(path)
    return name[17:] if re.fullmatch(r"[0-9a-f]{16}-.+", name) else name


def robust_sd(v):
    v = np.asarray(v, dtype=float)
    if v.size < 2:
        return float("nan")
    return float(1.4826 * np.median(np.abs(v - np.median(v))))


def slope(t, y):
    """Least-squares slope of y over t."""
    tc = t - t.mean()
    den = float(np.dot(tc, tc))
    return float(np.dot(tc, y - y.mean()) / den) if den > 0 else float("nan")


def regress(x, y):
    """Slope and r^2 of y on x."""
    xc, yc = x - x.mean(), y - y.mean()
    sxx, syy = float(np.dot(xc, xc)), float(np.dot(yc, yc))
    if sxx <= 0:
        return float("nan"), float("nan")
    b = float(np.dot(xc, yc) / sxx)
    r2 = float(np.dot(xc, yc) ** 2 / (sxx * syy)) if syy > 0 else float("nan")
    return b, r2


def velocity(t, x):
    """dx/dt by a central difference over +-2 samples (one-sided at the ends): the sign of
    the motion with the noise of 4 intervals rather than 2."""
    n = len(x)
    lo = np.clip(np.arange(n) - 2, 0, n - 1)
    hi = np.clip(np.arange(n) + 2, 0, n - 1)
    return (x[hi] - x[lo]) / (t[hi] - t[lo])


def rms(v):
    v = np.asarray(v, dtype=float)
    return float(np.sqrt(np.mean(v * v))) if v.size else float("nan")


def excess(r, noise):
    return float(math.sqrt(max(0.0, r * r - noise * noise))) if np.isfinite(r) else float("nan")


def clean(obj):
    """NaN/inf -> None, numpy -> float, for strict JSON."""
    if isinstance(obj, dict):
        return {k: clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [clean(v) for v in obj]
    if isinstance(obj, (float, np.floating)):
        return float(obj) if np.isfinite(obj) else None
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


def mm(v):
    return f"{1000 * v:.1f} mm" if abs(v) >= 0.00995 else f"{1000 * v:.2f} mm"


class Recording:
    """One recording aligned with its simulation: residuals and their slices."""

    def __init__(self, entry, base):
        self.file = resolve(entry["file"], base)
        self.name = own_name(self.file)
        sim_path = resolve(entry["sim"], base)
        with open(self.file + ".json") as f:
            self.genes = json.load(f)["command"].get("genes")  # none for a playback
        # The gait period the objective compared over (any robot's controller).
        metrics = entry.get("metrics", {})
        if "period_s_0" not in metrics:
            raise ValueError(f"the evaluation of {self.file} has no metric period_s_0 (the gait "
                             "period its comparison used); evaluate it again with gaitforge-sim "
                             "calibration-eval")
        self.period = float(metrics["period_s_0"])
        # A recording without a gait cycle (a playback of recorded inputs: period 0) is
        # compared whole, and sliced into PLAYBACK_WINDOWS equal windows in place of cycles.
        self.playback = not self.period > 0
        settle = 0.0 if self.playback else SETTLE_CYCLES * self.period
        self.shift = float(entry.get("time_offset_s", 0.0)) + \
            float(entry.get("metrics", {}).get("time_shift_s_0", 0.0))
        rec, sim = read_csv(self.file), read_csv(sim_path)
        t = rec["t"]
        ts = t + self.shift
        keep = (ts >= settle - 1e-9) & (ts >= sim["t"][0]) & (ts <= sim["t"][-1])
        if keep.sum() < 10:
            raise ValueError(f"{self.name}: fewer than 10 samples overlap the simulation"
                             + ("" if self.playback else f" after {SETTLE_CYCLES} settle cycles"))
        if self.playback:
            self.period = float(ts[keep][-1] - ts[keep][0]) / PLAYBACK_WINDOWS
        self.t, self.ts = t[keep], ts[keep]
        steps = np.diff(t)
        self.dt = float(np.median(steps))
        self.consecutive = np.abs(np.diff(self.t) - self.dt) < 0.05 * self.dt
        self.rec, self.sim, self.res, self.y_max = {}, {}, {}, 0.0
        self.markers = marker_names(rec)
        for m in self.markers:
            for axis in ("x", "z"):
                ch = f"{m}.{axis}"
                if ch not in rec or ch not in sim:
                    continue
                r = rec[ch][keep]
                s = np.interp(self.ts, sim["t"], sim[ch])
                d = r - s
                self.rec[ch], self.sim[ch], self.res[ch] = r, s, d - d.mean()
            for src in (rec, sim):
                if f"{m}.y" in src:
                    self.y_max = max(self.y_max, float(np.max(np.abs(src[f"{m}.y"]))))
        self.xs = [c for c in self.res if c.endswith(".x")]
        self.zs = [c for c in self.res if c.endswith(".z")]
        if not self.res:
            raise ValueError(f"{self.name}: no x or z marker channel in both the recording and "
                             f"the simulation: nothing to locate")
        self.span = float(self.ts[-1] - self.ts[0])
        self.cycles = self.span / self.period
        self.trend = {c: slope(self.ts, self.res[c]) for c in self.res}
        self.detrended = {c: self.res[c] - self.trend[c] * (self.ts - self.ts.mean())
                          for c in self.res}

    def noise(self):
        per = {}
        for c, r in self.res.items():
            d = np.diff(r)[self.consecutive]
            per[c] = (robust_sd(d) / math.sqrt(2), float(np.std(d, ddof=1)) / math.sqrt(2))
        return per

    def slices(self, noise):
        T, ts = self.period, self.ts
        out = {"file": self.file, "period_s": T, "time_shift_s": self.shift,
               "samples": int(len(ts)), "cycles": self.cycles, "playback": self.playback}
        # axis
        axis = {}
        for name, chans in (("x", self.xs), ("z", self.zs)):
            r = rms(np.concatenate([self.res[c] for c in chans])) if chans else float("nan")
            rd = rms(np.concatenate([self.detrended[c] for c in chans])) if chans else float("nan")
            axis[name] = {"rms_m": r, "rms_excess_m": excess(r, noise),
                          "detrended_rms_m": rd, "detrended_rms_excess_m": excess(rd, noise),
                          "per_marker_rms_m": {c.split(".")[0]: rms(self.res[c]) for c in chans},
                          "per_marker_detrended_rms_m": {c.split(".")[0]: rms(self.detrended[c])
                                                         for c in chans}}
        axis["y"] = {"max_abs_m": self.y_max}
        out["axis"] = axis
        # trend
        tr = {}
        half = ts < ts[0] + self.span / 2
        for name, chans in (("x", self.xs), ("z", self.zs)):
            per = {c.split(".")[0]: {"m_per_s": self.trend[c], "m_per_cycle": self.trend[c] * T,
                                     "drift_m": self.trend[c] * self.span} for c in chans}
            mean = float(np.mean([self.trend[c] for c in chans])) if chans else float("nan")
            tr[name] = {"mean_m_per_s": mean, "mean_m_per_cycle": mean * T,
                        "mean_drift_m": mean * self.span, "per_marker": per}
        if self.xs:
            cx = np.mean([self.res[c] for c in self.xs], axis=0)
            tr["x"]["first_half_m_per_cycle"] = slope(ts[half], cx[half]) * T
            tr["x"]["second_half_m_per_cycle"] = slope(ts[~half], cx[~half]) * T
        out["trend"] = tr
        # travel (a gait's; a playback travels nowhere)
        if self.xs and not self.playback:
            rc = np.mean([self.rec[c] for c in self.xs], axis=0)
            sc = np.mean([self.sim[c] for c in self.xs], axis=0)
            cres = np.mean([self.res[c] for c in self.xs], axis=0)
            d_rec, d_sim = slope(ts, rc) * T, slope(ts, sc) * T
            b_rec, r2_rec = regress(rc - rc[0], cres)
            b_sim, r2_sim = regress(sc - sc[0], cres)
            out["travel"] = {
                "recorded_m_per_cycle": d_rec, "simulated_m_per_cycle": d_sim,
                "fraction_missing": 1 - d_rec / d_sim if abs(d_sim) > 1e-4 else float("nan"),
                "residual_vs_recorded_displacement": {"slope": b_rec, "r2": r2_rec},
                "residual_vs_simulated_displacement": {"slope": b_sim, "r2": r2_sim},
            }
        # phase
        phase = np.mod(ts, T) / T
        bins = np.minimum((phase * PHASE_BINS).astype(int), PHASE_BINS - 1)
        ph = {"bin_edges": [i / PHASE_BINS for i in range(PHASE_BINS + 1)]}
        for name, chans in (("x", self.xs), ("z", self.zs)):
            vals = []
            for k in range(PHASE_BINS):
                sel = bins == k
                vals.append(rms(np.concatenate([self.detrended[c][sel] for c in chans]))
                            if chans and sel.any() else float("nan"))
            ph[f"{name}_rms_m"] = vals
        out["phase"] = ph
        # contact and velocity: where the x drift accrues. Contact needs a marker's x and z
        # (its height says whether it is down), velocity its x; a recording without them
        # has no such slice (null).
        contact = {s: {"share": [], "x": [], "z": [], "drift": []} for s in ("ground", "airborne")}
        vel = {s: {"share": [], "x": [], "drift": []} for s in ("forward", "backward")}
        for m in self.markers:
            cx, cz = f"{m}.x", f"{m}.z"
            if cx not in self.res:
                continue
            dres = np.concatenate([np.diff(self.res[cx]), [0.0]])
            # a step counts for the state at its start; steps across dropped rows still count
            # (the drift must add up), their state is that of the sample before the gap
            if cz in self.res:
                z = self.rec[cz]
                ground = z <= np.percentile(z, 1) + CONTACT_BAND_M
                for state, sel in (("ground", ground), ("airborne", ~ground)):
                    c = contact[state]
                    c["share"].append(sel.mean())
                    c["x"].append(self.detrended[cx][sel])
                    c["z"].append(self.detrended[cz][sel])
                    c["drift"].append(dres[sel].sum())
            v = velocity(self.t, self.rec[cx])
            for state, sel in (("forward", v > 0), ("backward", v <= 0)):
                c = vel[state]
                c["share"].append(sel.mean())
                c["x"].append(self.detrended[cx][sel])
                c["drift"].append(dres[sel].sum())
        out["contact"] = {
            "band_m": CONTACT_BAND_M,
            **{s: {"share": float(np.mean(c["share"])),
                   "x_rms_m": rms(np.concatenate(c["x"])), "z_rms_m": rms(np.concatenate(c["z"])),
                   "x_drift_m_per_cycle": float(np.mean(c["drift"])) / self.cycles}
               for s, c in contact.items()}} if contact["ground"]["share"] and not self.playback \
            else None
        out["velocity"] = {
            **{s: {"share": float(np.mean(c["share"])), "x_rms_m": rms(np.concatenate(c["x"])),
                   "x_drift_m_per_cycle": float(np.mean(c["drift"])) / self.cycles}
               for s, c in vel.items()}} if self.xs and not self.playback else None
        return out


def spread_of(rec, variants):
    """The model's own numeric spread on one recording: rec (the main eval) beside the same
    fit under each numerically irrelevant variant (Recordings of the same file)."""
    def travel(r):
        return slope(r.ts, np.mean([r.sim[c] for c in r.xs], axis=0)) * r.period \
            if r.xs else float("nan")

    shape = {}
    for axis, chans in (("x", rec.xs), ("z", rec.zs)):
        per = []
        for v in variants:
            _, i, j = np.intersect1d(rec.t, v.t, return_indices=True)
            both = [c for c in chans if c in v.detrended]
            if len(i) >= 10 and both:
                per.append(rms(np.concatenate([rec.detrended[c][i] - v.detrended[c][j]
                                               for c in both])))
        shape[axis] = float(np.max(per)) if per else float("nan")
        shape[axis + "_all"] = per
    sims = np.array([travel(r) for r in [rec] + variants])
    ok = sims[np.isfinite(sims)]
    mean = float(ok.mean()) if ok.size else float("nan")
    sd = float(ok.std(ddof=1)) if ok.size > 1 else float("nan")
    rec_travel = slope(rec.ts, np.mean([rec.rec[c] for c in rec.xs], axis=0)) * rec.period \
        if rec.xs else float("nan")
    return {"variants": len(sims), "simulated_m_per_cycle": [float(v) for v in sims],
            "simulated_mean_m_per_cycle": mean, "simulated_sd_m_per_cycle": sd,
            "recorded_sds": (rec_travel - mean) / sd if sd > 0 else float("nan"),
            "x_shape_m": shape["x"], "z_shape_m": shape["z"],
            "x_shape_per_variant_m": shape["x_all"], "z_shape_per_variant_m": shape["z_all"]}


def shape_floor(s, axis, noise):
    """The floor a shape excess must clear: the noise, and the model's numeric spread."""
    sp = s.get("numeric_spread")
    v = sp.get(f"{axis}_shape_m") if sp else None
    return math.hypot(noise, v) if v is not None and np.isfinite(v) else noise


def travel_text(tv):
    """Recorded against simulated travel, and the missing share when the model moves forward."""
    if not tv:
        return "no x channels"
    rec, sim, frac = tv["recorded_m_per_cycle"], tv["simulated_m_per_cycle"], tv["fraction_missing"]
    text = f"recorded {mm(rec)} per cycle against simulated {mm(sim)}"
    if sim > 1e-4 and np.isfinite(frac):
        if frac > 0:
            text = f"{100 * frac:.0f}% of the simulated travel is missing: " + text
            if rec < 0:
                text += ", the recording goes backwards"
        else:
            text = f"the recording travels {100 * -frac:.0f}% further than simulated: " + text
    elif sim < -1e-4:
        text += " (a backward gait)"
    return text


def findings_for(s, noise):
    """Sentences for the effects of one recording's slices above SIGNIFICANT x noise and
    beyond the model's numeric spread, the size (in noise units) of the largest, for the
    summary, and those that stay within the spread (sentences, and their kinds)."""
    lim = SIGNIFICANT * noise
    name = own_name(s["file"])
    out, score, within = [], {}, {}
    ax, tr = s["axis"], s["trend"]
    sp = s.get("numeric_spread")
    z_floor = shape_floor(s, "z", noise)
    z_ex = excess(ax["z"]["rms_m"], z_floor)
    floor_words = "noise" if z_floor == noise else "noise and the model's numeric spread"
    if not np.isfinite(z_ex):
        z_text = "the vertical motion is not recorded (no z channel)"
    elif z_ex <= lim:
        z_text = (f"vertical motion matches within {floor_words} ({mm(z_ex)} RMS beyond it, "
                  f"under the {mm(lim)} threshold)")
    else:
        z_text = f"vertical motion differs too ({mm(ax['z']['rms_m'])} RMS)"
    drift = tr["x"]["mean_drift_m"]
    # Within the spread: the recorded travel within SPREAD_SDS sds of the variants' mean
    # (and the drift's own threshold, per cycle).
    spread_text = ""
    if sp and np.isfinite(sp.get("simulated_sd_m_per_cycle", float("nan"))):
        m, sd = sp["simulated_mean_m_per_cycle"], sp["simulated_sd_m_per_cycle"]
        rec = s.get("travel", {}).get("recorded_m_per_cycle", float("nan"))
        calm = abs(rec - m) <= SPREAD_SDS * sd + lim / s["cycles"]
        spread_text = (f"the model travels {mm(m)} +- {mm(sd)} per cycle under "
                       f"{sp['variants']} numerically irrelevant variants, the recording "
                       f"{mm(rec)}: {abs(rec - m) / sd if sd > 0 else float('inf'):.1f} sd off")
    else:
        calm = False
    if abs(drift) > lim and calm:
        within["drift"] = (f"{name}: the x residual drifts by {mm(tr['x']['mean_m_per_cycle'])} "
                           f"per cycle, within the model's numeric spread ({spread_text})")
    elif abs(drift) > lim:
        per = tr["x"]["per_marker"]
        n_same = sum(1 for p in per.values() if abs(p["drift_m"]) > lim
                     and np.sign(p["drift_m"]) == np.sign(drift))
        verb = "falls" if drift < 0 else "rises"
        tv = s.get("travel", {})
        what = travel_text(tv)
        if spread_text:
            what += f"; beyond the model's numeric spread: {spread_text}"
        if len(per) == 1:
            who = "the one marker"
        elif n_same == len(per):
            who = f"all {len(per)} markers"
        else:
            who = f"{n_same} of {len(per)} markers"
        out.append(f"{name}: forward drift: the x residual of {who} "
                   f"{verb} by {mm(abs(tr['x']['mean_m_per_cycle']))} per cycle "
                   f"({mm(abs(drift))} over {s['cycles']:.1f} cycles; {what}), while {z_text}")
        score["drift"] = abs(drift) / noise
        a, b = tr["x"].get("first_half_m_per_cycle"), tr["x"].get("second_half_m_per_cycle")
        if a is not None and abs(b - a) * s["cycles"] / 2 > lim:
            out.append(f"{name}: the x drift changes along the run: {mm(a)} per cycle in the "
                       f"first half, {mm(b)} per cycle in the second")
            score["growth"] = abs(b - a) * s["cycles"] / 2 / noise
        for key, label in (("contact", ("ground", "airborne")),
                           ("velocity", ("forward", "backward"))):
            if not s[key]:
                continue
            parts = [(st, s[key][st]["x_drift_m_per_cycle"], s[key][st]["share"]) for st in label]
            big = [p for p in parts if abs(p[1]) * s["cycles"] > lim]
            if big:
                desc = ", ".join(f"{mm(d)} per cycle while {STATE_TEXT[st]} ({100 * sh:.0f}% of "
                                 f"the samples)" for st, d, sh in parts)
                out.append(f"{name}: the x drift accrues {desc}")
    for axis, label in (("x", "horizontal"), ("z", "vertical")):
        floor = shape_floor(s, axis, noise)
        rd = ax[axis]["detrended_rms_m"]
        e = excess(rd, floor)
        if not np.isfinite(e):  # the axis is not recorded
            continue
        if e <= lim:
            if excess(rd, noise) > lim:
                within[f"{axis}_shape"] = (
                    f"{name}: {label} shape: the {axis} residual beyond any drift is {mm(rd)} "
                    f"RMS, within the noise and the model's numeric spread "
                    f"(the variants differ from the model by up to "
                    f"{mm(s['numeric_spread'][axis + '_shape_m'])} RMS)")
            continue
        ph = s["phase"][f"{axis}_rms_m"]
        k = int(np.nanargmax(ph))
        med = float(np.nanmedian(ph))
        where = ""
        if ph[k] > 1.5 * med and excess(ph[k], floor) > lim:
            where = (f", largest at gait phase {k / PHASE_BINS:.1f}-{(k + 1) / PHASE_BINS:.1f} "
                     f"({mm(ph[k])} RMS against a median of {mm(med)})")
        worst = max(ax[axis]["per_marker_detrended_rms_m"].items(), key=lambda kv: kv[1])
        c = s["contact"]
        if c:
            where += (f"; {mm(c['ground'][axis + '_rms_m'])} RMS on the ground, "
                      f"{mm(c['airborne'][axis + '_rms_m'])} airborne")
        if floor > noise:
            where += (f"; beyond the model's numeric spread: its variants differ from it by "
                      f"up to {mm(s['numeric_spread'][axis + '_shape_m'])} RMS")
        out.append(f"{name}: {label} shape: the {axis} residual beyond any drift is "
                   f"{mm(rd)} RMS (most at {worst[0]}, {mm(worst[1])}){where}")
        score[f"{axis}_shape"] = e / noise
    return out, score, within


def summary_of(slices, scores, noise, withins=()):
    """The summary sentence, and what the recordings could not show."""
    no_x = [own_name(s["file"]) for s in slices if "travel" not in s and not s["playback"]]
    unseen = (f" The forward travel is not compared in {', '.join(no_x)}: no x channel."
              if no_x else "")
    return summary_core(slices, scores, noise, withins) + unseen


def summary_core(slices, scores, noise, withins):
    n = len(slices)
    spread = [s["numeric_spread"]["variants"] for s in slices if s.get("numeric_spread")]
    if not any(scores):
        if not spread:
            return f"No systematic mismatch beyond noise (noise floor {mm(noise)})."
        text = ("No systematic mismatch beyond the noise and the model's own numeric spread "
                f"({spread[0]} numerically irrelevant variants; noise floor {mm(noise)})")
        sds = [(abs(s["numeric_spread"]["recorded_sds"]), s["numeric_spread"]["recorded_sds"],
                own_name(s["file"])) for s in slices if s.get("numeric_spread")
               and np.isfinite(s["numeric_spread"]["recorded_sds"])]
        if sds:
            _, worst, name = max(sds)
            text += (f": the recorded travel per cycle lies within {SPREAD_SDS:g} sd of the "
                     f"variants' in every recording (the farthest: {name}, {worst:+.1f} sd)")
        return text + "."
    drifted = [s for s, sc in zip(slices, scores) if "drift" in sc]
    parts = []
    if drifted:
        per = ", ".join(f"{mm(s['trend']['x']['mean_m_per_cycle'])}" for s in drifted)
        fr = [s["travel"]["fraction_missing"] for s in drifted if s.get("travel")
              and s["travel"]["simulated_m_per_cycle"] > 1e-4
              and np.isfinite(s["travel"]["fraction_missing"])]
        fr_text = ", ".join(f"{100 * f:.0f}%" for f in fr)
        parts.append(f"in {len(drifted)} of {n} recordings the x residual drifts ({per} per "
                     f"cycle" + (f"; of the forward gaits' simulated travel {fr_text} is missing"
                                 if fr_text else "") + ")")
    for axis, label in (("z_shape", "the vertical motion"), ("x_shape", "the horizontal shape")):
        k = [s for s, sc in zip(slices, scores) if axis in sc]
        if k:
            worst = max(s["axis"][axis[0]]["detrended_rms_m"] for s in k)
            parts.append(f"{label} differs in {len(k)} of {n} (up to {mm(worst)} RMS)")
    flat = [s for s, sc in zip(slices, scores)
            if "z_shape" not in sc and np.isfinite(s["axis"]["z"]["rms_m"])]
    if drifted and len(flat) == n:
        parts.append("the vertical motion matches within noise in all" if not spread else
                     "the vertical motion matches within the noise and the spread in all")
    calm = [s for s, sc, w in zip(slices, scores, withins) if "drift" in w]
    if calm:
        parts.append(f"within the model's numeric spread: the travel in {len(calm)} of {n}")
    lead = max(("drift", "x_shape", "z_shape"),
               key=lambda k: sum(sc.get(k, 0) for sc in scores))
    what = {"drift": "forward travel", "x_shape": "the horizontal shape of the stroke",
            "z_shape": "the vertical motion"}[lead]
    floor = f"noise floor {mm(noise)}"
    if spread:
        floor += f"; beyond the model's spread under {spread[0]} numerically irrelevant variants"
    return f"The mismatch lives mainly in {what}: " + "; ".join(parts) + f" ({floor})."


def read_variants(arg, recs):
    """Per recording of recs, its Recordings under the variant evals (comma-separated
    paths); [] without any. Every variant must hold every recording, valid."""
    paths = [p for p in arg.split(",") if p]
    out = [[] for _ in recs]
    for path in paths:
        with open(path) as f:
            ev = json.load(f)
        base = os.path.dirname(os.path.abspath(path))
        by_name = {own_name(e.get("file", "")): e for e in ev.get("recordings", [])}
        for i, r in enumerate(recs):
            e = by_name.get(r.name)
            if e is None or not e.get("valid") or not e.get("sim"):
                raise ValueError(f"{path}: no valid simulation of {r.name}")
            out[i].append(Recording(e, base))
    return out if paths else []


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--eval", required=True, help="calibration-eval JSON (with --out-dir)")
    ap.add_argument("--out", required=True, help="the slices and findings, JSON")
    ap.add_argument("--figure", help="residuals against time and by phase, SVG")
    ap.add_argument("--variants", default="",
                    help="calibration-eval JSONs of the same fit under numerically irrelevant "
                         "variants, comma-separated: the model's own spread")
    args = ap.parse_args()
    try:
        with open(args.eval) as f:
            ev = json.load(f)
    except (OSError, ValueError) as e:
        print(f"gaitforge_locate: cannot read {args.eval}: {e}", file=sys.stderr)
        return 2
    base = os.path.dirname(os.path.abspath(args.eval))
    recs, skipped = [], []
    for entry in ev.get("recordings", []):
        if not entry.get("valid") or not entry.get("sim"):
            skipped.append(f"{entry.get('file')}: {entry.get('reason') or 'no simulated markers'}")
            continue
        try:
            recs.append(Recording(entry, base))
        except (OSError, ValueError, KeyError) as e:
            print(f"gaitforge_locate: {e}", file=sys.stderr)
            return 2
    if not recs:
        print("gaitforge_locate: no valid recording with simulated markers (run calibration-eval "
              "with --out-dir)" + "".join(f"\n  {s}" for s in skipped), file=sys.stderr)
        return 2
    try:
        variants = read_variants(args.variants, recs)
    except (OSError, ValueError, KeyError) as e:
        print(f"gaitforge_locate: --variants: {e}", file=sys.stderr)
        return 2
    per_channel = [v for r in recs for v in r.noise().values()]
    noise = float(np.median([p[0] for p in per_channel]))
    noise_plain = float(np.median([p[1] for p in per_channel]))
    slices = [r.slices(noise) for r in recs]
    if variants:
        for r, s, vs in zip(recs, slices, variants):
            s["numeric_spread"] = spread_of(r, vs)
    findings, scores, withins = [], [], []
    for s in slices:
        f, sc, w = findings_for(s, noise)
        if s["playback"]:  # windows of a recording without a gait, not cycles
            f = [t.replace(" per cycle", " per window").replace(" cycles", " windows")
                 .replace("; no x channels)", ")") for t in f]
            w = {k: t.replace(" per cycle", " per window") for k, t in w.items()}
        findings += f
        scores.append(sc)
        withins.append(w)
    summary = summary_of(slices, scores, noise, withins)
    if all(s["playback"] for s in slices):
        summary = summary.replace(" per cycle", " per window").replace(" of the stroke", "")
    findings += [text for w in withins for text in w.values()]
    if not any(scores):
        floor = "noise and the model's numeric spread" if variants else "noise"
        findings.insert(0, f"no systematic mismatch beyond the {floor} ({mm(noise)}): every "
                           f"drift and RMS excess is below {SIGNIFICANT:g} x the noise floor"
                        + (" or within the variants' spread" if variants else ""))
    pooled = {
        "x_rms_m": rms(np.concatenate([[]] + [r.res[c] for r in recs for c in r.xs])),
        "z_rms_m": rms(np.concatenate([[]] + [r.res[c] for r in recs for c in r.zs])),
        "x_trend_m_per_cycle": [s["trend"]["x"]["mean_m_per_cycle"] for s in slices],
        "fraction_missing": [s.get("travel", {}).get("fraction_missing") for s in slices],
    }
    out = {"eval": args.eval, "noise_m": noise, "noise_sd_diff_m": noise_plain,
           "threshold_m": SIGNIFICANT * noise, "skipped": skipped,
           "variants": 1 + len(variants[0]) if variants else 1,
           # null without --variants: beyond the noise is not beyond the model's spread
           "beyond_spread": any(bool(sc) for sc in scores) if variants else None,
           "beyond_recordings": [r.name for r, sc in zip(recs, scores) if sc] if variants else None,
           "slices": {"recordings": slices, "pooled": pooled},
           "findings": findings, "summary": summary}
    with open(args.out, "w") as f:
        json.dump(clean(out), f, indent=1)
        f.write("\n")
    if args.figure:
        from gaitforge_locate_figure import figure  # matplotlib only when drawing
        figure(recs, slices, args.figure, variants, PHASE_BINS)
    try:
        print(summary)
        for line in findings:
            print(f"  - {line}")
        sys.stdout.flush()
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    return 0


if __name__ == "__main__":
    sys.exit(main())
