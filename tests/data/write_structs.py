"""Writes tests/data/structs_v7.mat, a MAT file of structs, struct arrays and contents
dampid does not read, for tests/mat_structs.rs. Run from the repository root:

    python3 tests/data/write_structs.py

with NumPy 2.4 and SciPy 1.17 (the versions that wrote the committed file). SciPy, not
dampid, writes it (compressed, as MATLAB's default -v7), so the reader is checked against
an independent writer.
"""

import numpy as np
import scipy.io

# A 1 × 1 struct of a column, a nested struct (int16 row) and a units text; a 1 × 3
# struct array with a row (1 × 4) and a column (4 × 1) field per element; a cell array;
# a complex vector; a plain top-level vector and the scalar gain of it.
element = np.dtype([("frequency", object), ("amplitude", object), ("units", object)])
sweeps = np.empty((1, 3), dtype=element)
for k in range(3):
    sweeps[0, k]["frequency"] = np.array([[10.0, 11.0, 12.0, 13.0]]) + k
    sweeps[0, k]["amplitude"] = np.array([[1.0], [2.0], [3.0], [4.0]]) * (k + 1)
    sweeps[0, k]["units"] = "m/s^2"
scipy.io.savemat(
    "tests/data/structs_v7.mat",
    {
        "s": {
            "a": np.array([[0.5], [1.5], [2.5]]),
            "inner": {"d": np.array([[1, -2, 3]], dtype=np.int16)},
            "units": "N",
        },
        "sweeps": sweeps,
        "c": np.array([[1.0, "text"]], dtype=object),
        "z": np.array([1 + 2j, 3 - 1j]),
        "q": np.arange(4.0),
        "gain": 2.5,
    },
    do_compression=True,
)
