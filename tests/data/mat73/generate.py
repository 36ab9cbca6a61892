"""Writes the MAT v7.3 (HDF5) fixtures of tests/mat73.rs, in MATLAB's v7.3 layout, with
h5py (not dampid), and the same numbers as level-5 files with SciPy for the tests that
compare the two readers. Run from the repository root:

    python3 tests/data/mat73/generate.py

with NumPy 2.4, SciPy 1.17 and h5py 3.16 (the versions that wrote the committed files).

MATLAB's v7.3 layout (as `save -v7.3` writes it): a 512-byte user block whose first 128
bytes are the level-5 header (116 bytes of text starting `MATLAB 7.3 MAT-file`, an 8-byte
subsystem offset, version 0x0200, endianness mark 'IM'), then HDF5. Each variable is a
dataset, or a group for a struct, with a string attribute MATLAB_class; dimensions are
stored reversed (an r x c array is a dataset of shape (c, r), its data MATLAB's
column-major order); char is uint16 (MATLAB_int_decode = 2); logical is uint8; complex is
a compound (real, imag); an empty array holds its dimensions with MATLAB_empty = 1; a
struct array is a group whose fields are datasets of object references, one per element,
to values in the group `#refs#`; a cell is a dataset of such references.
"""

import os

import h5py
import numpy as np
import scipy.io

HERE = "tests/data/mat73"


def header(path):
    """Writes MATLAB's 128-byte text header into the user block of `path`."""
    text = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Sat Nov 28 17:00:00 2026 HDF5 schema 1.00 ."
    head = text.ljust(116, b" ") + b"\x00" * 8 + b"\x00\x02" + b"IM"
    assert len(head) == 128
    with open(path, "r+b") as f:
        f.write(head)


class Writer:
    """MATLAB's conventions on an h5py file."""

    def __init__(self, path):
        self.file = h5py.File(path, "w", userblock_size=512, libver="earliest")
        self.refs = None
        self.count = 0
        self.compress = {}

    def ref_group(self):
        if self.refs is None:
            self.refs = self.file.create_group("#refs#")
        return self.refs

    def numeric(self, parent, name, array, cls=None):
        array = np.asarray(array)
        if array.ndim == 0:
            array = array.reshape(1, 1)
        if array.ndim == 1:
            array = array.reshape(1, -1)
        cls = cls or {"float64": "double", "float32": "single", "int16": "int16",
                      "int32": "int32", "uint8": "uint8", "int64": "int64"}[array.dtype.name]
        if array.size == 0:
            d = parent.create_dataset(name, data=np.array(array.shape, dtype=np.uint64))
            d.attrs.create("MATLAB_class", np.bytes_(cls))
            d.attrs.create("MATLAB_empty", np.uint8(1))
            return d
        options = self.compress if array.size > 64 else {}
        d = parent.create_dataset(name, data=np.ascontiguousarray(array.T), **options)
        d.attrs.create("MATLAB_class", np.bytes_(cls))
        return d

    def char(self, parent, name, text):
        codes = np.array([[ord(c) for c in text]], dtype=np.uint16)  # 1 x n
        d = parent.create_dataset(name, data=codes.T)
        d.attrs.create("MATLAB_class", np.bytes_("char"))
        d.attrs.create("MATLAB_int_decode", np.int32(2))
        return d

    def fields(self, group, names):
        vlen = h5py.vlen_dtype(np.dtype("S1"))
        value = np.empty(len(names), dtype=object)
        for k, n in enumerate(names):
            value[k] = np.frombuffer(n.encode(), dtype="S1")
        group.attrs.create("MATLAB_fields", value, dtype=vlen)

    def value(self, parent, name, v):
        """A Python value as MATLAB would store it: dict = 1 x 1 struct, list of dicts =
        1 x n struct array, str = char, ('cell', [...]), ('complex', array),
        ('logical', array), ndarray/number = numeric."""
        if isinstance(v, dict):
            g = parent.create_group(name)
            g.attrs.create("MATLAB_class", np.bytes_("struct"))
            self.fields(g, list(v))
            for k, x in v.items():
                self.value(g, k, x)
            return g
        if isinstance(v, list):
            names = list(v[0])
            g = parent.create_group(name)
            g.attrs.create("MATLAB_class", np.bytes_("struct"))
            self.fields(g, names)
            for field in names:
                refs = [self.referenced(e[field]) for e in v]
                g.create_dataset(field, data=np.array(refs, dtype=h5py.ref_dtype).reshape(len(v), 1))
            return g
        if isinstance(v, str):
            return self.char(parent, name, v)
        if isinstance(v, tuple) and v[0] == "cell":
            refs = [self.referenced(x) for x in v[1]]
            d = parent.create_dataset(name, data=np.array(refs, dtype=h5py.ref_dtype).reshape(len(refs), 1))
            d.attrs.create("MATLAB_class", np.bytes_("cell"))
            return d
        if isinstance(v, tuple) and v[0] == "complex":
            z = np.atleast_2d(v[1])
            compound = np.dtype([("real", "<f8"), ("imag", "<f8")])
            data = np.empty(z.T.shape, dtype=compound)
            data["real"], data["imag"] = z.T.real, z.T.imag
            d = parent.create_dataset(name, data=data)
            d.attrs.create("MATLAB_class", np.bytes_("double"))
            return d
        if isinstance(v, tuple) and v[0] == "logical":
            return self.numeric(parent, name, np.asarray(v[1], dtype=np.uint8), "logical")
        return self.numeric(parent, name, v)

    def referenced(self, v):
        name = self._name()
        return self.value(self.ref_group(), name, v).ref

    def _name(self):
        self.count += 1
        return "r%d" % self.count

    def close(self, path):
        self.file.close()
        header(path)


def write(path, variables, compress=False):
    w = Writer(path)
    if compress:
        w.compress = {"compression": "gzip", "compression_opts": 3, "chunks": True}
    for name, v in variables.items():
        w.value(w.file, name, v)
    w.close(path)


# 1. A record: the 700 rows of models/data/chain3/record_1.csv (t, x as N x 3, f), beside
# a scalar gain; deflated chunks as MATLAB writes.
table = np.loadtxt("models/data/chain3/record_1.csv", delimiter=",", skiprows=1)
t, x, f = table[:, [0]], table[:, 1:4], table[:, [7]]
write(f"{HERE}/chain3_record1_v73.mat", {"t": t, "x": x, "f": f, "gtau": np.array([[0.02]])}, compress=True)

# 2. Contents of every kind: the structs of tests/data/structs_v7.mat and what is not read.
sweeps = [
    {"frequency": np.array([[10.0, 11.0, 12.0, 13.0]]) + k,
     "amplitude": np.array([[1.0], [2.0], [3.0], [4.0]]) * (k + 1),
     "units": "m/s^2"}
    for k in range(3)
]
write(f"{HERE}/contents_v73.mat", {
    "s": {"a": np.array([[0.5], [1.5], [2.5]]),
          "inner": {"d": np.array([[1, -2, 3]], dtype=np.int16)},
          "units": "N"},
    "sweeps": sweeps,
    "c": ("cell", [np.array([[1.0]]), "text"]),
    "z": ("complex", np.array([[1 + 2j, 3 - 1j]])),
    "flags": ("logical", np.array([[1, 0, 1]])),
    "m": np.arange(6.0).reshape(2, 3),
    "q": np.arange(4.0).reshape(4, 1),
    "single": np.array([[0.25, 0.5]], dtype=np.float32),
    "empty": np.zeros((0, 3)),
    "gain": np.array([[2.5]]),
})

# 3. The lab's stepped-sine layout of issue 30: FRdata.ForceControl(1..4) and
# FRdata.ResponseControl(1..8), each with frequency 1 x 41, force, amplitude, phase 41 x 1
# and a units text, from the one-DOF oscillator of tests/support/stepped_sine_table.rs
# (m = 1, k = (2*pi*50)^2, viscous c = 1.2566 plus d |v|^1.5 sign v with d = 5, harmonic
# balance), 0.5 % noise on force and amplitude, 0.3 deg on the phase. Written as v7.3
# (h5py) and as level 5 (SciPy) with the same numbers.
M, K, C, D = 1.0, (2 * np.pi * 50) ** 2, 1.2566, 5.0
n = 200_000
theta = (np.arange(n) + 0.5) * 2 * np.pi / n
INTEGRAL = np.sum(np.abs(np.sin(theta)) ** 2.5) * 2 * np.pi / n


def response(omega, force):
    def c_eq(x):
        return C + D * np.sqrt(omega * x) * INTEGRAL / np.pi

    stiff = K - M * omega * omega
    lo, hi = 0.0, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid * np.hypot(stiff, omega * c_eq(mid)) - force > 0:
            hi = mid
        else:
            lo = mid
    x = 0.5 * (lo + hi)
    return x, np.arctan2(omega * c_eq(x), stiff)


rng = np.random.default_rng(30)
levels = [0.05, 0.1, 0.2, 0.5, 0.7, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0]
elements = []
for force in levels:
    f_hz = 50.0 * (0.97 + 0.06 * np.arange(41) / 40)
    xs, phis = zip(*(response(2 * np.pi * fh, force) for fh in f_hz))
    elements.append({
        "frequency": f_hz.reshape(1, 41),
        "force": (force * (1 + 0.005 * rng.standard_normal(41))).reshape(41, 1),
        "amplitude": (np.array(xs) * (1 + 0.005 * rng.standard_normal(41))).reshape(41, 1),
        "phase": (np.degrees(phis) + 0.3 * rng.standard_normal(41)).reshape(41, 1),
        "units": "Hz, N, m, deg",
    })
frdata = {"ForceControl": elements[:4], "ResponseControl": elements[4:]}
write(f"{HERE}/frdata_v73.mat", {"FRdata": frdata}, compress=True)
record = np.dtype([(k, object) for k in elements[0]])


def struct_array(items):
    a = np.empty((1, len(items)), dtype=record)
    for k, e in enumerate(items):
        for field, v in e.items():
            a[0, k][field] = v
    return a


scipy.io.savemat(
    f"{HERE}/frdata_v7.mat",
    {"FRdata": {"ForceControl": struct_array(elements[:4]),
                "ResponseControl": struct_array(elements[4:])}},
    do_compression=True,
)
# 4. A struct array whose element refers to itself (a crafted file: refused, not followed
# forever), beside a vector.
w = Writer(f"{HERE}/cycle_v73.mat")
loop = w.ref_group().create_group("loop")
loop.attrs.create("MATLAB_class", np.bytes_("struct"))
loop.create_dataset("next", data=np.array([[loop.ref]], dtype=h5py.ref_dtype))
top = w.file.create_group("top")
top.attrs.create("MATLAB_class", np.bytes_("struct"))
top.create_dataset("next", data=np.array([[loop.ref], [loop.ref]], dtype=h5py.ref_dtype))
w.numeric(w.file, "x", np.arange(3.0))
w.close(f"{HERE}/cycle_v73.mat")

for name in sorted(os.listdir(HERE)):
    print(name, os.path.getsize(f"{HERE}/{name}"))
