#!/usr/bin/env python3
"""Generates record_1.csv ... record_4.csv: a two-mass chain (ground - m1 - m2) whose
spring between the masses carries a loss factor (structural damping, complex stiffness
k2 (1 + i eta)), with a viscous dashpot from each mass to ground, in its steady state
under a force on mass 1 (dampid project data, licence MIT OR Apache-2.0 as the
project). Python's standard library only; deterministic (random.Random(2026)).

    M x'' + C x' + K(eta) x = r(t),    r = sum_n F_n cos(n w t) on mass 1

No time integration (a loss factor is non-causal in time, so no integrator produces
it): per harmonic the steady state is closed form, (K(eta) - M (n w)^2 + i n w C) X_n =
F_n e_1, solved here by Cramer's rule, and x(t) = sum_n Re[X_n e^{i n w t}].

Truth: m1 = 1, m2 = 0.5, k1 = 1000 (mass 1 to ground), k2 = 400 (between the masses),
eta = 0.05 on k2 only, c = 0.3 on each mass to ground (consistent units). Natural
frequencies 21.44 and 41.72 rad/s. Four records: w = 19 rad/s with harmonics (1, 2)
of amplitudes (1.0, 0.4) and (2.0, 0), w = 38 rad/s with (1.0, 0) and (1.0, 0.5).
Each keeps 6 periods of 200 samples (t, x1, x2, f) with white Gaussian noise of 2 %
of each displacement's largest harmonic amplitude and 1 % of the force's, written with
10 significant digits.

Run from anywhere: python3 models/data/structural_chain/generate.py
"""
import cmath
import math
import os
import random

M1, M2, K1, K2, ETA, C = 1.0, 0.5, 1000.0, 400.0, 0.05, 0.3
SAMPLES, PERIODS = 200, 6
RECORDS = [(19.0, [1.0, 0.4]), (19.0, [2.0, 0.0]), (38.0, [1.0, 0.0]), (38.0, [1.0, 0.5])]
X_NOISE, F_NOISE = 0.02, 0.01


def response(w, f):
    """(X1, X2) of the force f on mass 1 at angular frequency w."""
    k2 = complex(K2, K2 * ETA)
    a = K1 + k2 - M1 * w * w + 1j * w * C
    b = -k2
    d = k2 - M2 * w * w + 1j * w * C
    det = a * d - b * b
    return f * d / det, -b * f / det


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    rng = random.Random(2026)
    for number, (w, forces) in enumerate(RECORDS, start=1):
        period = 2.0 * math.pi / w
        step = period / SAMPLES
        phasors = [(n + 1, f, response((n + 1) * w, f)) for n, f in enumerate(forces) if f]
        sx = [X_NOISE * max(abs(x[j]) for _, _, x in phasors) for j in range(2)]
        sf = F_NOISE * max(forces)
        lines = ["t,x1,x2,f"]
        for i in range(SAMPLES * PERIODS):
            t = i * step
            x = [sum((x[j] * cmath.exp(1j * n * w * t)).real for n, _, x in phasors) for j in range(2)]
            f = sum(f * math.cos(n * w * t) for n, f, _ in phasors)
            x = [x[j] + rng.gauss(0.0, sx[j]) for j in range(2)]
            f += rng.gauss(0.0, sf)
            lines.append(",".join(f"{v:.10g}" for v in [t, x[0], x[1], f]))
        with open(os.path.join(here, f"record_{number}.csv"), "w") as out:
            out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
