#!/usr/bin/python3
"""The locating step against the model's own numeric spread (docs/diagnosis.md, step 3),
on real simulations: gaitforge-sim calibration-eval of the shipped cases' training
recordings under the six numeric variants, then clients/python/gaitforge_locate.py.

  /usr/bin/python3 tests/diagnosis/locate_test.py --bin-dir build/bin

A null (nothing concealed; the rig's numerics differ) must read as within the spread,
though without the variants its drift reads as a mismatch; the paper's hose must read as
beyond it, naming the recording that shows it; a variant eval that lacks a recording is
refused, naming the file.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
LOCATE = os.path.join(ROOT, "clients", "python", "gaitforge_locate.py")
VARIANTS = ["", "simulation.timestep_s=0.0005", "simulation.timestep_s=0.00075",
            "simulation.timestep_s=0.00125", "ground.contact_cfm=3e-6", "ground.contact_cfm=3e-5"]
BIN = os.path.join(ROOT, "build", "bin")


def evaluate(case, out, recordings=("train/gait-a.csv", "train/gait-b.csv")):
    """calibration-eval of the case's recordings (or of files given by absolute path) under
    each variant: the eval.json paths. calibration-eval creates its --out-dir."""
    files = ",".join(os.path.join(HERE, "cases", case, r) for r in recordings)
    paths = []
    for i, v in enumerate(VARIANTS):
        d = os.path.join(out, f"{case}-v{i}", "sims")
        # the shipped cases' time offset (make_cases.py): the baseline fits about this much
        sets = "nuisance.time_offset_s=-0.02" + (f",{v}" if v else "")
        r = subprocess.run([os.path.join(BIN, "gaitforge-sim"), "calibration-eval",
                            "--recordings", files, "--set", sets, "--out-dir", d],
                           capture_output=True, text=True, check=True)
        with open(os.path.join(d, "eval.json"), "w") as f:
            f.write(r.stdout)
        paths.append(os.path.join(d, "eval.json"))
    return paths


def cut(src, dst, channels, every=1):
    """A copy of recording src (100 Hz) with only `channels` and the rows on a grid of
    `every` intervals: what another lab's capture may hold (fewer markers, one axis, a lower
    rate; its dropped rows stay dropped), the values untouched."""
    with open(src) as f:
        rows = [line.rstrip("\n").split(",") for line in f if line.strip()]
    keep = [0] + [rows[0].index(c) for c in channels]
    t0 = float(rows[1][0])
    with open(dst, "w") as f:
        for k, row in enumerate(rows):
            if k == 0 or round((float(row[0]) - t0) / 0.01) % every == 0:
                f.write(",".join(row[i] for i in keep) + "\n")
    with open(src + ".json") as f:
        side = json.load(f)
    side.pop("channels", None)
    with open(dst + ".json", "w") as f:
        json.dump(side, f)
    return dst


def locate(evals, out, variants=True):
    args = ["/usr/bin/python3", LOCATE, "--eval", evals[0], "--out", out]
    if variants:
        args += ["--variants", ",".join(evals[1:])]
    r = subprocess.run(args, capture_output=True, text=True)
    return r, (json.load(open(out)) if r.returncode == 0 else None)


class LocateAgainstSpread(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="gf-locate-")
        cls.null = evaluate("null-a", cls.tmp.name)
        cls.hose = evaluate("tether-hose", cls.tmp.name)

    def test_null_is_within_the_spread_though_its_drift_exceeds_the_noise(self):
        r, plain = locate(self.null, os.path.join(self.tmp.name, "null-plain.json"), False)
        self.assertEqual(r.returncode, 0, r.stderr)
        # Against the noise alone the chaos reads as a mismatch, and no spread is claimed.
        self.assertTrue(plain["summary"].startswith("The mismatch lives mainly in"),
                        plain["summary"])
        self.assertIsNone(plain["beyond_spread"])
        r, got = locate(self.null, os.path.join(self.tmp.name, "null.json"))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertFalse(got["beyond_spread"], got["summary"])
        self.assertEqual(got["variants"], 6)
        self.assertEqual(got["beyond_recordings"], [])
        self.assertTrue(got["summary"].startswith("No systematic mismatch beyond the noise and "
                                                  "the model's own numeric spread"), got["summary"])
        for s in got["slices"]["recordings"]:
            sp = s["numeric_spread"]
            self.assertEqual(len(sp["simulated_m_per_cycle"]), 6)
            self.assertLess(abs(sp["recorded_sds"]), 3, s["file"])
            self.assertGreater(sp["simulated_sd_m_per_cycle"], 0)

    def test_the_hose_is_beyond_the_spread_where_the_gait_is_regular(self):
        r, got = locate(self.hose, os.path.join(self.tmp.name, "hose.json"))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(got["beyond_spread"], got["summary"])
        self.assertIn("gait-b.csv", got["beyond_recordings"])
        self.assertTrue(got["summary"].startswith("The mismatch lives mainly in forward travel"),
                        got["summary"])
        b = [s for s in got["slices"]["recordings"] if s["file"].endswith("gait-b.csv")][0]
        self.assertLess(b["numeric_spread"]["recorded_sds"], -3)  # it travels less, far less

    def test_a_variant_without_the_recording_is_refused_naming_it(self):
        held = evaluate("null-a", os.path.join(self.tmp.name, "held"), ("held_out/gait-c.csv",))
        r, _ = locate([self.null[0], held[1]], os.path.join(self.tmp.name, "bad.json"))
        self.assertEqual(r.returncode, 2)
        self.assertIn("--variants", r.stderr)
        self.assertIn("gait-a.csv", r.stderr)



class LocateWhatARecordingHolds(unittest.TestCase):
    """Recordings made elsewhere: one axis only, two markers at half the rate."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="gf-locate-cut-")
        src = os.path.join(HERE, "cases", "tether-hose", "train", "gait-b.csv")
        markers = [f"m{i}" for i in range(1, 7)]
        files = {
            "x": cut(src, os.path.join(cls.tmp.name, "x-only.csv"), [m + ".x" for m in markers]),
            "z": cut(src, os.path.join(cls.tmp.name, "z-only.csv"), [m + ".z" for m in markers]),
            "ends": cut(src, os.path.join(cls.tmp.name, "ends-50hz.csv"),
                        ["m1.x", "m1.z", "m6.x", "m6.z"], every=2),
            "y": cut(src, os.path.join(cls.tmp.name, "y-only.csv"), ["m3.y"]),
        }
        cls.got = {}
        for key, path in files.items():
            evals = evaluate("hose-" + key, cls.tmp.name, (path,))
            cls.got[key] = locate(evals, os.path.join(cls.tmp.name, key + ".json"))

    def test_x_only_locates_the_hose_and_says_z_is_not_recorded(self):
        r, got = self.got["x"]
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(got["beyond_spread"], got["summary"])
        self.assertTrue(got["summary"].startswith("The mismatch lives mainly in forward travel"),
                        got["summary"])
        s = got["slices"]["recordings"][0]
        self.assertIsNone(s["contact"])             # no height: no contact state
        self.assertIsNotNone(s["velocity"])
        self.assertIsNone(s["axis"]["z"]["rms_m"])
        self.assertTrue(any("not recorded (no z channel)" in f for f in got["findings"]),
                        got["findings"])

    def test_z_only_has_no_travel_and_claims_none(self):
        r, got = self.got["z"]
        self.assertEqual(r.returncode, 0, r.stderr)
        s = got["slices"]["recordings"][0]
        self.assertNotIn("travel", s)
        self.assertIsNone(s["velocity"])
        self.assertIsNone(s["trend"]["x"]["mean_m_per_cycle"])
        self.assertIsNone(s["numeric_spread"]["recorded_sds"])
        self.assertFalse(got["summary"].startswith("The mismatch lives mainly in forward"))
        self.assertIn("The forward travel is not compared in z-only.csv: no x channel.",
                      got["summary"])
        self.assertFalse(any("forward drift" in f for f in got["findings"]), got["findings"])

    def test_a_recording_without_x_or_z_is_refused_naming_it(self):
        r, got = self.got["y"]
        self.assertEqual(r.returncode, 2)
        self.assertIsNone(got)
        self.assertIn("y-only.csv: no x or z marker channel", r.stderr)

    def test_two_markers_at_half_the_rate_still_locate_the_hose(self):
        r, got = self.got["ends"]
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(got["beyond_spread"], got["summary"])
        s = got["slices"]["recordings"][0]
        self.assertLess(s["numeric_spread"]["recorded_sds"], -3)
        self.assertIsNotNone(s["contact"])
        self.assertEqual(sorted(s["axis"]["x"]["per_marker_rms_m"]), ["m1", "m6"])


class LocateAPlayback(unittest.TestCase):
    """A recording without a gait (paper 004's arm driven by recorded rod forces): no cycle,
    so it is compared from its start and sliced into windows; it neither travels nor
    touches the ground."""

    def test_an_arms_playback_is_located_in_windows(self):
        with tempfile.TemporaryDirectory(prefix="gf-locate-arm-") as tmp:
            case = os.path.join(HERE, "robots", "continuum_arm", "cases", "null-1", "train")
            d = os.path.join(tmp, "sims")
            r = subprocess.run([os.path.join(BIN, "gaitforge-sim"), "calibration-eval",
                                "--recordings", ",".join(os.path.join(case, f) for f in
                                                         ("step-a.csv", "swing.csv")),
                                "--options", "error=pointwise;channels=tip.x,tip.y,tip.z",
                                "--out-dir", d], capture_output=True, text=True, check=True)
            with open(os.path.join(d, "eval.json"), "w") as f:
                f.write(r.stdout)
            r, got = locate([os.path.join(d, "eval.json")], os.path.join(tmp, "arm.json"), False)
            self.assertEqual(r.returncode, 0, r.stderr)
            for s in got["slices"]["recordings"]:
                self.assertTrue(s["playback"])
                self.assertAlmostEqual(s["cycles"], 4.0, places=6)
                self.assertNotIn("travel", s)
                self.assertIsNone(s["contact"])
                self.assertIsNone(s["velocity"])
                self.assertIsNotNone(s["axis"]["x"]["rms_m"])
            self.assertFalse(any("per cycle" in f or "no x channel" in f for f in got["findings"]),
                             got["findings"])
            self.assertNotIn("per cycle", got["summary"])
            self.assertNotIn("no x channel", got["summary"])


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin-dir", default=BIN)
    a, rest = ap.parse_known_args()
    BIN = os.path.abspath(a.bin_dir)
    unittest.main(argv=[sys.argv[0]] + rest)
