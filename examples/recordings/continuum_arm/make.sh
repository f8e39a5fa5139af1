#!/usr/bin/env bash
# Makes the continuum arm's recordings of examples/arm-estimation.yaml (paper 004's
# estimation: rod forces applied to the arm at rest, the tip's motion recorded). No
# hardware recording exists, so a reference that is not the model fitted makes them: the
# same descriptor stepped 4 times finer (0.25 ms), with joint parameters concealed as the
# truth to recover (not the descriptor's Table 2 values, so that the fit has to move):
#   P = [k_x, k_y, c_x, c_y] = [0.15, 0.08, 0.03, 0.015] (N m/rad, N m s/rad).
# Each recording: the tip (motion capture at 100 Hz, noise-free) and the three rod forces
# (rod1.force .. rod3.force, N) that drove it, from rest. Training: three force steps held
# for 1 s (step-a is the paper's Table 2 state, f = [0.3025, 0.3263, -0.1265] N); held out:
# forces swinging at 1.3 Hz for 2 s.
#   build/bin must hold gaitforge-sim (scripts/build.sh);  examples/recordings/continuum_arm/make.sh
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
sim="${GAITFORGE_SIM:-$here/../../../build/bin/gaitforge-sim}"
truth="joint.stiffness_x_nm_per_rad=0.15,joint.stiffness_y_nm_per_rad=0.08"
truth+=",joint.damping_x_nms_per_rad=0.03,joint.damping_y_nms_per_rad=0.015,simulation.timestep_s=0.00025"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
record() {  # NAME DURATION_S FORCES(t) as a Python expression of t giving (f1, f2, f3)
  /usr/bin/python3 - "$tmp/$1.csv" "$2" "$3" <<'PY'
import math, sys
path, duration, forces = sys.argv[1], float(sys.argv[2]), sys.argv[3]
with open(path, "w") as out:
    out.write("t,rod1.force,rod2.force,rod3.force\n")
    for k in range(round(duration * 1000) + 1):  # inputs at 1 kHz
        t = k / 1000
        out.write("%.6f,%.9g,%.9g,%.9g\n" % ((t,) + eval(forces, {"math": math, "t": t})))
PY
  "$sim" trajectory --robot continuum_arm --inputs "$tmp/$1.csv" --rate 100 --set "$truth" \
    --out "$here/$1.csv" >/dev/null
  # Conceal the truth: the sidecar keeps the robot and the command, not the overrides.
  /usr/bin/python3 - "$here/$1.csv.json" <<'PY'
import json, sys
meta = json.load(open(sys.argv[1]))
meta.pop("overrides", None)
meta.pop("parameters", None)
meta["source"] = "reference: the descriptor at 0.25 ms with concealed joint parameters"
meta["note"] = "paper 004's estimation experiment; made by examples/recordings/continuum_arm/make.sh"
json.dump(meta, open(sys.argv[1], "w"), indent=1)
PY
}
record step-a 1 "(0.3025, 0.3263, -0.1265)"
record step-b 1 "(-0.2, 0.1, 0.4)"
record step-c 1 "(0.35, -0.3, 0.05)"
record swing 2 "tuple(0.3 * math.sin(2 * math.pi * 1.3 * t + p) for p in (0, 2.1, 4.2))"

# Paper 004's tracking path (eq. 14): every joint at psi = rho (sin phi, cos phi),
# rho = a (2 pi + pi cos phi) / (6 N), phi = pi t / 10 - pi over 20 s (one loop), the tip where
# the chain of N links of L / N puts it (each joint turning by Rx(psi_x) Ry(psi_y)), at 50 Hz
# (the control rate). N = 5 and L = 0.3 m are the paper's (robot.yaml's defaults). a = 1/2:
# the paper's bend of 30 to 90 degrees is out of reach of this arm hanging under gravity (its
# tip gets at most 0.18 m from the axis; the loop asks 0.22 m), so the loop bends 15 to 45.
/usr/bin/python3 - "$here/eq14.csv" <<'PY'
import json, math, sys
import numpy as np
out, lumps, length, a = sys.argv[1], 5, 0.3, 0.5
def rot(axis, angle):
    c, s = math.cos(angle), math.sin(angle)
    if axis == "x":
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
with open(out, "w") as f:
    f.write("t,tip.x,tip.y,tip.z\n")
    for k in range(20 * 50 + 1):
        t = k / 50
        phi = math.pi * t / 10 - math.pi
        rho = a * (2 * math.pi + math.pi * math.cos(phi)) / (6 * lumps)
        joint = rot("x", rho * math.sin(phi)) @ rot("y", rho * math.cos(phi))
        tip, frame = np.zeros(3), np.eye(3)
        for _ in range(lumps):
            frame = frame @ joint
            tip += frame @ np.array([0.0, 0.0, -length / lumps])
        f.write("%.4f,%.9g,%.9g,%.9g\n" % (t, tip[0], tip[1], tip[2]))
meta = {"robot": "continuum_arm", "command": {"kind": "path"},
        "source": "paper 004, eq. 14, at half its bend",
        "note": "the tracking path; made by examples/recordings/continuum_arm/make.sh"}
json.dump(meta, open(out + ".json", "w"), indent=1)
PY
