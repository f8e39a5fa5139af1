"""A reference for the Go2's battery current, richer than gaitforge's motor model (issue 28).

No measured Go2 currents are at hand, so the learned current model (paper 002's MLP) is
trained on currents this reference computes from simulated joint torques and rates. It
adds what the motor model leaves out (workers/models/generic/power_meter.h), so that the
MLP has something to learn beyond the model it replaces:

- winding resistance rising with temperature (copper, +0.393 %/K from 20 C), each motor's
  winding a first-order thermal mass heated by its copper loss (C 60 J/K, 1.5 K/W to the
  25 C air: a 90 s time constant), starting at a run's own temperature;
- friction inside the motor: the rotor's Coulomb (0.01 N m) and viscous (2e-5 N m s/rad)
  friction need current in the direction of motion;
- regeneration when braking: a bus whose net power is negative returns 60 % of it;
- the current sensor: Gaussian noise of 0.05 A.

The motors' gearing, torque constant and resistance at 20 C, the bus voltage and the
standby current are the descriptor's (robots/go2_castors/robot.yaml, read here): each fact
once. All of this is a stand-in, documented as one: the R^2 beside the paper's is a check
of the pipeline, not of the paper.
"""
import os

import numpy as np
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

ALPHA_PER_K = 0.00393      # copper's temperature coefficient
HEAT_CAPACITY_J_PER_K = 60.0
THERMAL_RESISTANCE_K_PER_W = 1.5
AMBIENT_C = 25.0
COULOMB_NM = 0.01          # at the rotor
VISCOUS_NMS = 2e-5         # at the rotor
REGEN = 0.6
NOISE_A = 0.05


def descriptor_numbers(path=os.path.join(ROOT, "robots", "go2_castors", "robot.yaml")):
    """The electrical section's numbers at the nominal values: bus voltage, standby current,
    and per actuator its (gear, kt, resistance)."""
    with open(path) as f:
        d = yaml.safe_load(f)
    params = d["parameters"]

    def value(expr):
        if isinstance(expr, (int, float)):
            return float(expr)
        group, name = expr.split(".")
        return float(params[group][name]["value"])

    e = d["electrical"]
    motors = {}
    for m in e["motors"]:
        for a in m["actuators"]:
            motors[a] = (value(m["gear"]), value(m["kt"]), value(m["resistance"]))
    return value(e["bus_voltage"]), value(e["standby_current"]), motors


def bus_current(torque, rate, dt, start_c, seed, numbers=None):
    """The battery's current (A) at each sample. torque, rate: dicts actuator -> array (N m,
    rad/s at the joint), sampled every dt seconds; start_c: the windings' temperature at
    the start; seed: the sensor noise's."""
    volts, standby, motors = numbers or descriptor_numbers()
    n = len(next(iter(torque.values())))
    power = np.full(n, volts * standby)
    for name, (gear, kt, r20) in motors.items():
        w_m = gear * np.asarray(rate[name])
        tau_m = np.asarray(torque[name]) / gear + COULOMB_NM * np.sign(w_m) + VISCOUS_NMS * w_m
        i = tau_m / kt
        temp = start_c
        for k in range(n):
            r = r20 * (1 + ALPHA_PER_K * (temp - 20.0))
            copper = 1.5 * r * i[k] ** 2
            power[k] += kt * w_m[k] * i[k] + copper
            temp += dt * (copper - (temp - AMBIENT_C) / THERMAL_RESISTANCE_K_PER_W) / HEAT_CAPACITY_J_PER_K
    power = np.where(power < 0, REGEN * power, power)
    rng = np.random.default_rng(seed)
    return power / volts + rng.normal(0.0, NOISE_A, n)
