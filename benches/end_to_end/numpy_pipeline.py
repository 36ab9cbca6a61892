"""The end-to-end pipeline of `dampid identify` (default velocities) in NumPy/SciPy,
for benches/end_to_end/run.sh: load each record, cut it into windows of 10 whole
periods, project every displacement channel on the drive's harmonics by one real FFT
per window (the harmonics kept are those above the noise floor, a median of the bins
between harmonics, as dampid does), differentiate the projection, build one row per
window of the energy balance Σ_k θ_k ∮ vᵀ f_k dt = ∮ vᵀ r dt for the chain and
ground dashpots of generate.py's model, and solve by scipy.linalg.lstsq. No noise-bias
correction nor weighting (dampid's noise-robust rows do more per window).

    python numpy_pipeline.py DATA_DIR            # the whole pipeline
    python numpy_pipeline.py DATA_DIR --load [--repeats R] [--one]
        # numpy.load of every array only, read fully ({k: z[k] for k in z.files}),
        # R times in this one process (default 5), best and every time printed;
        # --one: record_1.npz alone

Prints the elapsed wall time of each stage and the total, in seconds, and the
coefficients.
"""

import sys
import time
from pathlib import Path

import numpy as np
import scipy.linalg

CYCLES = 10
PERIODS = {1: 400, 2: 500, 3: 800, 4: 1000}  # samples per period of record_r.npz


def load_all(files):
    return [{name: z[name] for name in z.files} for z in map(np.load, files)]


def window_row(x, f, per_period, step):
    """One row [chain, ground | input work] from a window of L = CYCLES·N samples."""
    length = CYCLES * per_period
    spectrum = np.fft.rfft(x[:length], axis=0)  # (L/2 + 1) × n
    most = min(int(0.45 * per_period), 100)
    harmonic_bins = CYCLES * np.arange(1, most + 1)
    amplitudes = np.abs(spectrum[harmonic_bins]) * 2 / length
    between = np.setdiff1d(np.arange(1, CYCLES * most), harmonic_bins)
    between = between[:: max(1, -(-len(between) // 256))]
    powers = np.vstack([amplitudes[most // 2 :] ** 2, (np.abs(spectrum[between]) * 2 / length) ** 2])
    noise = np.sqrt(np.median(powers, axis=0) / np.log(2))
    kept = np.flatnonzero((amplitudes > 3.5 * noise).any(axis=1)) + 1
    kept = np.union1d(kept, [1])
    # derivative of the projection: multiply bin kP by i kω, all other bins zero
    omega = 2 * np.pi / (per_period * step)
    derivative = np.zeros_like(spectrum)
    derivative[CYCLES * kept] = spectrum[CYCLES * kept] * (1j * kept * omega)[:, None]
    v = np.fft.irfft(derivative, n=length, axis=0)
    relative = np.diff(v, axis=1, prepend=0.0, append=0.0)  # chain elements, walls at 0
    chain = step * np.sum(relative**2)
    ground = step * np.sum(v**2)
    work = step * np.dot(f[:length], v[:, 0])
    return [chain, ground], work


def pipeline(files):
    stages = {"load": 0.0, "projection and rows": 0.0, "lstsq": 0.0}
    rows, rhs = [], []
    for r, path in enumerate(files, start=1):
        start = time.perf_counter()
        with np.load(path) as z:
            t, x, f = z["t"], z["x"], z["f"]
        stages["load"] += time.perf_counter() - start
        start = time.perf_counter()
        step = (t[-1] - t[0]) / (len(t) - 1)
        per_period = PERIODS[r]
        length = CYCLES * per_period
        for s in range(0, len(t) - length + 1, length):
            row, work = window_row(x[s : s + length], f[s : s + length], per_period, step)
            rows.append(row)
            rhs.append(work)
        stages["projection and rows"] += time.perf_counter() - start
    start = time.perf_counter()
    theta = scipy.linalg.lstsq(np.array(rows), np.array(rhs))[0]
    stages["lstsq"] += time.perf_counter() - start
    return stages, theta


def main():
    data = Path(sys.argv[1])
    files = [data / f"record_{r}.npz" for r in PERIODS]
    if "--load" in sys.argv:
        if "--one" in sys.argv:
            files = files[:1]
        repeats = int(sys.argv[sys.argv.index("--repeats") + 1]) if "--repeats" in sys.argv else 5
        times = []
        for _ in range(repeats):
            start = time.perf_counter()
            arrays = load_all(files)
            times.append(time.perf_counter() - start)
            size = sum(a.nbytes for record in arrays for a in record.values())
            del arrays
        runs = ", ".join(f"{t:.3f}" for t in times)
        print(f"numpy.load of every array: best {min(times):.3f} s of {runs} ({size / 1e9:.2f} GB)")
        return
    start = time.perf_counter()
    stages, theta = pipeline(files)
    total = time.perf_counter() - start
    for name, seconds in stages.items():
        print(f"{name}: {seconds:.3f} s")
    print(f"total: {total:.3f} s")
    print(f"c_chain = {theta[0]:.6f}, c_ground = {theta[1]:.6f}")


if __name__ == "__main__":
    main()
