#!/usr/bin/env python3
"""Generates bolted_joint.csv: a simulated stepped-sine test of one mode of a
bolted-joint-like structure (dampid project data, licence MIT OR Apache-2.0 as the
project). Python 3 standard library only; deterministic (seeded).

The mode: m x'' + c x' + d |x'|^1.5 sign(x') + k x = a cos(wt), i.e. viscous damping
plus a microslip-like dissipation per cycle E_p = d w^1.5 X^2.5 I,
I = int_0^2pi |sin t|^2.5 dt = 2 sqrt(pi) Gamma(1.75) / Gamma(2.25). In the harmonic
(describing-function) approximation the equivalent viscous coefficient is
c_eq(X) = c + d sqrt(w X) I / pi, and the modal response satisfies

    X |k - m w^2 + i w c_eq(X)| = a,    lag phi = atan2(w c_eq(X), k - m w^2),

solved for X by bisection. The measured response adds the residual compliance R of
the other modes (real, in phase with the force): Z = X e^{-i phi} + R a. Noise:
relative 0.5 % on force and amplitude, 0.3 degree on the phase. Seven force-
controlled sweeps (one per force level), 21 frequencies each, +-3 % around 50 Hz.

Usage: python3 generate.py [--levels N] [--points P] [--output FILE]
Without arguments it writes the shipped bolted_joint.csv (in the current folder) byte
for byte. --levels N gives N force levels log-spaced from 0.05 N to 3 N instead of the
seven shipped ones; --points P gives P frequencies per sweep over the same band (e.g.
--levels 12 --points 41 --output table12.csv: the 12-sweep, 492-point table of the
HTML page's check, tests/html/check.sh).

Truth: m = 1 kg, k = (2 pi 50)^2 N/m, c = 1.2566 N s/m (zeta = 0.2 %),
d = 5 N (s/m)^1.5, R = -2e-6 m/N.
"""
import argparse
import cmath
import math
import random

M, K, C, D, R = 1.0, (2 * math.pi * 50.0) ** 2, 1.2566, 5.0, -2.0e-6
I25 = 2 * math.sqrt(math.pi) * math.gamma(1.75) / math.gamma(2.25)
LEVELS = [0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 3.0]
POINTS = 21
NOISE_REL, NOISE_PHASE = 0.005, math.radians(0.3)


def response(w, a):
    stiff = K - M * w * w

    def c_eq(x):
        return C + D * math.sqrt(w * x) * I25 / math.pi

    lo, hi = 0.0, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid * math.hypot(stiff, w * c_eq(mid)) > a:
            hi = mid
        else:
            lo = mid
    x = 0.5 * (lo + hi)
    return x, math.atan2(w * c_eq(x), stiff)


def log_levels(n):
    """n force levels log-spaced from the smallest shipped level to the largest."""
    if n == 1:
        return [LEVELS[0]]
    lo, hi = LEVELS[0], LEVELS[-1]
    return [lo * (hi / lo) ** (k / (n - 1)) for k in range(n)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, help="force levels, log-spaced 0.05 N to 3 N (default: the seven shipped)")
    parser.add_argument("--points", type=int, default=POINTS, help=f"frequencies per sweep (default {POINTS})")
    parser.add_argument("--output", default="bolted_joint.csv", help="the CSV file to write")
    args = parser.parse_args()
    if args.points < 2 or (args.levels is not None and args.levels < 1):
        parser.error("--points must be at least 2 and --levels at least 1")
    levels = LEVELS if args.levels is None else log_levels(args.levels)
    points = args.points
    rng = random.Random(20)
    rows = ["level,f_hz,force_n,x_m,phase_deg"]
    for level, a in enumerate(levels, start=1):
        for i in range(points):
            f_hz = 50.0 * (0.97 + 0.06 * i / (points - 1))
            x, phi = response(2 * math.pi * f_hz, a)
            z = x * cmath.exp(-1j * phi) + R * a
            x_meas = abs(z) * (1 + NOISE_REL * rng.gauss(0, 1))
            phi_meas = -cmath.phase(z) + NOISE_PHASE * rng.gauss(0, 1)
            a_meas = a * (1 + NOISE_REL * rng.gauss(0, 1))
            rows.append(f"{level},{f_hz!r},{a_meas!r},{x_meas!r},{math.degrees(phi_meas)!r}")
    with open(args.output, "w") as out:
        out.write("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
