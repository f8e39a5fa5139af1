#!/usr/bin/python3
"""Paper 002's learned current model for the Go2 (issue 28): recordings, training, test.

1. Records the paper's experiment in simulation: 2 gaits (trot, slide) x 4 speeds (0.16,
   0.22, 0.28, 0.34 m/s) x 4 repeats, each `--seconds` long after two settling cycles, at
   500 Hz, with `gaitforge-sim trajectory` (the joints' angles, rates and torques: the
   descriptor's sensors). Repeats differ by the floor's friction (foot.mu 1.0, 0.8, 1.2,
   0.9) and by the windings' temperature at the start (25, 35, 45, 30 C).
2. Gives each sample the battery current of a reference richer than gaitforge's motor
   model (motor_reference.py: warming windings, motor friction, regeneration, sensor noise).
3. Trains the paper's MLP on it: 12 torques + 12 joint speeds -> total current, 4 hidden
   layers of 256 ReLU, linear output, MSE, Adam (lr 3e-4, batch 512), early stopping, no
   normalisation; repeats 1-3 for training and validation (random 80/20), repeat 4 for the
   test (scikit-learn's MLPRegressor, python3-sklearn).
4. Reports test MSE, MAE, R2, MAPE, the absolute error's sd and 95th percentile beside the
   paper's, and each condition's cost of transport from the reference current and from the
   network's; writes the network as a gaitforge.mlp.v1 file (docs/learned-models.md) that
   the descriptor's electrical.current_model names, the figures as JSON, and a figure.

Run from the repository root after ./scripts/build.sh, with the CPU to itself:
    /usr/bin/python3 bench/go2/current_model.py [--seconds 20] [--out-model FILE]
        [--json FILE] [--figure FILE]
"""
import argparse
import concurrent.futures
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import motor_reference  # noqa: E402

ROOT = motor_reference.ROOT
SIM = os.path.join(ROOT, "build", "bin", "gaitforge-sim")
JOINTS = [j for side in ("fr", "fl", "rr", "rl") for j in ("hip_" + side, "thigh_" + side, "calf_" + side)]
INPUTS = [j + ".torque" for j in JOINTS] + [j + ".rate" for j in JOINTS]
SPEEDS = [0.16, 0.22, 0.28, 0.34]
# Genes T, stance, lift, speed, height, load, lr, fh (robots/go2_castors/robot.yaml).
GAITS = {"trot": [0.6, 0.5, 0.08, None, 0.30, 1.0, 0.5, 0.5],
         "slide": [0.8, 0.6, 0.03, None, 0.10, 0.3, 0.0, 0.5]}
REPEATS = [(1.0, 25.0), (0.8, 35.0), (1.2, 45.0), (0.9, 30.0)]  # foot.mu, windings' start C
PAPER = {"mse": 0.1674, "mae": 0.1684, "r2": 0.974, "mape": 6.28, "abs_sd": 0.357, "p95": 0.468}
PAPER_COT = {"trot": [6.24, 4.67, 4.07, 3.48], "slide": [1.07, 0.97, 0.85, 0.73]}  # sim-NN
RATE_HZ = 500


def record(gait, speed, repeat, seconds, workdir):
    genes = list(GAITS[gait])
    genes[3] = speed
    mu, _ = REPEATS[repeat]
    cycles = max(1, round(seconds / genes[0]))
    out = os.path.join(workdir, "%s-%.2f-%d.csv" % (gait, speed, repeat))
    subprocess.run([SIM, "trajectory", "--robot", "go2_castors", "--genes", ",".join(map(str, genes)),
                    "--cycles", str(cycles), "--settle", "2", "--rate", str(RATE_HZ),
                    "--set", "foot.mu=%g" % mu, "--out", out], check=True, capture_output=True)
    with open(out) as f:
        rows = list(csv.reader(row for row in f if not row.startswith("#")))
    head, data = rows[0], np.array(rows[1:], dtype=float)
    return {name: data[:, k] for k, name in enumerate(head)}


def sample_set(runs, numbers):
    """Per run: inputs X (n x 24), the reference current y, and the run's speed (m/s)."""
    out = []
    for (gait, speed, repeat), ch in runs.items():
        x = np.stack([ch[name] for name in INPUTS], axis=1)
        torque = {j: ch[j + ".torque"] for j in JOINTS}
        rate = {j: ch[j + ".rate"] for j in JOINTS}
        y = motor_reference.bus_current(torque, rate, 1.0 / RATE_HZ, REPEATS[repeat][1],
                                        seed=hash((gait, speed, repeat)) % (1 << 31), numbers=numbers)
        v = (ch["torso.x"][-1] - ch["torso.x"][0]) / (ch["t"][-1] - ch["t"][0])
        out.append(((gait, speed, repeat), x, y, v))
    return out


def export(mlp, x_train, path):
    layers = [{"weights": w.T.tolist(), "bias": b.tolist()} for w, b in zip(mlp.coefs_, mlp.intercepts_)]
    net = {"format": "gaitforge.mlp.v1", "inputs": INPUTS, "outputs": ["bus.current"],
           "activation": "relu",
           "input_mean": [0.0] * len(INPUTS), "input_sd": [1.0] * len(INPUTS),
           "output_mean": [0.0], "output_sd": [1.0],
           "input_min": x_train.min(axis=0).tolist(), "input_max": x_train.max(axis=0).tolist(),
           "layers": layers}
    # 9 significant digits (float32's precision): a third of the bytes of 17.
    text = json.dumps(net, separators=(",", ":"))
    short = json.loads(text, parse_float=lambda s: float("%.9g" % float(s)))
    with open(path, "w") as f:
        f.write(json.dumps(short, separators=(",", ":")) + "\n")


def metrics(y, p):
    err = p - y
    big = np.abs(y) > 0.5  # MAPE over currents above 0.5 A (near zero it is undefined)
    return {"mse": float(np.mean(err ** 2)), "mae": float(np.mean(np.abs(err))),
            "r2": float(1 - np.sum(err ** 2) / np.sum((y - y.mean()) ** 2)),
            "mape": float(100 * np.mean(np.abs(err[big] / y[big]))),
            "abs_sd": float(np.std(np.abs(err))), "p95": float(np.percentile(np.abs(err), 95))}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=20.0, help="each run's measured length (s)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--max-epochs", type=int, default=30, help="the training's cap (early stopping, 3 epochs without gain, ends it sooner)")
    ap.add_argument("--out-model", default=os.path.join(ROOT, "robots", "go2_castors", "current.mlp.json"))
    ap.add_argument("--json", default=None, help="write the figures here")
    ap.add_argument("--figure", default=None, help="an SVG of the test repeat's current, reference and MLP")
    ap.add_argument("--fixture", default=os.path.join(ROOT, "tests", "fixtures", "go2", "current_held_out.csv"),
                    help="write 2 s of each gait of the test repeat at 0.22 m/s here (inputs and the "
                         "reference current) for tests/unit/generic/go2_current_test.cc")
    args = ap.parse_args()
    from sklearn.neural_network import MLPRegressor
    t0 = time.monotonic()
    keys = [(g, s, r) for g in GAITS for s in SPEEDS for r in range(len(REPEATS))]
    with tempfile.TemporaryDirectory() as work, concurrent.futures.ThreadPoolExecutor(2) as pool:
        futures = {k: pool.submit(record, *k, args.seconds, work) for k in keys}
        runs = {k: f.result() for k, f in futures.items()}
    t_record = time.monotonic() - t0
    numbers = motor_reference.descriptor_numbers()
    sets = sample_set(runs, numbers)
    train = [s for s in sets if s[0][2] < 3]
    test = [s for s in sets if s[0][2] == 3]
    x_train = np.concatenate([s[1] for s in train])
    y_train = np.concatenate([s[2] for s in train])
    print("go2 current: %d runs recorded in %.0f s; %d training samples, %d test" % (
        len(sets), t_record, len(y_train), sum(len(s[2]) for s in test)), flush=True)
    t1 = time.monotonic()
    mlp = MLPRegressor(verbose=True, hidden_layer_sizes=(256, 256, 256, 256), activation="relu", solver="adam",
                       learning_rate_init=3e-4, batch_size=512, early_stopping=True,
                       validation_fraction=0.2, n_iter_no_change=3, max_iter=args.max_epochs,
                       random_state=args.seed)
    mlp.fit(x_train, y_train)
    t_train = time.monotonic() - t1
    x_test = np.concatenate([s[1] for s in test])
    y_test = np.concatenate([s[2] for s in test])
    p_test = mlp.predict(np.clip(x_test, x_train.min(axis=0), x_train.max(axis=0)))
    m = metrics(y_test, p_test)
    print("trained in %.0f s, %d epochs" % (t_train, mlp.n_iter_))
    print("%-8s %10s %10s" % ("", "gaitforge", "paper"))
    for k in ("mse", "mae", "r2", "mape", "abs_sd", "p95"):
        print("%-8s %10.4f %10.4f" % (k, m[k], PAPER[k]))
    export(mlp, x_train, args.out_model)
    cot = cost_of_transport(test, mlp, x_train)
    print("\ncost of transport on the test repeat: reference / MLP (paper's sim-NN)")
    for gait in GAITS:
        print("%-6s " % gait + "  ".join("%.2f: %.2f / %.2f (%.2f)" % (s, cot[gait][i][0], cot[gait][i][1],
                                                                      PAPER_COT[gait][i])
                                         for i, s in enumerate(SPEEDS)))
    result = {"seconds": args.seconds, "runs": len(sets), "train_samples": int(len(y_train)),
              "test_samples": int(len(y_test)), "epochs": int(mlp.n_iter_), "train_s": t_train,
              "record_s": t_record, "metrics": m, "paper": PAPER, "cot": cot, "paper_cot": PAPER_COT,
              "speeds": SPEEDS}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)
    if args.figure:
        draw(test, mlp, x_train, args.figure)
    if args.fixture:
        write_fixture(test, args.fixture)


def write_fixture(test, path):
    """The held-out repeat's first 2 s of each gait at 0.22 m/s, every second sample."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write("# gait 0 trot, 1 slide; %s\n" % "written by bench/go2/current_model.py")
        f.write(",".join(["gait"] + INPUTS + ["bus.current"]) + "\n")
        for k, gait in enumerate(GAITS):
            (_, x, y, _) = next(s for s in test if s[0][0] == gait and s[0][1] == 0.22)
            for i in range(0, 2 * RATE_HZ, 2):
                f.write(",".join([str(k)] + ["%.6g" % v for v in x[i]] + ["%.6g" % y[i]]) + "\n")


def cost_of_transport(test, mlp, x_train):
    """Per gait and speed: mean V I / (m g v) from the reference current and the MLP's."""
    volts = motor_reference.descriptor_numbers()[0]
    weight = robot_mass() * 9.81
    out = {g: [None] * len(SPEEDS) for g in GAITS}
    for (gait, speed, _), x, y, v in test:
        p = mlp.predict(np.clip(x, x_train.min(axis=0), x_train.max(axis=0)))
        out[gait][SPEEDS.index(speed)] = [float(volts * y.mean() / (weight * v)),
                                          float(volts * p.mean() / (weight * v))]
    return out


def robot_mass():
    import yaml
    with open(os.path.join(ROOT, "robots", "go2_castors", "robot.yaml")) as f:
        p = yaml.safe_load(f)["parameters"]
    return (p["base"]["mass_kg"]["value"] + 4 * sum(p[g]["mass_kg"]["value"]
                                                    for g in ("hip", "thigh", "calf", "foot", "castor")))


def draw(test, mlp, x_train, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 1, figsize=(10, 6))
    for ax, gait in zip(axes, GAITS):
        (_, x, y, _) = next(s for s in test if s[0][0] == gait and s[0][1] == 0.22)
        p = mlp.predict(np.clip(x, x_train.min(axis=0), x_train.max(axis=0)))
        t = np.arange(len(y)) / RATE_HZ
        keep = t < 3
        ax.plot(t[keep], y[keep], lw=0.8, label="reference (motor_reference.py)")
        ax.plot(t[keep], p[keep], lw=0.8, label="MLP")
        ax.set_ylabel("battery current (A)")
        ax.set_title("%s at 0.22 m/s, test repeat" % gait)
        ax.legend(fontsize=8)
    axes[-1].set_xlabel("t (s)")
    fig.tight_layout()
    fig.savefig(path)


if __name__ == "__main__":
    main()
