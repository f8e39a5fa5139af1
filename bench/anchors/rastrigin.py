"""gaitforge's analytic.rastrigin over its default 13-gene space, in Python.

Mirrors workers/objectives/analytic.cc and services/core/objective_catalog.cc, shared by
the anchor scripts here: genes x1..x13 in [lo_i, hi_i) = [0, 1); z_i = 10 (x_i - lo_i) / (hi_i - lo_i) - 5 - s_i with
s_i = (+1 if i even else -1) * shift * 5; loss = 10 n + sum(z_i^2 - 10 cos(2 pi z_i));
fitness = -loss (maximised; 0 at the optimum).
"""
import math

NAMES = [f"x{i}" for i in range(1, 14)]
LO = [0.0] * 13
HI = [1.0] * 13


def rastrigin_fitness(x, shift=0.2):
    """Fitness (= -loss) of the genes x."""
    loss = 10.0 * len(x)
    for i, xi in enumerate(x):
        s = (1.0 if i % 2 == 0 else -1.0) * shift * 5.0
        z = 10.0 * (xi - LO[i]) / (HI[i] - LO[i]) - 5.0 - s
        loss += z * z - 10.0 * math.cos(2.0 * math.pi * z)
    return -loss
