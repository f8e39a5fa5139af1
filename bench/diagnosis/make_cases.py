#!/usr/bin/python3
"""Concealed test cases for the gap finder (issue 8): recordings made by a reference rig
with a known missing effect, disguised as hardware recordings.

For each case, three recordings of the caterpillar (gaits A and B for training, gait C held
out) are simulated by `gaitforge-sim trajectory` on a REFERENCE RIG that is not the model
being diagnosed (a finer timestep and a softer ground contact, RIG below) plus the case's
concealed effect, 10 measured cycles after 2 settle cycles at 100 Hz. Each CSV is then
disguised as a recording:

  - Gaussian sensor noise (sd 0.3 mm) on every x and z marker channel (y stays exactly 0:
    the robot is planar and the rig has no lateral motion);
  - a constant offset per marker and axis (x and z, uniform in +-4 mm);
  - a time offset: recording time = simulated time + 0.02 s (still regular);
  - about 3% of the rows dropped at random (never the first or the last), which the
    recording parser counts as dropped rows (docs/recording-format.md, "Sampling");
  - a sidecar without `overrides` and `parameters` and with a neutral note, so that
    neither names the rig or the effect.

Every random draw comes from numpy's default_rng seeded per case and gait, and the
simulator is deterministic, so the output is the same bytes on every run. Each file is
checked with `gaitforge-sim calibration-eval --recordings FILE` (exit 0, valid).

Writes (default --out tests/diagnosis):
  cases/<case>/train/gait-a.csv, train/gait-b.csv, held_out/gait-c.csv (+ .json sidecars)
  cases/<case>/case.json       which files are training and which held out (no answer)
  answers.sealed.json          the concealed effect per case; read it only after diagnosing

Prints the cases, the files, and the distance per cycle of the clean rig trajectories:
with the effect, without it (the null rig) and the diagnosed model (robots/caterpillar/robot.yaml).

Run from the repository root (binaries in build/bin):
    /usr/bin/python3 bench/diagnosis/make_cases.py [--out DIR] [--sim PATH] [--rig SET] [--survey]

Cases derived from these by occlude_cases.py (markers occluded at times) keep their
answers here; rerun that script after this one.

--survey writes nothing: it prints the distance per cycle of every case's effect on a few
nearby rigs (timestep x contact CFM), to show how much of a travel difference is the
effect and how much the hopping robot's sensitivity to numerically irrelevant changes.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SIM = os.path.join(ROOT, "build", "bin", "gaitforge-sim")

# The reference rig: not the diagnosed model (1 ms steps, contact CFM 1e-5).
RIG = "simulation.timestep_s=0.0005,ground.contact_cfm=2e-5"
CYCLES = 10
SETTLE = 2
RATE_HZ = 100

GAITS = {
    # evolved, forward hopping (T = 0.354 s)
    "a": "0.066346016790415963,0.92228296711382263,0.99884798501519678,0.91495911032617716,"
         "0.013764065590901597,0.027395295966066602,0.32783986902260742,0.36116692841980558,"
         "0.1062628441354091,0.40778045503790639,0.36272688662110386,0.30411357539492101,"
         "0.35444634996911673",
    # hand-made (T = 0.5 s, 0.7 s)
    "b": "0.05,0.2,0.35,0.3,0.45,0.6,0.45,0.6,0.75,0.7,0.85,0.0,0.5",
    "c": "0.0,0.1,0.2,0.5,0.6,0.7,0.3,0.4,0.5,0.8,0.9,0.0,0.7",
}
TRAIN = ["a", "b"]
HELD_OUT = ["c"]

# case: (catalog id or "none", concealed overrides, seed)
CASES = [
    ("tether-hose", "tether.constant", {"effect.tether_force_n": 1.1}, 101),
    ("tether-light", "tether.constant", {"effect.tether_force_n": 0.5}, 102),
    ("slope-up", "ground.slope", {"effect.slope_rad": 0.15}, 103),
    ("drag", "friction.viscous", {"effect.drag_n_s_per_m": 1.0}, 104),
    ("deadband", "actuator.deadband", {"effect.actuator_deadband_n": 1.0}, 107),
    ("soft-lumps", "model.resolution", {"effect.lump_compliance_per_mpa": 5.0}, 108),
    ("null-a", "none", {}, 105),
    ("null-b", "none", {}, 106),
    # Session 5: every catalog effect, and a second magnitude of the first five.
    ("tether-growing", "tether.growing", {"effect.tether_stiffness_n_per_m": 25.0}, 110),
    ("slope-steep", "ground.slope", {"effect.slope_rad": 0.25}, 111),
    ("drag-strong", "friction.viscous", {"effect.drag_n_s_per_m": 2.0}, 112),
    ("deadband-light", "actuator.deadband", {"effect.actuator_deadband_n": 0.5}, 113),
    ("soft-lumps-10", "model.resolution", {"effect.lump_compliance_per_mpa": 10.0}, 114),
    ("lag", "actuator.lag", {"effect.actuator_lag_s": 0.04}, 115),
    ("weak", "actuator.force_scale", {"actuators.force_n": 7.0}, 117),
    ("slip-back", "friction.anisotropic",
     {"effect.friction_forward": 1.5, "effect.friction_backward": 0.6}, 118),
    ("softening", "spring.softening", {"effect.spring_softening": 200.0}, 119),
    ("soft-ground", "contact.softness", {"ground.contact_cfm": 1e-3}, 120),
    ("heavy", "mass.offset", {"scale.mass": 1.3}, 121),
    ("soft-links", "stiffness.scale", {"scale.link_stiffness": 0.6}, 122),
    ("null-c", "none", {}, 109),
    # Session 10: a second magnitude of every effect that had one only. (No transport
    # delay: on these periodic gaits a delay of the command is a shift of the whole motion
    # once settled, which the fitted time offset takes; generated at 20 and 50 ms, gaits B
    # and C travelled within 0.02 mm per cycle of the null. docs/effects.md.)
    ("lag-strong", "actuator.lag", {"effect.actuator_lag_s": 0.08}, 125),
    ("weak-mild", "actuator.force_scale", {"actuators.force_n": 7.9}, 126),
    ("slip-back-mild", "friction.anisotropic",
     {"effect.friction_forward": 1.5, "effect.friction_backward": 1.0}, 127),
    ("softening-strong", "spring.softening", {"effect.spring_softening": 400.0}, 128),
    ("heavy-light", "mass.offset", {"scale.mass": 1.15}, 129),
    ("soft-links-mild", "stiffness.scale", {"scale.link_stiffness": 0.8}, 130),
    ("soft-ground-strong", "contact.softness", {"ground.contact_cfm": 3e-3}, 131),
    # Session 13: the link damping (damping.scale), below and above the paper's critical.
    ("underdamped", "damping.scale", {"scale.link_damping": 0.3}, 132),
    ("overdamped", "damping.scale", {"scale.link_damping": 2.5}, 133),
]

NOISE_SD_M = 3e-4
OFFSET_MAX_M = 4e-3
TIME_SHIFT_S = 0.02
DROP_FRACTION = 0.03
SOURCE = "reference rig (synthetic stand-in for hardware)"
NOTE = "gap finder test case (tests/diagnosis); generated by bench/diagnosis/make_cases.py"


def overrides_text(overrides):
    return ",".join(f"{k}={v!r}" for k, v in overrides.items())


def rig_with(rig, overrides):
    """The --set text of the rig with a concealed effect; the effect's keys replace the rig's
    (soft-ground sets the contact CFM the rig also sets)."""
    kept = [item for item in rig.split(",") if item and item.split("=")[0] not in overrides]
    return ",".join(x for x in [",".join(kept), overrides_text(overrides)] if x)


def simulate(sim, genes, set_text, out_csv):
    cmd = [sim, "trajectory", "--robot", "caterpillar", "--genes", genes, "--cycles", str(CYCLES),
           "--settle", str(SETTLE), "--rate", str(RATE_HZ), "--threads", "1", "--out", out_csv]
    if set_text:
        cmd += ["--set", set_text]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"make_cases: {' '.join(cmd)} failed ({r.returncode}): {r.stderr.strip()}")


def read_csv(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f if line.strip()]
    data = np.array([[float(c) for c in row] for row in rows])
    return header, data


def distance_per_cycle(path):
    """Least-squares slope of the centroid x (mean of m*.x) over the file, times T."""
    header, data = read_csv(path)
    with open(path + ".json") as f:
        period = json.load(f)["command"]["genes"][12]
    xs = [i for i, h in enumerate(header) if h.endswith(".x")]
    centroid = data[:, xs].mean(axis=1)
    return float(np.polyfit(data[:, 0], centroid, 1)[0] * period)


def disguise(src_csv, dst_csv, seed):
    """Noise, marker offsets, time offset and dropped rows; a sidecar that names nothing."""
    rng = np.random.default_rng(seed)
    header, data = read_csv(src_csv)
    n = len(data)
    out = data.copy()
    out[:, 0] = data[:, 0] + TIME_SHIFT_S
    offsets = {}
    for marker in range(1, 7):
        for axis in ("x", "z"):
            name = f"m{marker}.{axis}"
            col = header.index(name)
            offsets[name] = float(rng.uniform(-OFFSET_MAX_M, OFFSET_MAX_M))
            out[:, col] = data[:, col] + offsets[name] + rng.normal(0.0, NOISE_SD_M, n)
    n_drop = int(round(DROP_FRACTION * (n - 2)))
    dropped = set(int(i) for i in rng.choice(np.arange(1, n - 1), size=n_drop, replace=False))
    with open(dst_csv, "w") as f:
        f.write(",".join(header) + "\n")
        for i in range(n):
            if i in dropped:
                continue
            cells = [f"{out[i, 0]:.6f}"]
            for j in range(1, len(header)):
                cells.append("0" if header[j].endswith(".y") else f"{out[i, j]:.9g}")
            f.write(",".join(cells) + "\n")
    with open(src_csv + ".json") as f:
        sidecar = json.load(f)
    clean = {"robot": sidecar["robot"], "command": sidecar["command"], "source": SOURCE,
             "note": NOTE}
    with open(dst_csv + ".json", "w") as f:
        f.write(json.dumps(clean, indent=2) + "\n")
    return {"marker_offsets_m": offsets, "rows": n - n_drop, "dropped_rows": n_drop}


def check(sim, path):
    r = subprocess.run([sim, "calibration-eval", "--recordings", path, "--threads", "1"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"make_cases: calibration-eval refused {path} ({r.returncode}): "
                 f"{r.stderr.strip()}")
    rec = json.loads(r.stdout)["recordings"][0]
    if not rec["valid"]:
        sys.exit(f"make_cases: {path}: not valid in calibration-eval: {rec['reason']}")
    return rec["metrics"]


def survey(sim, names=None):
    rigs = [(ts, cfm) for ts in ("0.001", "0.0005", "0.00025") for cfm in ("1e-5", "2e-5", "3e-5")]
    effects = [("none", {})] + [(c[0], c[2]) for c in CASES
                                if c[1] != "none" and (not names or c[0] in names)]
    print("distance per cycle (mm) of the clean trajectories, 10 cycles; rig = timestep, CFM")
    with tempfile.TemporaryDirectory() as tmp:
        for name, overrides in effects:
            for g in GAITS:
                cells = []
                for ts, cfm in rigs:
                    path = os.path.join(tmp, "s.csv")
                    simulate(sim, GAITS[g], rig_with(
                        f"simulation.timestep_s={ts},ground.contact_cfm={cfm}", overrides), path)
                    cells.append(1000 * distance_per_cycle(path))
                print(f"{name:13s} gait {g}: " + " ".join(f"{v:7.2f}" for v in cells)
                      + f"   mean {np.mean(cells):6.2f} sd {np.std(cells, ddof=1):5.2f}")
        print("rigs: " + " ".join(f"{ts}/{cfm}" for ts, cfm in rigs))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "diagnosis"),
                    help="output directory (default: tests/diagnosis)")
    ap.add_argument("--sim", default=SIM, help="gaitforge-sim binary (default: build/bin)")
    ap.add_argument("--rig", default=RIG,
                    help=f"the reference rig's overrides (default: {RIG})")
    ap.add_argument("--survey", action="store_true",
                    help="print the effects' travel on nearby rigs; write nothing")
    ap.add_argument("--cases", default="",
                    help="with --survey: only these cases (comma-separated names)")
    args = ap.parse_args()
    if not os.access(args.sim, os.X_OK):
        sys.exit(f"make_cases: no gaitforge-sim at {args.sim}; build first")
    if args.survey:
        survey(args.sim, [c for c in args.cases.split(",") if c])
        return 0

    start = time.time()
    answers = {}
    table = []
    with tempfile.TemporaryDirectory() as tmp:
        # The two references of the travel table, clean: the null rig and the model itself.
        ref = {}
        for g in GAITS:
            for label, set_text in (("rig", args.rig), ("model", "")):
                path = os.path.join(tmp, f"{label}-{g}.csv")
                simulate(args.sim, GAITS[g], set_text, path)
                ref[(label, g)] = distance_per_cycle(path)
        for ci, (case, effect_id, overrides, seed) in enumerate(CASES):
            case_dir = os.path.join(args.out, "cases", case)
            files = {"train": [], "held_out": []}
            nuisance = {}
            for gi, g in enumerate(GAITS):
                split = "train" if g in TRAIN else "held_out"
                os.makedirs(os.path.join(case_dir, split), exist_ok=True)
                raw = os.path.join(tmp, f"{case}-{g}.csv")
                simulate(args.sim, GAITS[g], rig_with(args.rig, overrides), raw)
                rel = f"{split}/gait-{g}.csv"
                dst = os.path.join(case_dir, rel)
                nuisance[rel] = disguise(raw, dst, seed * 10 + gi)
                metrics = check(args.sim, dst)
                files[split].append(rel)
                d = distance_per_cycle(raw)
                table.append((case, g, split, d, ref[("rig", g)], ref[("model", g)],
                              metrics.get("distance_ratio_0", float("nan")),
                              nuisance[rel]["dropped_rows"]))
            with open(os.path.join(case_dir, "case.json"), "w") as f:
                f.write(json.dumps({"robot": "caterpillar", "train": files["train"],
                                    "held_out": files["held_out"]}, indent=2) + "\n")
            answers[case] = {
                "effect": effect_id,
                "params": overrides,
                "rig": args.rig,
                "nuisance": {"nuisance.time_offset_s": -TIME_SHIFT_S,
                             "noise_sd_m": NOISE_SD_M, "files": nuisance},
            }
    # Cases derived from these (occlude_cases.py) keep their answers: rerun that script to
    # derive them again from the new sources.
    answers_path = os.path.join(args.out, "answers.sealed.json")
    if os.path.exists(answers_path):
        with open(answers_path) as f:
            for case, answer in json.load(f).items():
                if "derived_from" in answer and case not in answers:
                    answers[case] = answer
    with open(answers_path, "w") as f:
        f.write(json.dumps(answers, indent=2) + "\n")

    print(f"rig: {args.rig}; {CYCLES} cycles after {SETTLE} settle cycles at {RATE_HZ} Hz")
    print(f"disguise: noise sd {NOISE_SD_M * 1000:g} mm, marker offsets within "
          f"+-{OFFSET_MAX_M * 1000:g} mm, t + {TIME_SHIFT_S:g} s, {DROP_FRACTION:.0%} rows dropped")
    print("distance per cycle (mm) of the clean centroid: case (effect on the rig) vs null rig "
          "vs the diagnosed model; eval ratio = real/sim distance from calibration-eval at the "
          "model")
    print(f"{'case':13s} gait split     case    null  model  case-null   eval ratio  dropped")
    for case, g, split, d, d_rig, d_model, ratio, drops in table:
        print(f"{case:13s} {g:4s} {split:8s} {1000 * d:7.2f} {1000 * d_rig:7.2f} "
              f"{1000 * d_model:6.2f} {1000 * (d - d_rig):+9.2f}   {ratio:9.3f}  {drops:5d}")
    print("wrote:")
    for case, *_ in CASES:
        print(f"  {os.path.relpath(os.path.join(args.out, 'cases', case))}/"
              "{case.json,train/gait-a.csv,train/gait-b.csv,held_out/gait-c.csv} (+ .json)")
    print(f"  {os.path.relpath(os.path.join(args.out, 'answers.sealed.json'))} (sealed)")
    print(f"done in {time.time() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
