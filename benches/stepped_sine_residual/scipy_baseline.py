#!/usr/bin/env python3
"""SciPy baseline of issue 30 item 6: the stepped-sine table table12.csv (12 sweeps x 41
points) with viscous + power damping, the exponent p and one residual receptance r_k
per sweep estimated, written as a user would write it: the full problem, c, d, p and
the 12 r_k all unknowns of one scipy.optimize.least_squares (trust region reflective,
bounds p in [0.5, 3], |r_k| <= min X/a of sweep k as dampid's default), on the
unweighted energy equations (dampid's `weighting = "ordinary"`, model_ordinary.toml):

    e_p = pi a X sin(phi) - c pi w Xm^2 - d w^p Xm^(p+1) G(p),
    Xm = |X e^{-i phi} - r_k a|,   G(p) = int_0^2pi |sin t|^(p+1) dt
         = 2 sqrt(pi) Gamma((p+2)/2) / Gamma((p+3)/2)

(dampid integrates the same columns over a synthesized period of 512 samples, which
equals the closed form to about 1e-8). Start: p = 1.2 and r_k = 0 as model.toml, c and
d from the linear least squares there. Jacobian: '2-point' (what most users write) and
analytic (dense, 492 x 15). Timing in-process, best of --repeat runs.

Usage: scipy_baseline.py [--repeat N] [--json]  (prints the estimates and the times)
"""
import argparse
import csv
import json
import math
import os
import time

import numpy as np
from scipy.optimize import least_squares
from scipy.special import digamma, gammaln

HERE = os.path.dirname(os.path.abspath(__file__))


def load():
    rows = list(csv.DictReader(open(os.path.join(HERE, "table12.csv"))))
    labels = []
    for r in rows:
        if r["level"] not in labels:
            labels.append(r["level"])
    sweep = np.array([labels.index(r["level"]) for r in rows])
    w = np.array([float(r["f_hz"]) for r in rows]) * 2 * math.pi
    a = np.array([float(r["force_n"]) for r in rows])
    x = np.array([float(r["x_m"]) for r in rows])
    phi = np.radians(np.array([float(r["phase_deg"]) for r in rows]))
    return sweep, len(labels), w, a, x, phi


SWEEP, S, W, A, X, PHI = load()
B = math.pi * A * X * np.sin(PHI)
RE, IM = X * np.cos(PHI), X * np.sin(PHI)
BOUND = np.array([np.min((X / A)[SWEEP == s]) for s in range(S)])


def log_g(p):
    return math.log(2 * math.sqrt(math.pi)) + gammaln((p + 2) / 2) - gammaln((p + 3) / 2)


def columns(p, r):
    re = RE - r[SWEEP] * A
    xm = np.hypot(re, IM)
    lin = math.pi * W * xm**2
    pw = np.exp(p * np.log(W) + (p + 1) * np.log(xm) + log_g(p))
    return xm, re, lin, pw


def residual(v):
    c, d, p, r = v[0], v[1], v[2], v[3:]
    _, _, lin, pw = columns(p, r)
    return B - c * lin - d * pw


def jacobian(v):
    c, d, p, r = v[0], v[1], v[2], v[3:]
    xm, re, lin, pw = columns(p, r)
    jac = np.zeros((len(B), 3 + S))
    jac[:, 0] = -lin
    jac[:, 1] = -pw
    dlogg = 0.5 * digamma((p + 2) / 2) - 0.5 * digamma((p + 3) / 2)
    jac[:, 2] = -d * pw * (np.log(W) + np.log(xm) + dlogg)
    # dXm/dr = -a (X cos phi - r a) / Xm; dA/dXm = (2 lin + (p+1) pw) / Xm per unit coefficient
    de_dxm = -(c * 2 * lin + d * (p + 1) * pw) / xm
    dxm_dr = -A * re / xm
    jac[np.arange(len(B)), 3 + SWEEP] = de_dxm * dxm_dr
    return jac


def start():
    p0, r0 = 1.2, np.zeros(S)
    _, _, lin, pw = columns(p0, r0)
    (c0, d0), *_ = np.linalg.lstsq(np.column_stack([lin, pw]), B, rcond=None)
    return np.concatenate([[c0, d0, p0], r0])


def fit(jac):
    lower = np.concatenate([[-np.inf, -np.inf, 0.5], -BOUND])
    upper = np.concatenate([[np.inf, np.inf, 3.0], BOUND])
    return least_squares(
        residual, start(), jac=jac, bounds=(lower, upper), x_scale="jac",
        xtol=1e-12, ftol=1e-12, gtol=1e-12, method="trf",
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    out = {}
    for name, jac in (("2-point", "2-point"), ("analytic", jacobian)):
        best = math.inf
        for _ in range(args.repeat):
            t = time.perf_counter()
            result = fit(jac)
            best = min(best, time.perf_counter() - t)
        out[name] = {
            "seconds": best,
            "evaluations": int(result.nfev),
            "cost": float(2 * result.cost),
            "status": int(result.status),
            "c": result.x[0], "d": result.x[1], "exponent": result.x[2],
            "r_k": list(result.x[3:]),
        }
    if args.json:
        print(json.dumps(out))
        return
    for name, o in out.items():
        print(f"scipy least_squares jac={name}: best of {args.repeat} {o['seconds']:.3f} s, "
              f"{o['evaluations']} evaluations, status {o['status']}, cost {o['cost']:.6e}")
        print(f"  c = {o['c']:.7e}  d = {o['d']:.7e}  exponent = {o['exponent']:.7e}")
        print("  r_k = " + " ".join(f"{x:.6e}" for x in o["r_k"]))


if __name__ == "__main__":
    main()
