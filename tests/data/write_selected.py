"""Writes the fixtures of tests/formats.rs that hold more than a record names, and the
other byte orders and compressions of NumPy files. Run from the repository root:

    python3 tests/data/write_selected.py

with NumPy 2.4 and SciPy 1.17 (the versions that wrote the committed files). The data are
the first 300 rows of models/data/chain3/record_1.csv, as for the other fixtures.
"""

import numpy as np
import scipy.io

table = np.loadtxt("models/data/chain3/record_1.csv", delimiter=",", skiprows=1)[:300]
t, x, f = table[:, 0], table[:, 1:4], table[:, 7]

# A record's arrays beside a 0-d text description, a 3-D array and a scalar gain: a
# model naming t, x and f reads it; the whole-file read refuses the description.
np.savez(
    "tests/data/chain3_extra.npz",
    t=t,
    x=x,
    f=f,
    description=np.array("chain3 record 1 with extras"),
    cube=np.zeros((2, 3, 4)),
    gain=np.array(35.15),
)
# The same arrays deflated (np.savez_compressed), x in Fortran order.
np.savez_compressed("tests/data/chain3_compressed.npz", t=t, x=np.asfortranarray(x), f=f)
# Big-endian f8, C order.
np.save("tests/data/x_big_endian.npy", x.astype(">f8"))
# A MATLAB file with scalars beside the record (a gain, a controller constant): the
# whole-file read refuses it (lengths differ), a record naming t, x and f reads it.
scipy.io.savemat(
    "tests/data/chain3_scalars.mat",
    {"t": t, "x": x, "f": f, "gain": 35.15, "gtau": np.array([[0.02]])},
)
