#!/usr/bin/env bash
# Paper 004's adaptive model and tracking on its continuum arm, end to end:
#  1. recordings of a state-dependent reference: the arm (4x finer step) whose joints soften
#     by up to 30% and damp by up to 50% more as it bends (a concealed map of the tip's
#     height), held by rod forces whose resultant pulls in 16 directions with 1 to 4 N (rod k
#     2/3 of it times the cosine from its angle: 64 playbacks of 1.2 s), and a swing held out;
#  2. gaitforge-sim learn-parameters: P = [k_x, k_y, c_x, c_y] fitted to all of them (the
#     constant model, LMD) and to each hold (the state it holds), an MLP (paper 004: one
#     hidden layer of 5 logsig units) from the tip's position to P (the adaptive model,
#     ALMD);
#  3. gaitforge-sim track on paper 004's eq. 14 loop (at half its bend): the PID alone, with
#     the feed-forward of the descriptor's model, of the fitted constant model and of the
#     adaptive model; the errors beside the paper's, and a figure.
#   examples/arm-adaptive.sh [OUT_DIR]     (default arm-adaptive-out; about 3 minutes on 2 cores)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$here/.."
sim="${GAITFORGE_SIM:-$root/build/bin/gaitforge-sim}"
out="${1:-arm-adaptive-out}"
mkdir -p "$out/recordings"
[ -x "$sim" ] || { echo "arm-adaptive: build first (scripts/build.sh): no $sim" >&2; exit 2; }
# The reference's concealed map: k falls by 30% and c rises by 50% as the tip rises by
# 15 mm (one logistic unit on tip.z, centred 15 mm above the straight arm's tip).
truth="$(mktemp)"
trap 'rm -f "$truth"' EXIT
cat > "$truth" <<'JSON'
{"format": "gaitforge.mlp.v1", "inputs": ["tip.x", "tip.y", "tip.z"],
 "outputs": ["joint.stiffness_x_nm_per_rad", "joint.stiffness_y_nm_per_rad",
             "joint.damping_x_nms_per_rad", "joint.damping_y_nms_per_rad"],
 "activation": "logsig", "input_mean": [0, 0, -0.285], "input_sd": [1, 1, 0.005],
 "output_mean": [0.1008, 0.1085, 0.0218, 0.0298], "output_sd": [1, 1, 1, 1],
 "layers": [{"weights": [[0, 0, 1]], "bias": [0]},
            {"weights": [[-0.03024], [-0.03255], [0.0109], [0.0149]], "bias": [0, 0, 0, 0]}]}
JSON
reference=(--set simulation.timestep_s=0.00025 --learned "$truth")
record() {  # NAME DURATION_S FORCES(t) as a Python expression of t
  /usr/bin/python3 - "$out/recordings/$1.in.csv" "$2" "$3" <<'PY'
import math, sys
path, duration, forces = sys.argv[1], float(sys.argv[2]), sys.argv[3]
with open(path, "w") as f:
    f.write("t,rod1.force,rod2.force,rod3.force\n")
    for k in range(round(duration * 1000) + 1):
        t = k / 1000
        f.write("%.6f,%.9g,%.9g,%.9g\n" % ((t,) + eval(forces, {"math": math, "t": t})))
PY
  "$sim" trajectory --robot continuum_arm --inputs "$out/recordings/$1.in.csv" --rate 100 \
    "${reference[@]}" --out "$out/recordings/$1.csv" >/dev/null
  rm "$out/recordings/$1.in.csv"
}
echo "1/3 recording the reference (64 holds and a swing)"
holds=()
for dir in 0 22.5 45 67.5 90 112.5 135 157.5 180 202.5 225 247.5 270 292.5 315 337.5; do
  for mag in 1 2 3 4; do
    record "hold-$dir-$mag" 1.2 \
      "tuple(2 / 3 * $mag * min(1, t / 0.3) * math.cos(math.radians($dir) - p) for p in (0, 2.0944, 4.1888))"
    holds+=("$out/recordings/hold-$dir-$mag.csv")
  done
done
record swing 3 "tuple(2.0 * min(1, t / 0.5) * math.sin(2 * math.pi * 0.7 * t + p) for p in (0, 2.1, 4.2))"
echo "2/3 learning the constant and the adaptive model"
P="joint.stiffness_x_nm_per_rad,joint.stiffness_y_nm_per_rad,joint.damping_x_nms_per_rad,joint.damping_y_nms_per_rad"
"$sim" learn-parameters --robot continuum_arm --recordings "$(IFS=,; echo "${holds[*]}")" \
  --held-out "$out/recordings/swing.csv" --params-learned "$P" --features tip.x,tip.y,tip.z \
  --evaluations 120 --threads 2 --out "$out/adaptive.json" > "$out/learn.json"
constant="$(/usr/bin/python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
print(','.join('%s=%.9g' % (n, v) for n, v in zip(d['params'], d['constant']['values'])))" "$out/learn.json")"
echo "3/3 tracking paper 004's eq. 14 loop"
path="$here/recordings/continuum_arm/eq14.csv"
track() {  # NAME ARGS...
  local name="$1"; shift
  "$sim" track --robot continuum_arm --path "$path" "${reference[@]}" --out "$out/track-$name.csv" "$@" \
    > "$out/track-$name.json"
}
track pid
track nominal --feedforward model
track constant --feedforward model --model-set "$constant"
track adaptive --feedforward model --model-learned "$out/adaptive.json"
/usr/bin/python3 "$root/clients/python/gaitforge_tracking_figure.py" --out "$out/tracking.svg" \
  --title "Paper 004's eq. 14 loop on a reference that softens as it bends" \
  --run "PID=$out/track-pid.csv" --run "PID + descriptor model=$out/track-nominal.csv" \
  --run "PID + constant model (LMD)=$out/track-constant.csv" \
  --run "PID + adaptive model (ALMD)=$out/track-adaptive.csv" >/dev/null
/usr/bin/python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
learn = json.load(open(f"{out}/learn.json"))
runs = {n: json.load(open(f"{out}/track-{n}.json")) for n in ("pid", "nominal", "constant", "adaptive")}
print(f"MLP: R {learn['training']['train_r']:.3f} train, {learn['training']['test_r']:.3f} test (paper: > 0.85)")
for h in learn["held_out"]:
    print(f"held-out swing, tip error: constant {1000 * h['constant_error_m']:.2f} mm, adaptive {1000 * h['adaptive_error_m']:.2f} mm")
for n, r in runs.items():
    print(f"{n:>9}: max {1000 * r['max_error_m']:7.2f} mm, rms {1000 * r['rms_error_m']:7.2f} mm")
c, a = runs["constant"]["max_error_m"], runs["adaptive"]["max_error_m"]
print(f"adaptive against constant feed-forward: max error {100 * (a - c) / c:+.1f}% (paper: -67.5%)")
print(f"figure: {out}/tracking.svg")
PY
