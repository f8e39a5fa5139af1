"""End to end test of the Python client (clients/python/gaitforge_client) against a real
coordinator and workers on loopback: a small analytic GA watched with a progress callback,
its history, hall of fame and individuals checked against `gaitforge --json` on the same
database; errors raised as GaitforgeError subclasses naming the field; a recording added and
a spec file naming it by path; cancel and resume; a coordinator that wants a token, and
one that is not there.

Usage: client_e2e_test.py --bin-dir build/bin --stubs build/python
"""
import argparse
import importlib.util
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "clients", "python"))

SPHERE = {"name": "py-sphere", "seed": 5, "engine": "ga", "population": 8, "generations": 3,
          "objective": {"name": "analytic.sphere"},
          "bounds": [{"name": "x", "lo": -1, "hi": 1}, {"name": "y", "lo": -1, "hi": 1}],
          "ga": {"elite": 2}}
RECORDING = os.path.join(REPO, "tests", "diagnosis", "cases", "tether-hose", "train", "gait-a.csv")
CALIBRATION_YAML = """name: py-calib
seed: 11
engine: cmaes
population: 4
generations: 50
objective:
  name: caterpillar.calibration
  options: {error: shape, metric: rmse}
  recordings: [walk.csv]
bounds:
  - {name: actuators.force_n, lo: 7.0, hi: 11.0}
"""


def check(cond, what):
    if not cond:
        raise AssertionError(what)
    print("ok:", what)


def cli_json(bin_dir, db, *args):
    out = subprocess.run([os.path.join(bin_dir, "gaitforge"), "--db", db, "--json", *args],
                         check=True, capture_output=True, text=True, timeout=60)
    return json.loads(out.stdout)


def same_number(a, b):
    return (a is None and b in ("NaN", None)) or float(a) == float(b)


def run_sphere(gf, seen):
    sid = gf.submit(SPHERE)
    final = gf.watch(sid, on_progress=seen.append)
    check(final["state"] == "completed" and final["generations_done"] == 3, "watch: completed, 3 generations")
    done = [p["generations_done"] for p in seen]
    check(len(seen) >= 1 and done == sorted(done), f"progress callback, non-decreasing {done}")
    return sid


ROBUST = {"name": "py-robust", "seed": 7, "population": 4, "generations": 1,
          "objective": {"name": "caterpillar.distance", "params": {"cycles": 1, "settle_cycles": 0},
                        "robust": {"numerics": [""],
                                   "parameters": [{"name": "actuators.force_n", "lo": 7, "hi": 10}]}},
          "ga": {"elite": 2}}


def check_validation_from_calibration(gf, tmp, sid):
    """Robust study `sid`'s best gait on the model a (short, completed) calibration fitted:
    the validation carries the calibration's value; walk.csv is in tmp
    (check_recording_and_control)."""
    spec_path = os.path.join(tmp, "calib-short.yaml")
    with open(spec_path, "w") as f:
        f.write(CALIBRATION_YAML.replace("generations: 50", "generations: 2"))
    cid = gf.submit(spec_path)
    check(gf.watch(cid)["state"] == "completed", "a short calibration completed")
    force = gf.hall_of_fame(cid)[0]["genes"][0]
    vid = gf.validate(sid, members=2, top=1, from_calibration=cid)
    check(gf.watch(vid)["state"] == "completed", "validate from_calibration: completed")
    spec = gf.study(vid)["spec"]
    check(cid in (spec.validate.from_calibration, spec.objective.from_calibration),
          "validate from_calibration: names the calibration")
    fitted = dict(kv.split("=") for kv in spec.objective.options["set"].split(","))
    check(abs(float(fitted["actuators.force_n"]) - force) <= 1e-4 * force,
          f"validate from_calibration: the model carries the fitted force {force:.4g} N")
    rows = gf.individuals(vid, 0)
    check(len(rows) == 1 and rows[0]["valid"], "validate from_calibration: the gait evaluated")


def check_validation(gf, errors, tmp):
    """A robust study's hall of fame over a fresh ensemble, and the refusals."""
    sid = gf.submit(ROBUST)
    gf.watch(sid)
    hof = gf.hall_of_fame(sid)
    vid = gf.validate(sid, members=3, top=2)
    check(gf.watch(vid)["state"] == "completed", "validate: the validation study completed")
    spec = gf.study(vid)["spec"]
    check(spec.engine == "sweep" and spec.objective.robust.members == 3 and spec.validate.seed == 8,
          "validate: a sweep over 3 fresh members, seed 7 + 1")
    rows = gf.individuals(vid, 0)
    check(len(rows) == 2 and [r["genes"] for r in rows] == [h["genes"] for h in hof[:2]],
          "validate: member i is hall-of-fame gait i")
    check(all(r["valid"] and "robust.mean" in r["metrics"] for r in rows),
          "validate: each gait's fresh ensemble mean")
    for bad, what in ((lambda: gf.validate("no-such-study"), errors.NotFound),
                      (lambda: gf.validate(sid, ensemble_seed=7), errors.InvalidSpec)):
        try:
            bad()
            check(False, f"validate refused with {what.__name__}")
        except what as e:
            check(True, f"validate refused with {what.__name__}: {e}")
    check_validation_from_calibration(gf, tmp, sid)


def check_reads(gf, sid):
    history = gf.history(sid)
    check([h["generation"] for h in history] == [0, 1, 2], "history: generations 0..2")
    hof = gf.hall_of_fame(sid)
    check(hof and hof[0]["rank"] == 0 and hof[0]["valid"], "hall of fame: rank 0 first, valid")
    check(len(gf.hall_of_fame(sid, generation=0)) >= 1, "hall of fame of generation 0")
    members = gf.individuals(sid, 0)
    check([m["member"] for m in members] == list(range(8)), "individuals: 8 members of generation 0")
    check(any(s["study_id"] == sid for s in gf.studies()), "studies() lists the study")
    check(gf.study(sid)["state"] == "completed", "study(): completed")
    if importlib.util.find_spec("pandas"):
        frame = gf.history(sid, as_dataframe=True)
        check(list(frame["generation"]) == [0, 1, 2], "history as a DataFrame")
    else:
        print("skip: pandas not installed; DataFrames untested")
    return history, hof, members


def check_errors(gf, tmp, errors):
    bad = dict(SPHERE, population=1)
    try:
        gf.submit(bad)
        check(False, "population 1 refused")
    except errors.InvalidSpec as e:
        check(e.field == "population" and e.exit_code == 2, f"InvalidSpec names 'population': {e}")
    bad_file = os.path.join(tmp, "bad.json")
    with open(bad_file, "w") as f:
        json.dump(bad, f)
    try:
        gf.submit(bad_file)
        check(False, "a spec file with population 1 refused")
    except errors.InvalidSpec as e:
        check(e.field == "population" and str(e).startswith(bad_file), f"InvalidSpec names the file: {e}")
    try:
        gf.submit(dict(SPHERE, generatons=3))
        check(False, "unknown key refused")
    except errors.InvalidSpec as e:
        check(e.field == "generatons", f"InvalidSpec names 'generatons': {e}")
    try:
        gf.history("no-such-study")
        check(False, "unknown study refused")
    except errors.NotFound as e:
        check(e.exit_code == 3, f"NotFound for an unknown study: {e}")
    try:
        gf.hall_of_fame(gf.studies()[0]["study_id"], generation=99)
        check(False, "generation 99 refused")
    except errors.NotFound as e:
        check(True, f"NotFound for generation 99: {e}")


def check_robot_folder(gf, source_dir, errors):
    """A robot that exists only as files, named by its folder, runs as the CLI runs it."""
    fixture = os.path.join(source_dir, "tests", "fixtures", "robots", "twobox")
    sid = gf.submit({"name": "twobox", "population": 6, "generations": 2, "ga": {"elite": 1},
                     "objective": {"name": "robot.distance", "robot": fixture}})
    gf.watch(sid)
    spec = gf.study(sid)["spec"]
    check(spec.objective.robot == "twobox" and "format: gaitforge.robot.v1" in
          spec.objective.robot_descriptor, "robot folder: the spec carries the descriptor")
    check(len(gf.hall_of_fame(sid)) > 0, "robot folder: a hall of fame")
    try:
        gf.submit({"population": 6, "generations": 2, "ga": {"elite": 1},
                   "objective": {"name": "robot.distance", "robot": fixture + "/nope.yaml"}})
        check(False, "a missing robot file is refused")
    except errors.NotFound as e:
        check("objective.robot" in str(e), f"NotFound names objective.robot: {e}")


def check_recording_and_control(gf, tmp, errors):
    added = gf.add_recording(RECORDING)
    check(len(added["hash"]) == 64 and not added["already_stored"], "add_recording: a hash")
    check(gf.add_recording(RECORDING)["already_stored"], "add_recording again: already stored")
    shutil.copy(RECORDING, os.path.join(tmp, "walk.csv"))
    shutil.copy(RECORDING + ".json", os.path.join(tmp, "walk.csv.json"))
    spec_path = os.path.join(tmp, "calib.yaml")
    with open(spec_path, "w") as f:
        f.write(CALIBRATION_YAML)
    sid = gf.submit(spec_path)
    spec = gf.study(sid)["spec"]
    check(list(spec.objective.recordings) == [added["hash"]], "spec file: recording path uploaded as its hash")
    check(gf.cancel(sid)["state"] == "cancelled", "cancel")
    check(gf.resume(sid)["state"] == "running", "resume")
    gf.cancel(sid)
    try:
        gf.watch(sid)
        check(False, "watch of a cancelled study raises")
    except errors.StudyNotCompleted as e:
        check(e.exit_code == 1, f"StudyNotCompleted: {e}")


def check_diagnosis(gf, tmp, errors):
    """A stored diagnosis from a spec file: its recordings uploaded, run by the coordinator,
    its report and files back; the same spec again is the same diagnosis."""
    cases = os.path.join(REPO, "tests", "diagnosis", "cases", "tether-hose")
    spec_path = os.path.join(tmp, "diag.yaml")
    with open(spec_path, "w") as f:
        f.write("name: py\nseed: 3\n"
                f"training: [{cases}/train/gait-a.csv, {cases}/train/gait-b.csv]\n"
                f"held_out: [{cases}/held_out/gait-c.csv]\n"
                "candidates: [tether.constant, ground.slope]\n"
                "screening_evaluations: 16\nfull_evaluations: 24\ntop: 2\ntry_pairs: false\n")
    did = gf.diagnose(spec_path)
    seen = []
    got = gf.diagnosis(did, wait=True, on_progress=seen.append,
                       files_dir=os.path.join(tmp, "diag-files"))
    check(got["state"] == "completed", f"diagnosis completed: {got['state']} {got['error']}")
    check(got["report"]["verdict"] == "found" and
          got["report"]["effects"][0]["id"] == "tether.constant", "diagnosis finds the hose")
    check(len(got["spec"]["training"][0]) == 64, "diagnosis spec: recordings by hash")
    check(os.path.exists(os.path.join(tmp, "diag-files", "diagnosis.svg")), "diagnosis files written")
    check(gf.diagnose(spec_path) == did, "the same spec again: the same diagnosis")
    listed = gf.diagnoses()
    check([d["diagnosis_id"] for d in listed] == [did] and listed[0]["verdict"] == "found",
          "diagnoses lists it")
    try:
        gf.diagnose({"name": "bad", "training": [], "held_out": []})
        check(False, "a diagnosis spec without recordings is refused")
    except errors.InvalidSpec as e:
        check("training" in e.message, f"InvalidSpec names the field: {e.message}")
    try:
        gf.diagnosis("no-such-diagnosis")
        check(False, "an unknown diagnosis raises")
    except errors.NotFound as e:
        check(e.exit_code == 3, f"NotFound: {e}")


def compare_with_cli(bin_dir, db, sid, history, hof, members):
    cli = cli_json(bin_dir, db, "history", sid)["generations"]
    check(len(cli) == len(history) and all(
        same_number(p[k], c[k]) for p, c in zip(history, cli) for k in ("best", "mean", "stddev", "diversity")
    ) and all(int(p["evaluations"]) == int(c["evaluations"]) for p, c in zip(history, cli)),
          "history equals `gaitforge history --json`")
    cli = cli_json(bin_dir, db, "hof", sid)["entries"]
    check([e["individual"]["genes"] for e in cli] == [h["genes"] for h in hof] and all(
        same_number(h["fitness"], e["individual"]["evaluation"]["fitness"]) for h, e in zip(hof, cli)),
          "hall of fame equals `gaitforge hof --json`")
    cli = cli_json(bin_dir, db, "individuals", sid, "--generation", "0")["individuals"]
    check([c["genes"] for c in cli] == [m["genes"] for m in members], "individuals equal `gaitforge individuals --json`")


def check_lost_coordinator(gf, proc, errors):
    """A study with no workers is watched while its coordinator stops: Unavailable."""
    sid = gf.submit(SPHERE)
    started, outcome = threading.Event(), []

    def watch():
        try:
            gf.watch(sid, on_progress=lambda p: started.set())
            outcome.append(None)
        except errors.GaitforgeError as e:
            outcome.append(e)

    watcher = threading.Thread(target=watch)
    watcher.start()
    check(started.wait(30), "watch of a study no worker runs sends progress")
    proc.terminate()
    proc.wait(10)
    watcher.join(30)
    check(outcome and isinstance(outcome[0], errors.Unavailable), f"Unavailable when the coordinator stops: {outcome}")


def check_tokens(bin_dir, tmp, Client, errors):
    token = "python-client-token-0123456789"
    port_file = os.path.join(tmp, "token.port")
    env = dict(os.environ, GAITFORGE_CLIENT_TOKEN=token)
    proc = subprocess.Popen([os.path.join(bin_dir, "gaitforge-coordinator"), "--listen", "127.0.0.1:0",
                             "--db", os.path.join(tmp, "token.db"), "--port-file", port_file],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        while not os.path.exists(port_file) and proc.poll() is None:
            time.sleep(0.05)
        with open(port_file) as f:
            target = "127.0.0.1:" + f.readline().strip()
        try:
            Client(target, token="").studies()
            check(False, "a call without a token refused")
        except errors.Denied as e:
            check(e.exit_code == 6, f"Denied without a token: {e}")
        gf = Client(target, token=token)
        check(gf.studies() == [], "the client token is accepted")
        check_lost_coordinator(gf, proc, errors)
        try:
            Client(target, token=token, timeout=2).studies()
            check(False, "a stopped coordinator is unavailable")
        except errors.Unavailable as e:
            check(e.exit_code == 4, f"Unavailable once it stopped: {e}")
        try:
            Client(target, token=token).watch("any")
            check(False, "watch of a stopped coordinator is unavailable")
        except errors.Unavailable as e:
            check("lost" not in str(e), f"watch of a stopped coordinator: Unavailable, not lost: {e}")
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.wait()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin-dir", required=True)
    ap.add_argument("--stubs", required=True)
    a = ap.parse_args()
    os.environ["GAITFORGE_PYTHON_STUBS"] = os.path.abspath(a.stubs)
    from gaitforge_client import Client, errors
    tmp = tempfile.mkdtemp(prefix="gaitforge-pyclient-")
    db = os.path.join(tmp, "py.db")
    try:
        seen = []
        with Client.local(db=db, workers=2, binaries=os.path.abspath(a.bin_dir)) as gf:
            sid = run_sphere(gf, seen)
            history, hof, members = check_reads(gf, sid)
            check_errors(gf, tmp, errors)
            check_recording_and_control(gf, tmp, errors)
            check_robot_folder(gf, REPO, errors)
            check_diagnosis(gf, tmp, errors)
            check_validation(gf, errors, tmp)
        compare_with_cli(a.bin_dir, db, sid, history, hof, members)
        check_tokens(a.bin_dir, tmp, Client, errors)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("client_e2e: all checks passed")


if __name__ == "__main__":
    main()
