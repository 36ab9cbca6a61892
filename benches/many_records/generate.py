"""Data for benches/many_records/run.sh: a stepped-sine campaign of 492 records of one
DOF (m = 1, k = 400, c = 0.6), each the closed-form steady state
x = F/√((k − mω²)² + (cω)²)·sin(ωt − φ), tan φ = cω/(k − mω²), of a force F·sin(ωt),
at 41 frequencies × 12 force levels, 64 samples per period and 20 periods.

Written twice: every record's arrays in one .npz (x_K, f_K, t_K), named by 492 records of
one model file, and one CSV per record (t, x, f) named by a second model file.
    python generate.py DIR
"""
import sys
from pathlib import Path

import numpy as np

m, k, c = 1.0, 400.0, 0.6
out = Path(sys.argv[1])
out.mkdir(parents=True, exist_ok=True)
omegas = np.linspace(14.0, 26.0, 41)
levels = np.geomspace(0.1, 10.0, 12)
arrays = {}
records_npz, records_csv = [], []
key = 0
for omega in omegas:
    for force in levels:
        key += 1
        period = 2 * np.pi / omega
        t = np.arange(64 * 20) * (period / 64)
        amplitude = force / np.hypot(k - m * omega**2, c * omega)
        phase = np.arctan2(c * omega, k - m * omega**2)
        x = amplitude * np.sin(omega * t - phase)
        f = force * np.sin(omega * t)
        arrays[f"t_{key}"], arrays[f"x_{key}"], arrays[f"f_{key}"] = t, x, f
        np.savetxt(out / f"record_{key}.csv", np.column_stack([t, x, f]), delimiter=",",
                   header="t,x,f", comments="", fmt="%.17g")
        def common(suffix):
            return f'period = {float(period)!r}\nforces = [{{ column = "f{suffix}", dof = 1 }}]\n'

        records_npz.append(f'[[data.records]]\nfile = "campaign.npz"\ntime = "t_{key}"\n'
                           f'displacements = ["x_{key}"]\n'
                           + common(f"_{key}"))
        records_csv.append(f'[[data.records]]\nfile = "record_{key}.csv"\ntime = "t"\n'
                           f'displacements = ["x"]\n' + common(""))
np.savez(out / "campaign.npz", **arrays)
head = """# benches/many_records: 492 stepped-sine records of one DOF, true c = 0.6
title = "492 records ({})"
dofs = 1

[[terms]]
kind = "viscous"
matrix = [[1.0]]
coefficient = "c"

"""
(out / "npz.toml").write_text(head.format("one .npz") + "\n".join(records_npz))
(out / "csv.toml").write_text(head.format("one CSV each") + "\n".join(records_csv))
