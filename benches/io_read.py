"""Data and NumPy/pandas baselines for benches/io_read.sh.

    python io_read.py generate DIR   # DIR/record.npz (323 MB) and DIR/table.csv (210 MB)
    python io_read.py time DIR R [READER...]   # R reads by each reader (default: all)

`generate` writes one record of 100 DOFs x 2e5 samples as np.savez does (stored, not
compressed): t, x and v (2e5 x 100, C order) and a force f; and a CSV of 1e6 rows x 12
columns (t and 11 channels) with 11 significant digits, as dampid writes CSV. `time`
prints one line per reader: `<reader> <file> <best s> <median s> <MB> <rows> <columns>
<CPU s> <sum>`, the CPU time (time.process_time: user and system, all threads) the
median, and the sum of every value read (which dampid's must match).
"""

import os
import sys
import time

import numpy as np


def generate(folder):
    os.makedirs(folder, exist_ok=True)
    rng = np.random.default_rng(17)
    n, dofs = 200_000, 100
    t = np.arange(n) * 1e-3
    phase = rng.uniform(0, 2 * np.pi, dofs)
    x = np.sin(2 * np.pi * 5 * t[:, None] + phase) + 1e-3 * rng.standard_normal((n, dofs))
    v = np.cos(2 * np.pi * 5 * t[:, None] + phase) + 1e-3 * rng.standard_normal((n, dofs))
    f = np.sin(2 * np.pi * 5 * t)
    np.savez(os.path.join(folder, "record.npz"), t=t, x=x, v=v, f=f)
    rows = 1_000_000
    table = np.empty((rows, 12))
    table[:, 0] = np.arange(rows) * 1e-3
    table[:, 1:] = rng.standard_normal((rows, 11))
    header = "t," + ",".join(f"c{j}" for j in range(1, 12))
    np.savetxt(os.path.join(folder, "table.csv"), table, fmt="%.10e", delimiter=",",
               header=header, comments="")


def timed(label, path, read, repeat):
    seconds, cpu = [], []
    shape, total = (0, 0), 0.0
    for _ in range(repeat):
        start, start_cpu = time.perf_counter(), time.process_time()
        shape, total = read(path)
        seconds.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
    seconds.sort()
    cpu.sort()
    mb = os.path.getsize(path) / 1e6
    print(f"{label} {path} {seconds[0]:.4f} {seconds[len(seconds) // 2]:.4f} {mb:.1f} "
          f"{shape[0]} {shape[1]} {cpu[len(cpu) // 2]:.4f} {total:.12e}", flush=True)


def numpy_load(path):
    with np.load(path) as archive:
        arrays = {name: archive[name] for name in archive.files}
    columns = sum(a.shape[1] if a.ndim == 2 else 1 for a in arrays.values())
    return (arrays["x"].shape[0], columns), sum(float(a.sum()) for a in arrays.values())


def numpy_loadtxt(path):
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    return table.shape, float(table.sum())


def pandas_read_csv(path):
    import pandas

    table = pandas.read_csv(path, engine="c")
    return table.shape, float(table.to_numpy().sum())


def main():
    command, folder = sys.argv[1], sys.argv[2]
    if command == "generate":
        generate(folder)
        return
    repeat = int(sys.argv[3])
    readers = sys.argv[4:] or ["numpy.load", "pandas.read_csv", "numpy.loadtxt"]
    for label, file, read in [
        ("numpy.load", "record.npz", numpy_load),
        ("pandas.read_csv", "table.csv", pandas_read_csv),
        ("numpy.loadtxt", "table.csv", numpy_loadtxt),
    ]:
        if label in readers:
            timed(label, os.path.join(folder, file), read, repeat)


if __name__ == "__main__":
    main()
