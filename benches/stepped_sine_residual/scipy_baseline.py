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

(dampid evaluates the same columns in closed form, as here, and their derivative in
each residual receptance r_k too; c and d it projects out). Start: p = 1.2 and r_k = 0 as model.toml, c and
d from the linear least squares there. Jacobian: '2-point' (what most users write) and
analytic (dense, 492 x 15). Timing in-process, best of --repeat runs.

With intervals (the same work as dampid's report): the fit, then the exponent's
profile-likelihood interval as a SciPy user would compute it, the way dampid defines
it (varpro/profile.rs): the p where the profiled cost P(p) = min over c, d, r_k of
||e||^2 (a least_squares refit with p fixed, warm-started from the nearest p solved)
rises by F_{1,nu}(0.95) * cost/nu above the minimum, nu = 492 - 15, each end found by
scipy.optimize.brentq between the estimate and the bound to 1e-6 of the bound
interval (dampid's tolerance).

Usage: scipy_baseline.py [--repeat N] [--json]  (prints the estimates and the times)
"""
import argparse
import csv
import json
import math
import os
import time

import numpy as np
from scipy.optimize import brentq, least_squares
from scipy.special import digamma, gammaln
from scipy.stats import f as fisher

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


def profile_interval(jac, best, level=0.95):
    """The exponent's profile interval around the fit `best` (module doc): (lower,
    upper, refits); an end where the rise is not reached at the bound is None."""
    m, n = len(B), 3 + S
    dof = m - n
    minimum = 2 * best.cost
    rise = fisher.ppf(level, 1, dof) * minimum / dof
    lower = np.concatenate([[-np.inf, -np.inf], -BOUND])
    upper = np.concatenate([[np.inf, np.inf], BOUND])
    solved = [(best.x[2], np.delete(best.x, 2))]
    refits = [0]

    def profiled(p):
        start = min(solved, key=lambda s: abs(s[0] - p))[1]
        full = lambda u: np.insert(u, 2, p)
        fixed_jac = jac if jac == "2-point" else (lambda u: np.delete(jacobian(full(u)), 2, axis=1))
        r = least_squares(
            lambda u: residual(full(u)), np.clip(start, lower, upper), jac=fixed_jac,
            bounds=(lower, upper), x_scale="jac", xtol=1e-12, ftol=1e-12, gtol=1e-12,
            method="trf",
        )
        refits[0] += 1
        solved.append((p, r.x))
        return 2 * r.cost - minimum - rise

    ends = []
    p_hat = best.x[2]
    for bound in (0.5, 3.0):
        if profiled(bound) < 0:
            ends.append(None)
            continue
        a, b = sorted((bound, p_hat))
        ends.append(brentq(profiled, a, b, xtol=1e-6 * 2.5))
    return ends[0], ends[1], refits[0]


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
        best_interval = math.inf
        for _ in range(args.repeat):
            t = time.perf_counter()
            with_interval = fit(jac)
            lo, hi, refits = profile_interval(jac, with_interval)
            best_interval = min(best_interval, time.perf_counter() - t)
        out[name] = {
            "seconds": best,
            "seconds_with_interval": best_interval,
            "exponent_interval": [lo, hi],
            "interval_refits": refits,
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
        print(f"  with the exponent's profile interval: {o['seconds_with_interval']:.3f} s, "
              f"[{o['exponent_interval'][0]:.7e}, {o['exponent_interval'][1]:.7e}], "
              f"{o['interval_refits']} refits")
        print("  r_k = " + " ".join(f"{x:.6e}" for x in o["r_k"]))


if __name__ == "__main__":
    main()
