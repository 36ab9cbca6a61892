"""Writes ringdown.npz and stepped.csv: a ringdown and a stepped-sine table of the same
mode (models/backbones_ringdown.toml and models/backbones_stepped.toml read them;
`dampid backbones` puts their backbones on one plot, docs/free_decay.md "Ringdown
against stepped sine").

The mode (unit modal mass, 80 Hz): m x'' + c x' + d |x'|^1.5 sgn x' + k x = a cos(wt),
c = 1.00531 (zeta = 0.1 %), d = 5. Its equivalent damping ratio at amplitude X,

    zeta_eq(X) = (c + d sqrt(w X) I / pi) / (2 m w),  I = int_0^2pi |sin t|^2.5 dt,

is the truth both backbones are compared with (tests/backbones.rs).

- ringdown.npz: the free decay from x0 = 2 mm at rest, the displacement `x`, 6.4 kHz,
  32 768 samples (5.12 s), RK4 with 8 substeps per sample; Gaussian noise of 0.1 % of
  the signal's RMS.
- stepped.csv: eight force-controlled sweeps, 0.01 N to 3 N log-spaced, 21 frequencies
  each over +-1.2 % around 80 Hz; the response from the harmonic (describing-function)
  balance X |k - m w^2 + i w c_eq(X)| = a solved by bisection; noise 0.5 % on force and
  amplitude, 0.3 degree on the phase (seeded).

NumPy and the standard library only, not dampid: the truth the example is compared with.

    python3 models/data/backbones/make.py
"""

import math
import random
from pathlib import Path

import numpy as np

M, W = 1.0, 2 * math.pi * 80.0
K = M * W * W
C, D, P = 2 * 0.001 * W, 5.0, 1.5
I15 = 2 * math.sqrt(math.pi) * math.gamma(1.75) / math.gamma(2.25)

STEP, SAMPLES, SUBSTEPS, X0 = 1.0 / 6400.0, 32_768, 8, 2e-3
LEVELS = [0.01 * 300 ** (k / 7) for k in range(8)]
POINTS, SPAN = 21, 0.012


def acc(x, v):
    return (-C * v - D * abs(v) ** P * math.copysign(1.0, v) - K * x) / M


def ringdown():
    x, v = X0, 0.0
    h = STEP / SUBSTEPS
    out = np.empty(SAMPLES)
    for i in range(SAMPLES):
        out[i] = x
        for _ in range(SUBSTEPS):
            k1x, k1v = v, acc(x, v)
            k2x, k2v = v + 0.5 * h * k1v, acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v)
            k3x, k3v = v + 0.5 * h * k2v, acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v)
            k4x, k4v = v + h * k3v, acc(x + h * k3x, v + h * k3v)
            x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
            v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
    return out


def response(w, a):
    stiff = K - M * w * w

    def c_eq(x):
        return C + D * math.sqrt(w * x) * I15 / math.pi

    lo, hi = 0.0, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid * math.hypot(stiff, w * c_eq(mid)) > a:
            hi = mid
        else:
            lo = mid
    x = 0.5 * (lo + hi)
    return x, math.atan2(w * c_eq(x), stiff)


def table():
    rng = random.Random(31)
    rows = ["level,f_hz,force_n,x_m,phase_deg"]
    for level, a in enumerate(LEVELS, start=1):
        for i in range(POINTS):
            f_hz = 80.0 * (1 - SPAN + 2 * SPAN * i / (POINTS - 1))
            x, phi = response(2 * math.pi * f_hz, a)
            x_meas = x * (1 + 0.005 * rng.gauss(0, 1))
            phi_meas = phi + math.radians(0.3) * rng.gauss(0, 1)
            a_meas = a * (1 + 0.005 * rng.gauss(0, 1))
            rows.append(f"{level},{f_hz!r},{a_meas!r},{x_meas!r},{math.degrees(phi_meas)!r}")
    return "\n".join(rows) + "\n"


def main():
    here = Path(__file__).parent
    x = ringdown()
    rng = np.random.default_rng(31)
    x = x + rng.normal(0.0, 0.001 * np.sqrt(np.mean(x * x)), x.size)
    np.savez_compressed(here / "ringdown.npz", x=x)
    (here / "stepped.csv").write_text(table())
    print(f"wrote {here / 'ringdown.npz'} and {here / 'stepped.csv'}")


if __name__ == "__main__":
    main()
