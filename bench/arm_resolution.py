#!/usr/bin/python3
"""Paper 004's resolution trade-off (issue 29): the continuum arm as N lumps against a fine
reference (N = 40 at 0.25 ms), and what each N costs. Runs gaitforge-bench-arm-resolution,
prints its table, keeps its figures as JSON and draws them (matplotlib,
python3-matplotlib): error against N (tip position RMS, paper 004's 1 - F of the tip's
acceleration) and cost against N (simulated s per CPU s, 20 ms control steps per second,
with the paper's 50 Hz at N = 5 as the anchor).

Run from the repository root after ./scripts/build.sh, with the CPU to itself:
    /usr/bin/python3 bench/arm_resolution.py [--json FILE] [--figure FILE]
"""
import argparse
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "bin", "gaitforge-bench-arm-resolution")


def draw(data, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = data["rows"]
    n = [r["lumps"] for r in rows]
    fig, (err, cost) = plt.subplots(1, 2, figsize=(10, 4))
    err.plot(n, [r["step_accel_error"] for r in rows], "o-", label="1 - F, Table 2 step")
    err.plot(n, [r["swing_accel_error"] for r in rows], "s-", label="1 - F, rods swinging 1.3 Hz")
    err.set_xscale("log")
    err.set_yscale("log")
    err.set_xlabel("lumps N")
    err.set_ylabel("acceleration error 1 - F against N = 40")
    tip = err.twinx()
    tip.plot(n, [r["swing_tip_rms_mm"] for r in rows], "^:", color="grey", label="tip RMS (mm), swing")
    tip.set_yscale("log")
    tip.set_ylabel("tip position RMS error (mm)")
    err.axvline(5, color="k", lw=0.5)
    err.legend(loc="lower left", fontsize=8)
    tip.legend(loc="upper right", fontsize=8)
    err.set_title("error of N lumps (paper: N = 5)")
    cost.plot(n, [r["control_steps_per_s"] for r in rows], "o-", label="20 ms control steps per s")
    cost.plot(n, [r["sim_s_per_cpu_s"] for r in rows], "s-", label="simulated s per CPU s")
    cost.axhline(data["anchor_control_hz_at_5"], color="r", lw=0.8,
                 label="paper: 50 Hz at N = 5 (MATLAB)")
    cost.set_xscale("log")
    cost.set_yscale("log")
    cost.set_xlabel("lumps N")
    cost.set_title("cost (one core)")
    cost.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", help="write the figures here")
    ap.add_argument("--figure", default="arm-resolution.svg", help="the figure (SVG or PNG)")
    args = ap.parse_args()
    if not os.path.exists(BIN):
        sys.exit("build first: ./scripts/build.sh (no %s)" % BIN)
    data = json.loads(subprocess.run([BIN, "--json"], check=True, capture_output=True,
                                     text=True).stdout)
    print("N lumps at h = 1 ms against N = 40 at 0.25 ms; paper 004: N = 5 ran one model step")
    print("above 50 Hz in MATLAB, finer models below 5 Hz\n")
    print("%4s %14s %9s %15s %10s %14s %13s" % ("N", "step tip (mm)", "step 1-F", "swing tip (mm)",
                                               "swing 1-F", "sim s / CPU s", "20 ms steps/s"))
    for r in data["rows"]:
        print("%4d %14.3f %9.4f %15.3f %10.4f %14.1f %13.0f" % (
            r["lumps"], r["step_tip_rms_mm"], r["step_accel_error"], r["swing_tip_rms_mm"],
            r["swing_accel_error"], r["sim_s_per_cpu_s"], r["control_steps_per_s"]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(data, f, indent=1)
    draw(data, args.figure)
    print("wrote", args.figure)


if __name__ == "__main__":
    main()
