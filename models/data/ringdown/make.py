"""Writes hammer.npz: a hammer test of one structure with two modes, as an
accelerometer and an instrumented hammer record it (models/ringdown.toml reads it).

Mode 1 (80 Hz, unit modal mass): viscous c = 1.00531 N·s/m (ζ = 0.1 %) plus a power law
5 |v|^1.5 sgn v (a joint's micro-slip); mode 2 (296 Hz) linear, ζ = 0.3 %. A half-sine
force of 400 N over 0.5 ms hits both modes after 0.02 s of quiet; the accelerometer reads
the sum of the modes' accelerations. 12.8 kHz, 65 536 samples; Gaussian noise of 0.5 % of
each channel's RMS. Integrated by RK4 with 8 substeps per sample (NumPy only, not
dampid: the truth the example is compared with).

    python3 models/data/ringdown/make.py
"""

import math
from pathlib import Path

import numpy as np

STEP = 1.0 / 12_800.0
SAMPLES = 65_536
SUBSTEPS = 8
QUIET = 256
PEAK, DURATION = 400.0, 0.5e-3
W1, W2 = 2 * math.pi * 80.0, 2 * math.pi * 296.0
C1, D1, P1 = 2 * 0.001 * W1, 5.0, 1.5
C2 = 2 * 0.003 * W2


def force(t):
    t0 = QUIET * STEP
    return PEAK * math.sin(math.pi * (t - t0) / DURATION) if t0 <= t <= t0 + DURATION else 0.0


def acc1(t, x, v):
    return force(t) - C1 * v - D1 * abs(v) ** P1 * math.copysign(1.0, v) - W1 * W1 * x


def acc2(t, x, v):
    return force(t) - C2 * v - W2 * W2 * x


def simulate(acc):
    x = v = 0.0
    h = STEP / SUBSTEPS
    out = np.empty(SAMPLES)
    for i in range(SAMPLES):
        t = i * STEP
        out[i] = acc(t, x, v)
        for s in range(SUBSTEPS):
            ts = t + s * h
            k1x, k1v = v, acc(ts, x, v)
            k2x, k2v = v + 0.5 * h * k1v, acc(ts + 0.5 * h, x + 0.5 * h * k1x, v + 0.5 * h * k1v)
            k3x, k3v = v + 0.5 * h * k2v, acc(ts + 0.5 * h, x + 0.5 * h * k2x, v + 0.5 * h * k2v)
            k4x, k4v = v + h * k3v, acc(ts + h, x + h * k3x, v + h * k3v)
            x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
            v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
    return out


def main():
    rng = np.random.default_rng(2026)
    a = simulate(acc1) + simulate(acc2)
    f = np.array([force(i * STEP) for i in range(SAMPLES)])
    noisy = lambda s: s + rng.normal(0.0, 0.005 * np.sqrt(np.mean(s * s)), s.size)
    out = Path(__file__).with_name("hammer.npz")
    np.savez_compressed(out, acceleration=noisy(a), force=noisy(f))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
