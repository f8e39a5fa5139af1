#!/usr/bin/python3
"""Transfer benchmark (issue 26): do evolved gaits walk on a build of the robot they were
not evolved on?

Evolves the caterpillar's 13-gene gait through the real CLI (`gaitforge local`, 2 workers,
SQLite files): with the paper's fitness; with robust evaluation (the gap finder's six
numeric variants, several cycles, mean - k sd) for the same number of generations; and with
the paper's fitness for the robust study's budget of simulations (six times the
generations: one simulation per genotype against six). Then runs gaits of each study on two
independent builds, bench/diagnosis/rig2d.py (sub-lumps, penalty contact, 50 us Euler) and
bench/independent/caterpillar_mujoco.cc (MuJoCo: generalised coordinates, soft convex
contact, tendon pistons), with nothing concealed and with concealed hoses.

--calibrate closes the loop through the structure, with nothing concealed: the three gaits
and CALIBRATION_GAITS random ones recorded on each build, a calibration of what the model
idealises (STRUCTURE: friction and contact, stiffness and damping, force, lump compliance)
on all but one of them, and a robust study started from it (`objective.from_calibration`),
measured on that build. --rounds R repeats it R times, as a user with the robot would:
each round records the last study's --record-best best distinct gaits on the build and adds
them to the calibration's recordings, so the next calibration sees what the GA exploited;
each round's gaits are also predicted again by the next round's model (transfer.json's
`repredicted`: a study's gaits ranked by the model that has seen some of them walk).
--rerank (with --rounds 2) skips the second evolution: the second calibration runs in the
first round's database and ranks the first study's gaits by itself (`gaitforge validate
STUDY --from-calibration CAL`), the product's one-command form of that step.
--structure NAMES calibrates only those of STRUCTURE's parameters; --select-structure also
calibrates each alone and keeps the fit with the lowest training error over the model's
step and the gap finder's timestep variants (structure chosen by evidence).

--diagnose closes the loop on each build: three gaits recorded on the build with the strong
hose concealed (make_cases.GAITS: two for training, one held out), `gaitforge diagnose` on
them, and a robust study started from that diagnosis (`objective.from_diagnosis`); its
gaits are measured on that build and hose only, the robot it was corrected for.

For each study and set (the 20 best distinct gaits of the whole study; 20 distinct gaits
spread over the final population's ranks) it prints the ratio of achieved to predicted
travel (sums over the set; predicted = the study's fitness, or for a robust study the
ensemble mean, robust.mean), the Spearman rank correlation of predicted and achieved
travel, and the best gait's achieved travel. --validate M also predicts each robust
study's gaits over a fresh ensemble of M members (`gaitforge validate`: one the study's
selection never saw) and prints the ratio and correlation against that prediction too.

    /usr/bin/python3 bench/transfer.py [--bin build/bin] [--population 100]
        [--generations 30] [--builds rig2d,mujoco] [--diagnose] [--quick]

Prints a table and writes transfer.json (every gait's genes, predictions and travel too) and
transfer.svg (achieved against predicted travel per gait) in --out. --quick: a smoke run (small studies,
few gaits) to check the pipeline, not a measurement.
"""
import argparse
import json
import os
import sqlite3
import struct
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "diagnosis"))
import make_cases  # noqa: E402  (the gap finder's recording gaits and lengths)
import mujoco_caterpillar  # noqa: E402
import rig2d  # noqa: E402
from transfer_report import agreement, per_gait, plot, table  # noqa: E402

ROBUST_MEMBERS = 6  # numerics: [standard] on the caterpillar
ROBUST_K = 0.5  # the robust studies' statistic, mean - k sd (--robust-k)
BUILDS = {"rig2d": rig2d, "mujoco": mujoco_caterpillar}
STRONG_HOSE = "hose 0.4 N"
SCENARIOS = {"nothing concealed": {}, "hose 0.05 N + 0.5 N/m": {"hose_n": 0.05, "hose_n_per_m": 0.5},
             STRONG_HOSE: {"hose_n": 0.4}}


# --structural: the robust study's ensemble also samples the model's idealisations, over
# physical priors rather than any build's values: a finite friction of silicone on a floor
# instead of no slip, deformable lumps (the paper's silicone is 2.3 /MPa; 0 is rigid) and
# the links' damping off by up to 2x.
STRUCTURAL = ("    parameters:\n"
              "      - {name: ground.friction_coefficient, lo: 1.0, hi: 3.0}\n"
              "      - {name: effect.lump_compliance_per_mpa, lo: 0.0, hi: 5.0}\n"
              "      - {name: scale.link_damping, lo: 0.5, hi: 2.0}\n")


# --calibrate: what the ODE model idealises, fitted on recordings of the build (ranges wide
# enough for any plausible build of the robot, not any one build's values), and the number
# of random gaits recorded beside make_cases.GAITS. Since session 41 with a creeping contact
# (effects contact.creep), which regularised contact laws and soft feet have.
STRUCTURE = [("ground.friction_coefficient", 0.3, 5.0), ("ground.contact_cfm", 1e-6, 1e-3),
             ("scale.link_stiffness", 0.5, 2.0), ("scale.link_damping", 0.3, 3.0),
             ("actuators.force_n", 5.0, 12.0), ("effect.lump_compliance_per_mpa", 0.0, 5.0),
             ("effect.contact_slip_m_per_n_s", 1e-5, 1.0), ("nuisance.time_offset_s", -0.05, 0.05)]
OFFSET = STRUCTURE[-1][0]  # a nuisance, fitted with every family
CALIBRATION_GAITS = 3
# --select-structure: each structural parameter calibrated alone (with the time offset) on
# this budget (CMA-ES on two genes converges within it); the fits are compared at the
# gap finder's timestep variants too (robots/numerics.cc; its contact softness variants
# would overwrite a fitted softness).
SINGLE_EVALUATIONS = 300
STEP_VARIANTS = ["simulation.timestep_s=0.0005", "simulation.timestep_s=0.00075",
                 "simulation.timestep_s=0.00125"]


def spec(name, population, generations, robust, diagnosis="", structural=False, calibration="",
         k=ROBUST_K, seed=1, sampling="box"):
    text = (f"name: {name}\nseed: {seed}\nengine: ga\npopulation: {population}\n"
            f"generations: {generations}\nga: {{elite: 10, mutation_rate: 0.10}}\n"
            "objective:\n  name: caterpillar.distance\n")
    if diagnosis:
        text += f"  from_diagnosis: {diagnosis}\n"
    if calibration:
        text += f"  from_calibration: {calibration}\n"
    if not robust:
        return text + "  params: {cycles: 1, settle_cycles: 2}\n"
    fits = "    sampling: fits\n" if calibration and sampling == "fits" else ""
    return text + ("  params: {cycles: 2, settle_cycles: 1}\n"
                   "  robust:\n    numerics: [standard]\n"
                   f"    statistic: mean_minus_sd\n    k: {k}\n" + fits) + (
                       STRUCTURAL if structural else "")


def evolve(args, name, generations, robust, db=None, diagnosis="", structural=False, calibration=""):
    if db is None:
        db = os.path.join(args.out, f"{name}.db")
        if os.path.exists(db):
            os.remove(db)
    path = os.path.join(args.out, f"{name}.yaml")
    with open(path, "w") as f:
        f.write(spec(name, args.population, generations, robust, diagnosis, structural, calibration,
                     args.robust_k, args.seed, args.sampling))
    t0 = time.monotonic()
    r = subprocess.run([os.path.join(args.bin, "gaitforge"), "--db", db, "local", path,
                        "--workers", "2"], capture_output=True, text=True)
    wall = time.monotonic() - t0
    if r.returncode != 0:
        sys.exit(f"transfer: {name} failed ({r.returncode}): {r.stderr[-2000:]}")
    return db, wall


def genes_of(blob):
    return list(struct.unpack(f"<{len(blob) // 8}d", blob))


def same_gait(a, b):
    """Equal up to one shift of all 12 phases (the hall of fame's rule)."""
    if abs(a[12] - b[12]) > 1e-9:
        return False
    d = [((x - y) % 1.0) for x, y in zip(a[:12], b[:12])]
    return all(min(abs(x - d[0]), 1 - abs(x - d[0])) < 1e-9 for x in d)


def study_id(db, name):
    """The newest completed study named `name` in `db` (a --reuse database may also hold an
    interrupted one of the same name)."""
    row = sqlite3.connect(db).execute(
        "SELECT study_id FROM studies WHERE name = ? AND state = 'completed' "
        "ORDER BY created_ms DESC LIMIT 1", (name,)).fetchone()
    if row is None:
        sys.exit(f"transfer: {db} holds no completed study named {name}")
    return row[0]


def individuals(db, robust, study):
    """(generation, fitness, predicted, genes) of every valid individual the study named
    `study` evaluated, and (fitness, predicted, genes) of its final population."""
    con = sqlite3.connect(db)
    sid = study_id(db, study)
    rows = con.execute("SELECT generation, member, genes, fitness FROM individuals "
                       "WHERE study_id = ? AND valid = 1 AND carried = 0", (sid,)).fetchall()
    mean = dict(((g, m), v) for g, m, v in con.execute(
        "SELECT generation, member, value FROM metrics WHERE study_id = ? AND name = 'robust.mean'",
        (sid,)))
    out = []
    for g, m, blob, fit in rows:
        out.append((g, fit, mean.get((g, m), fit) if robust else fit, genes_of(blob)))
    last = con.execute("SELECT MAX(generation) FROM individuals WHERE study_id = ?", (sid,)).fetchone()[0]
    # A carried elite's metrics are stored once, with the evaluation it was carried from.
    rows = con.execute("SELECT origin_generation, origin_member, genes, fitness FROM individuals "
                       "WHERE study_id = ? AND valid = 1 AND generation = ?", (sid, last)).fetchall()
    if robust and any((g, m) not in mean for g, m, _, _ in rows):
        sys.exit(f"transfer: {study}: a final member without robust.mean")
    final = [(fit, mean[(g, m)] if robust else fit, genes_of(blob)) for g, m, blob, fit in rows]
    return out, final


def distinct(ranked, n, every=1):
    chosen = []
    for k, item in enumerate(ranked):
        if k % every:
            continue
        if any(same_gait(item[-1], c[-1]) for c in chosen):
            continue
        chosen.append(item)
        if len(chosen) == n:
            break
    return chosen


def gait_sets(db, robust, n, study):
    every, final = individuals(db, robust, study)
    best = distinct(sorted(every, key=lambda r: -r[1]), n)
    final.sort(key=lambda r: -r[0])
    spread = distinct(final, n, every=max(1, len(final) // n))
    return {"best": [(p, g) for _, _, p, g in best], "spread": [(p, g) for _, p, g in spread]}


def measure(sets, where, cycles):
    """Achieved travel per cycle of every gait of every set, on every (build, scenario) of
    where[study], one batch per build."""
    achieved = {}
    for build, module in BUILDS.items():
        runs = [(study, kind, i, scen) for study in sets for kind in sets[study]
                for i in range(len(sets[study][kind])) for b, scen in where[study] if b == build]
        if not runs:
            continue
        t0 = time.monotonic()
        genes = [sets[s][k][i][1] for s, k, i, _ in runs]
        out = module.travel(genes, [SCENARIOS[scen] for *_, scen in runs], settle=1, cycles=cycles)
        achieved.update({(build,) + run: a for run, a in zip(runs, out)})
        print(f"{build}: {len(runs)} runs in {time.monotonic() - t0:.0f} s", flush=True)
    return achieved


def validate(args, db, study, sets, label="", calibration=""):
    """Each gait of `sets` (kind -> [(predicted, genes)]) of robust study `study` over a
    fresh ensemble of --validate members (`gaitforge validate`; with `calibration`, of that
    calibration's model: --from-calibration); kind -> validated means."""
    gf = [os.path.join(args.bin, "gaitforge"), "--db", db]
    ident = study_id(db, study)
    out = {}
    for kind, gaits in sets.items():
        path = os.path.join(args.out, f"{label or study}-{kind}.gaits")
        with open(path, "w") as f:
            f.writelines(" ".join(repr(x) for x in genes) + "\n" for _, genes in gaits)
        t0 = time.monotonic()
        extra = ["--from-calibration", calibration] if calibration else []
        r = subprocess.run(gf + ["validate", ident, "--gaits", path, "--members", str(args.validate),
                                 "--workers", "2", "--json"] + extra, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"transfer: validate {study} {kind} failed ({r.returncode}): {r.stderr[-2000:]}")
        rows = json.loads(r.stdout)["gaits"]
        out[kind] = [g["validated"]["mean"] if g["valid"] else float("nan") for g in rows]
        print(f"validated {study} {kind}: {len(rows)} gaits x {args.validate} members in "
              f"{time.monotonic() - t0:.0f} s", flush=True)
    return out


def record_one(build, path, genes, effects):
    """One gait recorded on `build` as the gap finder's cases are (length, rate), with its
    sidecar."""
    if build == "rig2d":
        times, markers = rig2d.simulate(genes, [effects], settle=make_cases.SETTLE,
                                        cycles=make_cases.CYCLES, rate_hz=make_cases.RATE_HZ)
        rig2d.write_csv(path, times, markers[0])
    else:
        mujoco_caterpillar.record(path, genes, effects, settle=make_cases.SETTLE,
                                  cycles=make_cases.CYCLES, rate_hz=make_cases.RATE_HZ)
    with open(path + ".json", "w") as f:
        json.dump({"robot": "caterpillar", "command": {"kind": "gait", "genes": genes}}, f)


def record_case(args, build, folder):
    """The gap finder's three gaits recorded on `build` with the strong hose; returns the
    diagnosis spec's path."""
    files = {}
    for g, text in make_cases.GAITS.items():
        files[g] = os.path.join(folder, f"gait-{g}.csv")
        record_one(build, files[g], [float(x) for x in text.split(",")], SCENARIOS[STRONG_HOSE])
    spec_path = os.path.join(folder, "diagnosis.yaml")
    with open(spec_path, "w") as f:
        f.write(f"name: hose-on-{build}\nseed: 1\nrobot: caterpillar\n"
                f"training: [{', '.join(files[g] for g in make_cases.TRAIN)}]\n"
                f"held_out: [{', '.join(files[g] for g in make_cases.HELD_OUT)}]\n"
                f"screening_evaluations: {args.screening}\nfull_evaluations: {args.full}\n")
    return spec_path


def diagnose_and_evolve(args, build):
    """Diagnoses the strong hose on `build`, then evolves robustly from the diagnosis.
    Returns (db, wall seconds, what the diagnosis named)."""
    folder = os.path.join(args.out, f"diagnosis-{build}")
    os.makedirs(folder, exist_ok=True)
    db = os.path.join(args.out, f"diagnosed-{build}.db")
    if os.path.exists(db):
        os.remove(db)
    gf = [os.path.join(args.bin, "gaitforge"), "--db", db]
    t0 = time.monotonic()
    r = subprocess.run(gf + ["--out", folder, "diagnose", record_case(args, build, folder), "--json",
                             "--workers", "2"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"transfer: diagnosis on {build} failed ({r.returncode}): {r.stderr[-2000:]}")
    report = json.loads(r.stdout)
    named = ", ".join(f"{e['id']} {e.get('params', '')}" for e in report.get("effects", []))
    print(f"diagnosis on {build}: {report['verdict']} {named} ({time.monotonic() - t0:.0f} s)",
          flush=True)
    listed = json.loads(subprocess.run(gf + ["diagnoses", "--json"], capture_output=True,
                                       text=True, check=True).stdout)
    last = listed["diagnoses"][-1]
    ident = last.get("diagnosis_id") or last.get("diagnosisId")
    if report["verdict"] != "found":
        return None, time.monotonic() - t0, f"{report['verdict']}: nothing to correct"
    db, wall = evolve(args, f"diagnosed-{build}", args.generations, True, db=db, diagnosis=ident)
    return db, time.monotonic() - t0, named


def record_gaits(build, folder, effects):
    """make_cases.GAITS and CALIBRATION_GAITS random gaits recorded on `build` (recording
    length and rate as the gap finder's cases); returns their CSV paths."""
    gaits = {g: [float(x) for x in text.split(",")] for g, text in make_cases.GAITS.items()}
    rng = np.random.default_rng(3)
    for i in range(CALIBRATION_GAITS):
        gaits[f"r{i}"] = list(rng.random(12)) + [float(rng.uniform(0.2, 1.0))]
    paths = []
    for g, genes in gaits.items():
        paths.append(os.path.join(folder, f"gait-{g}.csv"))
        record_one(build, paths[-1], genes, effects)
    return paths


def completed(db, name):
    """Whether `db` holds a completed study named `name` (--reuse)."""
    if not os.path.exists(db):
        return False
    try:
        row = sqlite3.connect(db).execute("SELECT state FROM studies WHERE name = ?",
                                          (name,)).fetchone()
    except sqlite3.OperationalError:  # a file that is no gaitforge database (yet)
        return False
    return bool(row) and row[0] == "completed"


def log_mark(lo, hi):
    """`, log: true` for a range of two decades or more (searched by its logarithm, as the
    gap finder judges such ranges: LogScaled in services/diagnosis/decision.cc)."""
    return ", log: true" if lo > 0 and hi >= 100 * lo else ""


def calibrate(args, build, folder, db, name, training, held_out, family, evaluations):
    """CMA-ES over `family` on `training` recordings of `build`; returns (study id, fit, its
    training error)."""
    bounds = "".join(f"  - {{name: {n}, lo: {lo}, hi: {hi}{log_mark(lo, hi)}}}\n"
                     for n, lo, hi in family)
    path = os.path.join(folder, f"{name}.yaml")
    with open(path, "w") as f:
        f.write(f"name: {name}\nseed: 1\nengine: cmaes\npopulation: 10\n"
                f"generations: 200\nobjective:\n  name: caterpillar.calibration\n"
                f"  options: {{error: shape, metric: rmse}}\n"
                f"  recordings: [{', '.join(training)}]\n  held_out: [{held_out}]\n"
                f"bounds:\n{bounds}cmaes: {{sigma0: 0.25, restarts: none, "
                f"max_evaluations: {evaluations}}}\n")
    gf = [os.path.join(args.bin, "gaitforge"), "--db", db]
    if not (args.reuse and completed(db, name)):
        r = subprocess.run(gf + ["--out", folder, "local", path, "--workers", "2", "--dashboard",
                                 "off"], capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"transfer: calibration on {build} failed ({r.returncode}): {r.stderr[-2000:]}")
    studies = json.loads(subprocess.run(gf + ["list", "--json"], capture_output=True, text=True,
                                        check=True).stdout)["studies"]
    ident = next(s["study_id"] for s in studies if s["spec"]["name"] == name)
    hof = json.loads(subprocess.run(gf + ["hof", ident, "--json"], capture_output=True, text=True,
                                    check=True).stdout)
    best = hof["entries"][0]["individual"]
    return ident, {n: g for (n, *_), g in zip(family, best["genes"])}, -best["evaluation"]["fitness"]


def select_structure(args, build, folder, db, name, training, held_out):
    """The --structure family calibrated on `training`; with --select-structure also each of
    its parameters alone (with the time offset, SINGLE_EVALUATIONS each), and the fit kept
    whose training error is lowest on average over the model's own step and the gap
    finder's timestep variants (STEP_VARIANTS): structure chosen by evidence across the
    recordings that does not rest on the step it was fitted at. Returns (study id, fit, the
    chosen family's key, every family's errors)."""
    family = structure_family(args)
    fits = {"family": calibrate(args, build, folder, db, name, training, held_out, family,
                                args.calibration_evaluations)}
    offset = [e for e in family if e[0] == OFFSET]
    for entry in family if args.select_structure else ():
        if entry[0] != OFFSET:
            single = [entry] + offset
            fits[entry[0]] = calibrate(args, build, folder, db, f"{name}-{entry[0]}", training,
                                       held_out, single,
                                       min(SINGLE_EVALUATIONS, args.calibration_evaluations))
    errors = {k: step_errors(args, training, fit) for k, (_, fit, _) in fits.items()}
    chosen = min(fits, key=lambda k: np.mean(errors[k]))
    return fits[chosen][0], fits[chosen][1], chosen, errors


def step_errors(args, recordings, fit):
    """The mean training error of `fit` at the model's step and at each of STEP_VARIANTS."""
    values = ",".join(f"{n}={v!r}" for n, v in fit.items())
    out = []
    for variant in [""] + STEP_VARIANTS:
        r = subprocess.run([os.path.join(args.bin, "gaitforge-sim"), "calibration-eval",
                            "--recordings", ",".join(recordings), "--set",
                            values + ("," + variant if variant else "")],
                           capture_output=True, text=True, check=True)
        rows = json.loads(r.stdout)["recordings"]
        out.append(float(np.mean([x["metrics"]["error"] if x["valid"] else np.inf for x in rows])))
    return out


def structure_family(args):
    """STRUCTURE's entries that --structure names (all by default), with the time offset."""
    if not args.structure:
        return STRUCTURE
    names = args.structure.split(",")
    unknown = sorted(set(names) - {n for n, *_ in STRUCTURE})
    if unknown:
        sys.exit(f"--structure: unknown {', '.join(unknown)}; known: "
                 f"{', '.join(n for n, *_ in STRUCTURE)}")
    return [s for s in STRUCTURE if s[0] in names or s[0] == OFFSET]


def calibrate_and_evolve(args, build):
    """Calibrates the model's structure on recordings of `build` (nothing concealed), then
    evolves robustly from that calibration; with --rounds R, R times, each round adding the
    --record-best best distinct gaits of the last study, recorded on the build, to the
    calibration's training recordings. Yields (study name, db, wall seconds, the fit) per
    round; with --rerank the second round only calibrates, in the first round's database, and
    yields the calibration's name, its fit holding `rerank`: its study id."""
    folder = os.path.join(args.out, f"calibration-{build}")
    os.makedirs(folder, exist_ok=True)
    paths = record_gaits(build, folder, {})
    training, held_out = paths[:-1], paths[-1]
    for rnd in range(args.rounds):
        base = f"calibrated-{build}" + (f"-r{rnd + 1}" if rnd else "")
        rerank = args.rerank and rnd > 0
        if not rerank:
            db = os.path.join(args.out, f"{base}.db")
        if os.path.exists(db) and not args.reuse and not rerank:
            os.remove(db)
        t0 = time.monotonic()
        ident, fit, chosen, errors = select_structure(args, build, folder, db, f"structure-{base}",
                                                      training, held_out)
        if rerank:
            print(f"calibration {base} on {len(training)} recordings, kept {chosen}: {fit} "
                  f"({time.monotonic() - t0:.0f} s); it ranks {study}'s gaits", flush=True)
            yield f"structure-{base}", db, time.monotonic() - t0, {
                "fit": fit, "recordings": len(training), "family": chosen, "rerank": ident,
                "training_errors_at_steps": errors}
            break
        # The robust study is named for the family it starts from, so --reuse finds its own.
        study = (base if chosen == "family" else f"{base}-{chosen}") + (
            f"-seed{args.seed}" if args.seed != 1 else "") + (f"-{args.tag}" if args.tag else "")
        reused = args.reuse and completed(db, study)
        print(f"calibration {base} on {len(training)} recordings, kept {chosen}: {fit} "
              f"({time.monotonic() - t0:.0f} s; training errors at the steps: {errors})",
              flush=True)
        if not reused:
            evolve(args, study, args.generations, True, db=db, calibration=ident)
        ensemble = ensemble_of(db, study)
        print(f"ensemble of {study}: {ensemble}", flush=True)
        yield study, db, time.monotonic() - t0, {"fit": fit, "ensemble": ensemble,
                                                 "recordings": len(training),
                                                 "family": chosen,
                                                 "training_errors_at_steps": errors}
        if rnd + 1 == args.rounds:
            break
        best = gait_sets(db, True, args.record_best, study)["best"]
        for i, (_, genes) in enumerate(best):
            training.append(os.path.join(folder, f"{study}-best{i}.csv"))
            record_one(build, training[-1], genes, {})


def ensemble_of(db, study):
    """The parameter ranges the coordinator gave the robust study `study` (its stored spec)."""
    con = sqlite3.connect(db)
    spec_json = con.execute("SELECT spec_json FROM studies WHERE name = ?", (study,)).fetchone()[0]
    robust = json.loads(spec_json).get("objective", {}).get("robust", {})
    return {p["name"]: [p.get("lo", 0.0), p.get("hi", 0.0)] for p in robust.get("parameters", [])}


def recorded_genes(args, build, study):
    """The genes of `study`'s gaits that --rounds recorded on `build` for the next round."""
    folder = os.path.join(args.out, f"calibration-{build}")
    out = []
    for i in range(args.record_best):
        path = os.path.join(folder, f"{study}-best{i}.csv.json")
        if os.path.exists(path):
            with open(path) as f:
                out.append(json.load(f)["command"]["genes"])
    return out


def repredicted(args, rounds, sets, where, achieved):
    """With --rounds: each round's gaits predicted again by the next round's model (the
    next robust study's objective, `gaitforge validate NEXT --gaits`; with --rerank the next
    calibration's, `gaitforge validate PREV --from-calibration CAL`), against the travel
    measured; also over the gaits that were not recorded for that model's calibration."""
    rows = []
    for (prev, prev_db, build, _), (study, db, _, cal) in zip(rounds, rounds[1:]):
        kept = {k: sets[prev][k] for k in ("best", "spread")}
        t0 = time.monotonic()
        fresh = (validate(args, prev_db, prev, kept, label=f"{prev}-by-{study}", calibration=cal)
                 if cal else validate(args, db, study, kept, label=f"{prev}-by-{study}"))
        wall = time.monotonic() - t0
        recorded = recorded_genes(args, build, prev)
        for b, scen in where[prev]:
            for kind in ("best", "spread"):
                genes = [g for _, g in sets[prev][kind]]
                pred = np.array(fresh[kind])
                ach = np.array([achieved[(b, prev, kind, i, scen)] for i in range(len(pred))])
                new = np.array([not any(np.allclose(g, r) for r in recorded) for g in genes])
                ratio, rho = agreement(pred, ach)
                u_ratio, u_rho = agreement(pred[new], ach[new])
                top = int(np.nanargmax(pred))
                rows.append({"study": prev, "predicted_by": study, "build": b, "scenario": scen,
                             "set": kind, "gaits": len(pred), "unrecorded": int(new.sum()),
                             "predicted_cm": 100 * np.nanmean(pred),
                             "achieved_cm": 100 * np.nanmean(ach), "ratio": ratio,
                             "spearman": rho, "unrecorded_ratio": u_ratio,
                             "unrecorded_spearman": u_rho, "top_predicted_gait_cm": 100 * ach[top],
                             "validate_wall_s": wall})
                print(f"{prev} {kind} predicted by {study}: ratio {ratio:.2f} rho {rho:.2f}; "
                      f"{int(new.sum())} unrecorded: {u_ratio:.2f} {u_rho:.2f}; the gait it "
                      f"ranks first achieves {100 * ach[top]:.2f} cm", flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default=os.path.join(HERE, "..", "build", "bin"))
    ap.add_argument("--out", default="transfer-out")
    ap.add_argument("--population", type=int, default=100)
    ap.add_argument("--generations", type=int, default=30)
    ap.add_argument("--gaits", type=int, default=20)
    ap.add_argument("--cycles", type=int, default=4, help="measured cycles on the builds")
    ap.add_argument("--builds", default="rig2d,mujoco", help="independent builds, comma separated")
    ap.add_argument("--diagnose", action="store_true",
                    help="also diagnose the strong hose on each build and evolve from it")
    ap.add_argument("--calibrate", action="store_true",
                    help="also calibrate the model's structure on each build (nothing concealed) "
                         "and evolve robustly from that calibration")
    ap.add_argument("--calibration-evaluations", type=int, default=800,
                    help="--calibrate: CMA-ES evaluations of the calibration")
    ap.add_argument("--structure", default="",
                    help="--calibrate: only these of STRUCTURE's parameters, comma separated "
                         "(the time offset always; default: all)")
    ap.add_argument("--select-structure", action="store_true",
                    help="--calibrate: also calibrate each structural parameter alone and keep "
                         "the fit with the lowest training error over the timestep variants")
    ap.add_argument("--rounds", type=int, default=1,
                    help="--calibrate: calibrate and evolve this many times, each round "
                         "recording the last study's --record-best best gaits on the build "
                         "and adding them to the calibration")
    ap.add_argument("--rerank", action="store_true",
                    help="--rounds 2: the second round calibrates only and ranks the first "
                         "study's gaits by that calibration (validate --from-calibration)")
    ap.add_argument("--record-best", type=int, default=5,
                    help="--rounds: gaits recorded per round")
    ap.add_argument("--reuse", action="store_true",
                    help="--calibrate: keep the calibrations and studies that completed in "
                         "--out's databases (a benchmark interrupted, or run with fewer rounds "
                         "or without --select-structure)")
    ap.add_argument("--structural", action="store_true",
                    help="also a robust study whose ensemble samples the model's idealisations "
                         "(STRUCTURAL)")
    ap.add_argument("--only", default="", help="only these studies, comma separated "
                    "(paper, robust, paper-long, robust-structural)")
    ap.add_argument("--screening", type=int, default=120, help="--diagnose: screening budget")
    ap.add_argument("--full", type=int, default=480, help="--diagnose: refit budget")
    ap.add_argument("--robust-k", type=float, default=ROBUST_K,
                    help="k of the robust studies' statistic, mean - k sd")
    ap.add_argument("--seed", type=int, default=1,
                    help="the gait studies' seed (a study from a calibration is named -seedN "
                         "when N is not 1): one study's figures carry the hopping robot's chaos; "
                         "several seeds measure it")
    ap.add_argument("--tag", default="",
                    help="--calibrate: name the robust studies -TAG, so that --reuse keeps the "
                         "calibrations and evolves anew (after a change to the ensemble, say)")
    ap.add_argument("--sampling", choices=("box", "fits"), default="box",
                    help="--calibrate: the robust study's objective.robust.sampling: the open "
                         "ranges sampled independently (box) or the calibration's own fits as "
                         "joint samples (fits)")
    ap.add_argument("--validate", type=int, default=0, metavar="MEMBERS",
                    help="also predict each robust study's gaits over a fresh ensemble of this "
                         "many members (gaitforge validate), reported beside the study's own")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    if args.quick:
        args.population, args.generations, args.gaits, args.cycles = 12, 3, 3, 2
        args.screening, args.full, args.calibration_evaluations = 24, 48, 40
    structure_family(args)  # an unknown --structure name stops here, before any recording
    if args.rounds < 1 or args.record_best < 1:
        sys.exit(f"--rounds and --record-best: at least 1 (got {args.rounds}, {args.record_best})")
    if args.rerank and args.rounds != 2:
        sys.exit(f"--rerank: with --rounds 2 (got --rounds {args.rounds})")
    builds = args.builds.split(",")
    unknown = sorted(set(builds) - set(BUILDS))
    if unknown:
        sys.exit(f"--builds: unknown {', '.join(unknown)}; known: {', '.join(BUILDS)}")
    for b in set(BUILDS) - set(builds):
        del BUILDS[b]
    os.makedirs(args.out, exist_ok=True)
    walls, sets, where, named, validated = {}, {}, {}, {}, {}
    check = (lambda db, study: validated.__setitem__(study, validate(args, db, study, sets[study]))
             if args.validate else None)
    everywhere = [(b, scen) for b in BUILDS for scen in SCENARIOS]
    # paper-long: the paper's fitness for the robust study's number of simulations (6
    # members each).
    longer = args.generations * ROBUST_MEMBERS
    studies = [("paper", args.generations, False, False), ("robust", args.generations, True, False),
               ("paper-long", longer, False, False)]
    if args.structural:
        studies.append(("robust-structural", args.generations, True, True))
    only = set(args.only.split(",")) if args.only else {n for n, *_ in studies}
    for name, generations, robust, structural in studies:
        if name not in only:
            continue
        db, walls[name] = evolve(args, name, generations, robust, structural=structural)
        sets[name], where[name] = gait_sets(db, robust, args.gaits, name), everywhere
        if robust:
            check(db, name)
        print(f"{name}: {generations} generations in {walls[name]:.0f} s", flush=True)
    for build in BUILDS if args.diagnose else ():
        db, wall, named[build] = diagnose_and_evolve(args, build)
        if db:
            study = f"diagnosed-{build}"
            sets[study], where[study], walls[study] = gait_sets(db, True, args.gaits, study), [(build, STRONG_HOSE)], wall
            check(db, study)
    fits, rounds = {}, {}
    for build in BUILDS if args.calibrate else ():
        for study, db, wall, fits[study] in calibrate_and_evolve(args, build):
            rounds.setdefault(build, []).append((study, db, build, fits[study].get("rerank", "")))
            if rounds[build][-1][3]:
                continue  # a calibration that ranks the last study's gaits: no gaits of its own
            sets[study], where[study], walls[study] = (gait_sets(db, True, args.gaits, study),
                                                       [(build, "nothing concealed")], wall)
            check(db, study)
    achieved = measure(sets, where, args.cycles)
    rows = table(sets, where, achieved, walls, validated)
    gaits = per_gait(sets, where, achieved, validated)
    again = [r for build in rounds for r in repredicted(args, rounds[build], sets, where, achieved)]
    with open(os.path.join(args.out, "transfer.json"), "w") as f:
        json.dump({"rows": rows, "repredicted": again,
                   "population": args.population, "generations": args.generations,
                   "paper_long_generations": longer, "diagnoses": named,
                   "calibrations": fits, "gaits": gaits}, f, indent=1)
    plot(gaits, os.path.join(args.out, "transfer.svg"))


if __name__ == "__main__":
    main()
