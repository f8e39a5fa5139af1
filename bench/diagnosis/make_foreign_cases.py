#!/usr/bin/python3
"""Foreign test cases for the gap finder: recordings from an independent simulator
(bench/diagnosis/rig2d.py: finer lumps, penalty contact with finite friction, bushings,
semi-implicit Euler at 50 us) with effects written in forms of its own, disguised like the
shipped cases (noise, marker offsets, time offset, dropped rows; make_cases.disguise).

The answers name the catalog effect(s) a diagnosis may call it (`accept`), and where the
forms are comparable, the library parameter's equivalent value (a 30-degree hose's
horizontal pull, for example). run_suite.py scores them with --suite tests/diagnosis/foreign.

--build mujoco makes a second suite (default --out tests/diagnosis/foreign-mujoco) from the
caterpillar's MuJoCo build (bench/independent/caterpillar_mujoco.cc: generalised
coordinates, soft convex contact with mu 2, tendon pistons), with its own effects and
magnitudes (MUJOCO_CASES): a suite the gap finder was not tuned on.

    /usr/bin/python3 bench/diagnosis/make_foreign_cases.py [--out tests/diagnosis/foreign]
        [--build rig2d|mujoco]
"""
import argparse
import json
import math
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_cases  # noqa: E402  (disguise, check, distance_per_cycle, gaits)
import mujoco_caterpillar  # noqa: E402
import rig2d  # noqa: E402

COS30 = math.cos(math.radians(30))
# case: (rig effects, truth, accepted ids, library-equivalent params, seed)
CASES = [
    ("foreign-null-a", {}, "none", [], {}, 201),
    ("foreign-null-b", {"contact_k": 5e4}, "none", [], {}, 202),
    # Another tuning of the rig's contact law: half as damped, a tangential spring 3x stiffer.
    ("foreign-null-c", {"contact_zeta": 0.25, "stick_k": 6e4}, "none", [], {}, 210),
    ("foreign-hose", {"hose_n": 0.3}, "tether.constant", ["tether.constant", "tether.growing"],
     {"effect.tether_force_n": 0.3 * COS30}, 203),
    # The paper's story at full strength: a hose pulling 0.8 N (0.69 N horizontal).
    ("foreign-hose-strong", {"hose_n": 0.8}, "tether.constant",
     ["tether.constant", "tether.growing"], {"effect.tether_force_n": 0.8 * COS30}, 211),
    ("foreign-drag", {"drag2_n_s2_per_m2": 40.0}, "friction.viscous", ["friction.viscous"], {}, 205),
    ("foreign-lag", {"actuator_lag_s": 0.04}, "actuator.lag", ["actuator.lag", "actuator.delay"],
     {"effect.actuator_lag_s": 0.04}, 206),
    ("foreign-lag-strong", {"actuator_lag_s": 0.08}, "actuator.lag",
     ["actuator.lag", "actuator.delay"], {"effect.actuator_lag_s": 0.08}, 212),
    ("foreign-weak", {"force_scale": 0.8}, "actuator.force_scale", ["actuator.force_scale"],
     {"actuators.force_n": 0.8 * 8.8}, 207),
    # Seal friction sliding at 0.8 N with a 1.2 N breakaway: the library's deadband is one
    # band F (taken as 1.0 N, between the two).
    ("foreign-seal", {"seal_n": 0.8, "seal_break_n": 1.2}, "actuator.deadband",
     ["actuator.deadband"], {"effect.actuator_deadband_n": 1.0}, 208),
    # Lumps of a softer silicone, 150 kPa instead of the rig's 435 (shear included): the
    # library's half-lumps have the same beam without shear, compliance 1/E = 6.7 /MPa.
    ("foreign-soft", {"lump_modulus_pa": 150e3}, "model.resolution", ["model.resolution"],
     {"effect.lump_compliance_per_mpa": 1 / 0.15}, 209),
    # Session 13: lossier links, their axial and bending damping 3x the rig's critical; the
    # lumps' silicone and the links' stiff shear rows keep theirs (the library's scale
    # multiplies the links' two ratios, and has no shear row to damp).
    ("foreign-lossy", {"link_damping_scale": 3.0}, "damping.scale", ["damping.scale"],
     {"scale.link_damping": 3.0}, 213),
]

# The MuJoCo build's cases: its hose pulls straight back (the library's tether is the same
# form), its drag is linear, its slope tilts gravity; magnitudes chosen before any run of
# the gap finder on this build, none equal to a rig2d case's.
MUJOCO_CASES = [
    ("mujoco-null", {}, "none", [], {}, 301),
    ("mujoco-hose", {"hose_n": 0.4}, "tether.constant", ["tether.constant", "tether.growing"],
     {"effect.tether_force_n": 0.4}, 302),
    # The growing hoses count their travel from x = 0, not from where the markers rest
    # (x = 0.08 m): the build read its rest position before any kinematics ran until session
    # 49, and these cases were recorded so. Their pull is 0.1 + 4 x 0.08 = 0.42 N at rest,
    # growing by 4 N/m of travel (and shrinking when the robot backs off): the library's
    # tether.growing with 0.42 N for a robot that walks forward. hose_anchor_x_m keeps them.
    ("mujoco-hose-growing", {"hose_n": 0.1, "hose_n_per_m": 4.0, "hose_anchor_x_m": 0.0},
     "tether.growing", ["tether.growing", "tether.constant"],
     {"effect.tether_force_n": 0.42, "effect.tether_stiffness_n_per_m": 4.0}, 303),
    ("mujoco-drag", {"drag_n_s_per_m": 1.5}, "friction.viscous", ["friction.viscous"],
     {"effect.drag_n_s_per_m": 1.5}, 304),
    ("mujoco-lag", {"actuator_lag_s": 0.06}, "actuator.lag", ["actuator.lag", "actuator.delay"],
     {"effect.actuator_lag_s": 0.06}, 305),
    ("mujoco-weak", {"force_scale": 0.75}, "actuator.force_scale", ["actuator.force_scale"],
     {"actuators.force_n": 0.75 * 8.8}, 306),
    ("mujoco-slope", {"slope_rad": 0.08}, "ground.slope", ["ground.slope"],
     {"effect.slope_rad": 0.08}, 307),
    # Session 40, sealed from tuning (issue 25: three nulls, two magnitudes per effect): two
    # nulls of another build of the same robot (a slipperier floor; a softer contact), and
    # each effect at about twice the first magnitude, chosen before any run on them.
    ("mujoco-null-slippery", {"ground_mu": 0.8}, "none", [], {}, 308),
    ("mujoco-null-soft", {"contact_time_s": 0.005}, "none", [], {}, 309),
    ("mujoco-hose-strong", {"hose_n": 0.8}, "tether.constant",
     ["tether.constant", "tether.growing"], {"effect.tether_force_n": 0.8}, 310),
    ("mujoco-hose-growing-strong", {"hose_n": 0.2, "hose_n_per_m": 8.0, "hose_anchor_x_m": 0.0},
     "tether.growing", ["tether.growing", "tether.constant"],
     {"effect.tether_force_n": 0.84, "effect.tether_stiffness_n_per_m": 8.0}, 311),
    ("mujoco-drag-strong", {"drag_n_s_per_m": 3.0}, "friction.viscous", ["friction.viscous"],
     {"effect.drag_n_s_per_m": 3.0}, 312),
    ("mujoco-lag-strong", {"actuator_lag_s": 0.12}, "actuator.lag",
     ["actuator.lag", "actuator.delay"], {"effect.actuator_lag_s": 0.12}, 313),
    ("mujoco-weak-strong", {"force_scale": 0.5}, "actuator.force_scale",
     ["actuator.force_scale"], {"actuators.force_n": 0.5 * 8.8}, 314),
    ("mujoco-slope-strong", {"slope_rad": 0.16}, "ground.slope", ["ground.slope"],
     {"effect.slope_rad": 0.16}, 315),
]
BUILDS = {"rig2d": (CASES, "foreign", "bench/diagnosis/rig2d.py"),
          "mujoco": (MUJOCO_CASES, "foreign-mujoco", "bench/independent/caterpillar_mujoco.cc")}


def build_of(answer):
    """The independent build a case's answer was recorded on ("rig2d", "mujoco"), or None."""
    return next((b for b, (_, _, rig) in BUILDS.items() if answer.get("rig") == rig), None)


def record_gait(build, genes, effects, dst, seed, settle=make_cases.SETTLE,
                cycles=make_cases.CYCLES):
    """One gait recorded on an independent build under `effects`, disguised as the suites
    are (make_cases.disguise), at `dst` with its sidecar; returns the clean centroid's travel
    per cycle (m)."""
    times, markers = simulate(build, genes, [effects], settle=settle, cycles=cycles)
    with tempfile.TemporaryDirectory() as tmp:
        raw = os.path.join(tmp, "raw.csv")
        rig2d.write_csv(raw, times, markers[0])
        with open(raw + ".json", "w") as f:
            json.dump({"robot": "caterpillar", "command": {"kind": "gait", "genes": list(genes)}}, f)
        os.makedirs(os.path.dirname(os.path.abspath(dst)), exist_ok=True)
        make_cases.disguise(raw, dst, seed)
        return make_cases.distance_per_cycle(raw)


def simulate(build, genes, effects, settle=make_cases.SETTLE, cycles=make_cases.CYCLES):
    """(times, markers[run, sample, lump, (x, z)]) of one gait under each effects dict."""
    if build == "rig2d":
        return rig2d.simulate(genes, effects, settle=settle, cycles=cycles,
                              rate_hz=make_cases.RATE_HZ)
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        for k, e in enumerate(effects):
            path = os.path.join(tmp, f"{k}.csv")
            mujoco_caterpillar.record(path, genes, e, settle=settle, cycles=cycles,
                                      rate_hz=make_cases.RATE_HZ)
            a = np.genfromtxt(path, delimiter=",", names=True)
            runs.append(np.stack([np.stack([a[f"m{i}x"], a[f"m{i}z"]], axis=1)
                                  for i in range(1, 7)], axis=1))
            times = a["t"]
    return times, np.array(runs)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default="rig2d", choices=sorted(BUILDS))
    ap.add_argument("--out", default="")
    ap.add_argument("--sim", default=make_cases.SIM, help="gaitforge-sim, to check each file")
    ap.add_argument("--cases", default="",
                    help="only these cases, comma separated; the others' files and answers stay "
                         "as they are (a batch of another size may differ in the last bits of "
                         "the chaotic trajectories)")
    ap.add_argument("--extra-train", type=int, default=0, metavar="N",
                    help="also train on N random gaits (r0 .. rN-1, 12 phases uniform, period "
                         "0.2 .. 1 s, as bench/transfer.py's calibration gaits): a structure "
                         "differing everywhere needs more gaits than the effect alone")
    args = ap.parse_args()
    all_cases, folder, rig = BUILDS[args.build]
    gaits = dict(make_cases.GAITS)
    rng = np.random.default_rng(3)
    for i in range(args.extra_train):
        gaits[f"r{i}"] = ",".join(repr(float(x)) for x in
                                  list(rng.random(12)) + [float(rng.uniform(0.2, 1.0))])
    train = make_cases.TRAIN + [f"r{i}" for i in range(args.extra_train)]
    args.out = args.out or os.path.join(make_cases.ROOT, "tests", "diagnosis", folder)
    cases = all_cases
    answers_path = os.path.join(args.out, "answers.sealed.json")
    if args.cases:
        wanted = args.cases.split(",")
        unknown = sorted(set(wanted) - {c[0] for c in all_cases})
        if unknown:
            print(f"--cases: unknown case(s) {', '.join(unknown)}; known: "
                  f"{', '.join(c[0] for c in all_cases)}", file=sys.stderr)
            return 2
        cases = [c for c in all_cases if c[0] in wanted]
    make_cases.SOURCE = "independent rig (synthetic stand-in for hardware)"
    make_cases.NOTE = ("gap finder foreign case (tests/diagnosis/foreign); generated by "
                       "bench/diagnosis/make_foreign_cases.py")
    start = time.time()
    answers, table = {}, []
    if args.cases and os.path.exists(answers_path):
        with open(answers_path) as f:
            answers = {k: v for k, v in json.load(f).items() if k not in {c[0] for c in cases}}
    with tempfile.TemporaryDirectory() as tmp:
        for gi, (g, text) in enumerate(gaits.items()):
            genes = [float(x) for x in text.split(",")]
            t0 = time.time()
            times, markers = simulate(args.build, genes, [c[1] for c in cases])
            print(f"gait {g}: {len(cases)} runs in {time.time() - t0:.0f} s", flush=True)
            split = "train" if g in train else "held_out"
            for ci, (case, _, truth, accept, params, seed) in enumerate(cases):
                raw = os.path.join(tmp, f"{case}-{g}.csv")
                rig2d.write_csv(raw, times, markers[ci])
                with open(raw + ".json", "w") as f:
                    json.dump({"robot": "caterpillar", "command": {"kind": "gait", "genes": genes}}, f)
                case_dir = os.path.join(args.out, "cases", case)
                os.makedirs(os.path.join(case_dir, split), exist_ok=True)
                rel = f"{split}/gait-{g}.csv"
                nuisance = make_cases.disguise(raw, os.path.join(case_dir, rel), seed * 10 + gi)
                make_cases.check(args.sim, os.path.join(case_dir, rel))
                table.append((case, g, 1000 * make_cases.distance_per_cycle(raw)))
                a = answers.setdefault(case, {"effect": truth, "accept": accept, "params": params,
                                              "rig": rig,
                                              "rig_effects": cases[ci][1], "files": {}})
                a["files"][rel] = nuisance
    for case, *_ in cases:
        with open(os.path.join(args.out, "cases", case, "case.json"), "w") as f:
            f.write(json.dumps({"robot": "caterpillar",
                                "train": [f"train/gait-{g}.csv" for g in train],
                                "held_out": [f"held_out/gait-{g}.csv" for g in make_cases.HELD_OUT]},
                               indent=2) + "\n")
    answers = {c[0]: answers[c[0]] for c in all_cases if c[0] in answers}
    with open(answers_path, "w") as f:
        f.write(json.dumps(answers, indent=2) + "\n")
    print("distance per cycle (mm) of the clean centroid on the independent rig:")
    by_case = {}
    for case, g, d in table:
        by_case.setdefault(case, {})[g] = d
    print(f"{'case':22s} " + " ".join(f"{g:>8s}" for g in gaits))
    for case, ds in by_case.items():
        print(f"{case:22s} " + " ".join(f"{ds[g]:8.2f}" for g in gaits))
    print(f"done in {time.time() - start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
