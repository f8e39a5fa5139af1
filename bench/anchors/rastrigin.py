"""gaitforge's analytic.rastrigin over the 13-gene caterpillar space, in Python.

Mirrors workers/objectives/analytic.cc and services/core/objective_catalog.cc, shared by
the anchor scripts here: genes x_i in [lo_i, hi_i) ([0, 1) for the first 12, [0.2, 2.0)
for the period T); z_i = 10 (x_i - lo_i) / (hi_i - lo_i) - 5 - s_i with
s_i = (+1 if i even else -1) * shift * 5; loss = 10 n + sum(z_i^2 - 10 cos(2 pi z_i));
fitness = -loss (maximised; 0 at the optimum).
"""
import math

NAMES = ["a_T1", "a_T2", "a_T3", "a_B1", "a_B2", "a_B3",
         "d_T1", "d_T2", "d_T3", "d_B1", "d_B2", "d_B3", "T"]
LO = [0.0] * 12 + [0.2]
HI = [1.0] * 12 + [2.0]


def rastrigin_fitness(x, shift=0.2):
    """Fitness (= -loss) of the genes x."""
    loss = 10.0 * len(x)
    for i, xi in enumerate(x):
        s = (1.0 if i % 2 == 0 else -1.0) * shift * 5.0
        z = 10.0 * (xi - LO[i]) / (HI[i] - LO[i]) - 5.0 - s
        loss += z * z - 10.0 * math.cos(2.0 * math.pi * z)
    return -loss
