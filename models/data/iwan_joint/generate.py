#!/usr/bin/env python3
"""Generates record_1.csv ... record_10.csv: a single-DOF oscillator with a
four-parameter Iwan joint (Segalman 2005) beside a linear spring and light viscous
damping, forced harmonically at five levels and two frequencies (dampid project data,
licence MIT OR Apache-2.0 as the project). NumPy only; deterministic (no random
numbers: the data are noise-free).

    m x'' + c x' + k x + F_J(x) = a cos(w t)

The joint: slider strengths phi with density R phi^chi on [0, phi_max] plus a spike
S delta(phi - phi_max), K_T = R phi_max^(chi+1)/(chi+1) + S its stiffness,
beta = S / (R phi_max^(chi+1)/(chi+1)). Here it is discretised with 400 sliders of
equal stiffness in the continuous part (slice k of t = phi/phi_max with equal
t^(chi+1) increments, its slider at the slice's centroid) plus the spike; each slider
of stiffness m_k holds an offset p_k with |x - p_k| <= phi_k, and
F_J = sum_k m_k (x - p_k). This is not dampid's discretisation (120 geometric
intervals, state advanced along x): the integrator here is classical RK4 in time on a
step 8 times finer than the records', each stage reading the force of the sliders
clipped to the stage's x, the sliders committed (clipped) after each step.

Truth: m = 1, k = 30, c = 0.3, K_T = 10, phi_max = 0.05, chi = -0.5, beta = 0.5
(consistent units, e.g. kg, N/m, N s/m, m). Drive: w = 0.7 and 1.4 w_n,
w_n = sqrt((k + K_T)/m); a = |k + K_T - m w^2| X for X = 0.01, 0.02, 0.035, 0.06, 0.1
(the linearised amplitude, from deep microslip to beyond macroslip at phi_max = 0.05).
Each record starts on the spring's linear steady state with the joint unloaded, runs
150 periods of transient and keeps 4 periods of 200 samples (t, x, v, f).

Run from anywhere: python3 models/data/iwan_joint/generate.py
"""
import os

import numpy as np

M, K, C = 1.0, 30.0, 0.3
K_T, PHI_MAX, CHI, BETA = 10.0, 0.05, -0.5, 0.5
SLIDERS = 400
SAMPLES = 200  # per period, in the records
FINE = 8  # integration steps per record sample
TRANSIENT = 150  # periods discarded
RECORDED = 4  # periods kept
RATIOS = [0.7, 1.4]
LEVELS = [0.01, 0.02, 0.035, 0.06, 0.1]


def sliders():
    """Strengths and stiffnesses of the discretised joint (equal-stiffness slices)."""
    c1, c2 = CHI + 1.0, CHI + 2.0
    k = np.arange(SLIDERS)
    a = (k / SLIDERS) ** (1.0 / c1)
    b = ((k + 1) / SLIDERS) ** (1.0 / c1)
    share = b**c1 - a**c1  # 1/SLIDERS each
    moment = c1 / c2 * (b**c2 - a**c2)
    strengths = np.append(PHI_MAX * moment / share, PHI_MAX)
    stiffness = np.append(K_T / (1.0 + BETA) * share, K_T * BETA / (1.0 + BETA))
    return strengths, stiffness


def main():
    strengths, stiffness = sliders()
    wn = np.sqrt((K + K_T) / M)
    omegas, forces, labels = [], [], []
    for ratio in RATIOS:
        w = ratio * wn
        for x in LEVELS:
            omegas.append(w)
            forces.append(abs(K + K_T - M * w * w) * x)
            labels.append((ratio, x))
    w = np.array(omegas)  # one record per entry, integrated side by side
    a = np.array(forces)
    period = 2.0 * np.pi / w
    h = period / (SAMPLES * FINE)
    x = a / (K - M * w * w)  # the spring's linear steady state
    v = np.zeros_like(x)
    p = np.repeat(x[:, None], len(strengths), axis=1)  # unloaded sliders

    def joint(x, p):
        clipped = np.clip(p, x[:, None] - strengths, x[:, None] + strengths)
        return (stiffness * (x[:, None] - clipped)).sum(axis=1)

    def accel(t, x, v, p):
        return (a * np.cos(w * t) - C * v - K * x - joint(x, p)) / M

    total = (TRANSIENT + RECORDED) * SAMPLES * FINE
    keep = TRANSIENT * SAMPLES * FINE
    rows = []
    for step in range(total):
        t = step * h
        if step >= keep and (step - keep) % FINE == 0:
            rows.append(np.stack([t - keep * h, x, v, a * np.cos(w * t)]))
        a1 = accel(t, x, v, p)
        x2, v2 = x + 0.5 * h * v, v + 0.5 * h * a1
        a2 = accel(t + 0.5 * h, x2, v2, p)
        x3, v3 = x + 0.5 * h * v2, v + 0.5 * h * a2
        a3 = accel(t + 0.5 * h, x3, v3, p)
        x4, v4 = x + h * v3, v + h * a3
        a4 = accel(t + h, x4, v4, p)
        x = x + h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
        v = v + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
        p = np.clip(p, x[:, None] - strengths, x[:, None] + strengths)
    assert np.all(np.isfinite(x)), "diverged"
    data = np.array(rows)  # (samples, 4, records)
    here = os.path.dirname(os.path.abspath(__file__))
    for r in range(len(omegas)):
        path = os.path.join(here, f"record_{r + 1}.csv")
        np.savetxt(
            path,
            data[:, :, r],
            delimiter=",",
            header="t,x,v,f",
            comments="",
            fmt="%.12e",
        )
        ratio, level = labels[r]
        print(f"record_{r + 1}.csv: w = {w[r]:.9f} ({ratio} w_n), a = {a[r]:.9f} (X ~ {level})")


if __name__ == "__main__":
    main()
