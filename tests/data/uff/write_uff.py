"""Writes the UFF dataset 58 fixtures of tests/uff.rs with pyuff (2.5.8, NumPy 2.4).

From the first 300 rows of models/data/chain3/record_1.csv (t from 600 s, step 5e-5 s,
so 20 kHz): displacements x1..x3 at nodes 1..3 in +Z (ordinate type 8, displacement,
ID lines "x1".."x3") and the force f1 at node 1 in +Z (type 13, excitation force, ID "f1").

    python3 tests/data/uff/write_uff.py      # from the repository root
"""
import csv
import os

import numpy as np
import pyuff

here = os.path.dirname(os.path.abspath(__file__))
with open("models/data/chain3/record_1.csv") as f:
    rows = list(csv.reader(f))
header, rows = rows[0], np.array(rows[1:301], dtype=float)
col = {name: rows[:, k] for k, name in enumerate(header)}
t = col["t"]


def dataset(name, node, kind, binary, spacing=1):
    return {
        "type": 58, "binary": binary, "func_type": 1, "id1": name, "id2": "dampid fixture",
        "rsp_node": node, "rsp_dir": 3, "ref_node": 1, "ref_dir": 3,
        "abscissa_spacing": spacing, "abscissa_spec_data_type": 17,
        "abscissa_axis_lab": "Time", "abscissa_axis_units_lab": "s",
        "ordinate_spec_data_type": kind, "ordinate_axis_lab": name,
        "ordinate_axis_units_lab": "N" if kind == 13 else "m",
        "orddenom_spec_data_type": 0, "data": col[name].copy(), "x": t.copy(),
    }


def write(file, binary, spacing=1, double=True):
    path = os.path.join(here, file)
    # pyuff 2.5.8 in mode "overwrite" truncates a binary file again after writing the
    # first set's header, losing that set, so every set is appended to an empty file.
    open(path, "w").close()
    sets = [dataset(f"x{j}", j, 8, binary, spacing) for j in (1, 2, 3)]
    sets.append(dataset("f1", 1, 13, binary, spacing))
    if not double:
        for s in sets:
            s["ord_data_type"] = 2
    pyuff.UFF(path).write_sets(sets, mode="add", force_double=double)


write("chain3_ascii.uff", binary=0)
write("chain3_binary.uff", binary=1)
write("chain3_single.unv", binary=0, double=False)
write("chain3_uneven.uff", binary=0, spacing=0)
