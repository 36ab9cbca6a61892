"""The paper's four-mass chain (Feeny 2009, section 2.2) simulated in NumPy.

M = I, K = tridiag(-1, 2, -1) (walls at both ends), damping C = c K plus d v|v| on every
mass, a force a cos(omega t) on mass 4; classical RK4 with step h, vectorized over
experiments. Independent of dampid's own simulator: the tests and the Dask example use
it as the truth dampid must recover.
"""

import numpy as np

C_TRUE = 0.15
D_TRUE = 0.10
OMEGA = 0.618

K = 2.0 * np.eye(4) - np.eye(4, k=1) - np.eye(4, k=-1)

MODEL = """
dofs = 4
[[terms]]
kind = "stiffness_proportional"
coefficient = "c"
matrix = "chain"

[[terms]]
kind = "law"
law = "quadratic"
elements = "each_dof"
coefficient = "d"
"""


def simulate(amplitudes, omegas, h=0.1, transient=1000, recorded=400, c=C_TRUE, d=D_TRUE):
    """Steady responses of the chain, one per (amplitude, omega) pair.

    Returns t (recorded,), x and v (experiments, recorded, 4), force (experiments, recorded)
    on DOF 4. The recorded time starts at transient * h.
    """
    a = np.asarray(amplitudes, dtype=float)[:, None]
    w = np.asarray(omegas, dtype=float)[:, None]
    e = a.shape[0]
    x = np.zeros((e, 4))
    v = np.zeros((e, 4))

    def accel(t, x, v):
        # M = I: x'' = f e4 - c K v - d v|v| - K x
        f = np.zeros_like(x)
        f[:, 3:4] = a * np.cos(w * t)
        return f - c * v @ K - d * v * np.abs(v) - x @ K

    total = transient + recorded
    xs = np.empty((e, recorded, 4))
    vs = np.empty((e, recorded, 4))
    for k in range(total):
        t = k * h
        if k >= transient:
            xs[:, k - transient] = x
            vs[:, k - transient] = v
        k1x, k1v = v, accel(t, x, v)
        k2x, k2v = v + 0.5 * h * k1v, accel(t + 0.5 * h, x + 0.5 * h * k1x, v + 0.5 * h * k1v)
        k3x, k3v = v + 0.5 * h * k2v, accel(t + 0.5 * h, x + 0.5 * h * k2x, v + 0.5 * h * k2v)
        k4x, k4v = v + h * k3v, accel(t + h, x + h * k3x, v + h * k3v)
        x = x + h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x)
        v = v + h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v)
    t = (transient + np.arange(recorded)) * h
    force = a * np.cos(w * t[None, :])
    return t, xs, vs, force
