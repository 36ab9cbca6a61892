"""Data for the end-to-end benchmark (benches/end_to_end/run.sh): 4 records of a chain
of 100 unit masses between walls, springs k and dashpots between neighbours (c_chain)
and from every mass to ground (c_ground), driven on mass 1 by
f(t) = F1 cos(ωt) + F3 sin(3ωt), in steady state.

The response is exact, not simulated: for each harmonic q of the drive the complex
amplitude solves (K − (qω)² M + i qω C) X_q = F_q, and x(t) = Σ_q Re(X_q e^{iqωt}),
v(t) = Σ_q Re(iqω X_q e^{iqωt}), so every record is periodic with a whole number of
samples per period (T = N h, N = 400, 500, 800, 1000) and the energy balance holds
exactly; seeded Gaussian noise of 10⁻⁴ of each signal's RMS is added to x, v and f.
Each record is an uncompressed .npz (np.savez) with t (n,), x (n × 100), v (n × 100)
and f (n,): 2·10⁵ samples, 323 MB, 1.29 GB in all. Also writes the model files
chain100_{measured,central_difference,harmonic_projection}.toml next to the data, and
the one-record case of issue 32 (record_1 alone, N = 400, windows of one period, one
coefficient per element: 101 chain and 100 ground dashpots, 201 coefficients,
accept_transient = true): one_record_{measured,harmonic_projection}.toml.

    python generate.py OUT_DIR           # the 4 records (1.29 GB)
    python generate.py OUT_DIR --one     # record_1 only (323 MB), for one_record.sh
"""

import sys
from pathlib import Path

import numpy as np

DOFS = 100
SAMPLES = 200_000
STEP = 1e-3
PER_PERIOD = [400, 500, 800, 1000]
K_SPRING = 1.0e4
C_CHAIN = 0.8
C_GROUND = 0.05
NOISE = 1e-4


def system():
    n = DOFS
    k = np.zeros((n, n))
    c = np.zeros((n, n))
    for i in range(n):
        k[i, i] = 2 * K_SPRING
        c[i, i] = 2 * C_CHAIN + C_GROUND
        if i + 1 < n:
            k[i, i + 1] = k[i + 1, i] = -K_SPRING
            c[i, i + 1] = c[i + 1, i] = -C_CHAIN
    return k, c


def record(per_period, rng):
    k, c = system()
    period = per_period * STEP
    omega = 2 * np.pi / period
    t = np.arange(SAMPLES) * STEP
    x = np.zeros((SAMPLES, DOFS))
    v = np.zeros((SAMPLES, DOFS))
    f = np.zeros(SAMPLES)
    # harmonic q with complex force amplitude on mass 1: F1 cos = Re(F1 e^{iωt}),
    # F3 sin(3ωt) = Re(−i F3 e^{3iωt})
    for q, amplitude in [(1, 10.0), (3, -2.0j)]:
        w = q * omega
        forcing = np.zeros(DOFS, dtype=complex)
        forcing[0] = amplitude
        amplitudes = np.linalg.solve(k - w * w * np.eye(DOFS) + 1j * w * c, forcing)
        phasor = np.exp(1j * w * t)
        x += np.real(np.outer(phasor, amplitudes))
        v += np.real(np.outer(phasor, 1j * w * amplitudes))
        f += np.real(amplitude * phasor)
    for signal in (x, v):
        signal += NOISE * np.sqrt(np.mean(signal**2, axis=0)) * rng.standard_normal(signal.shape)
    f += NOISE * np.sqrt(np.mean(f**2)) * rng.standard_normal(SAMPLES)
    return t, x, v, f, period


def model(velocity, periods):
    lines = [
        f"# End-to-end benchmark (benches/end_to_end/): the 100-mass chain of generate.py,",
        f"# velocity = {velocity}. True values: c_chain = {C_CHAIN}, c_ground = {C_GROUND}.",
        f'title = "100-mass chain, 4 records of 2e5 samples ({velocity})"',
        f"dofs = {DOFS}",
        "",
        "[[terms]]",
        'kind = "law"',
        'law = "linear"',
        'elements = "chain"',
        'coefficient = "c_chain"',
        "",
        "[[terms]]",
        'kind = "law"',
        'law = "linear"',
        'elements = "each_dof"',
        'coefficient = "c_ground"',
        "",
        "[identification]",
        f'velocity = "{velocity}"',
        "cycles = 10",
        "",
    ]
    x = ", ".join(f'"x[{i}]"' for i in range(1, DOFS + 1))
    v = ", ".join(f'"v[{i}]"' for i in range(1, DOFS + 1))
    for r, period in enumerate(periods, start=1):
        lines += [
            "[[data.records]]",
            f'file = "record_{r}.npz"',
            'time = "t"',
            f"displacements = [{x}]",
        ]
        if velocity == "measured":
            lines.append(f"velocities = [{v}]")
        lines += ['forces = [{ column = "f", dof = 1 }]', f"period = {period!r}", ""]
    return "\n".join(lines)


def one_record_model(velocity, period):
    """The one-record case: record_1, windows of one period, a coefficient per element."""
    x = ", ".join(f'"x[{i}]"' for i in range(1, DOFS + 1))
    v = ", ".join(f'"v[{i}]"' for i in range(1, DOFS + 1))
    lines = [
        "# One-record benchmark (benches/end_to_end/one_record.sh): record_1 of generate.py,",
        f"# velocity = {velocity}, one coefficient per element (101 + 100), windows of one period.",
        f'title = "100-mass chain, one record of 2e5 samples, 201 coefficients ({velocity})"',
        f"dofs = {DOFS}",
        "",
        "[[terms]]",
        'kind = "law"',
        'law = "linear"',
        'elements = "chain"',
        'per_element = "c_chain"',
        "",
        "[[terms]]",
        'kind = "law"',
        'law = "linear"',
        'elements = "each_dof"',
        'per_element = "c_ground"',
        "",
        "[identification]",
        f'velocity = "{velocity}"',
        "cycles = 1",
        "accept_transient = true",
        "",
        "[[data.records]]",
        'file = "record_1.npz"',
        'time = "t"',
        f"displacements = [{x}]",
    ]
    if velocity == "measured":
        lines.append(f"velocities = [{v}]")
    lines += ['forces = [{ column = "f", dof = 1 }]', f"period = {period!r}", ""]
    return "\n".join(lines)


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(17)
    periods = []
    count = 1 if "--one" in sys.argv else len(PER_PERIOD)
    for r, per_period in enumerate(PER_PERIOD[:count], start=1):
        t, x, v, f, period = record(per_period, rng)
        np.savez(out / f"record_{r}.npz", t=t, x=x, v=v, f=f)
        periods.append(period)
    if count == len(PER_PERIOD):
        for velocity in ["measured", "central_difference", "harmonic_projection"]:
            (out / f"chain100_{velocity}.toml").write_text(model(velocity, periods))
    for velocity in ["measured", "harmonic_projection"]:
        (out / f"one_record_{velocity}.toml").write_text(one_record_model(velocity, periods[0]))


if __name__ == "__main__":
    main()
