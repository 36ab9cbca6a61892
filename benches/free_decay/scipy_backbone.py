"""The free-decay anchor a user would otherwise pick, timed in-process against the same
file `dampid identify models/ringdown.toml` reads: numpy.load, a zero-phase Butterworth
band-pass (scipy.signal.sosfiltfilt), the analytic signal (scipy.signal.hilbert) for the
envelope and the instantaneous frequency, the acceleration envelope divided by ω² as a
displacement amplitude, and ζ from the slope of log(envelope) per cycle: a FREEVIB-style
backbone ζ(X), f(X), without a damping law, intervals or diagnostics.

    python3 benches/free_decay/scipy_backbone.py [REPEATS]

Prints the best wall time of REPEATS (default 7) and the backbone's ζ at the largest and
smallest amplitude, so the two can be compared.
"""

import sys
import time

import numpy as np
from scipy import signal

FILE = "models/data/ringdown/hammer.npz"
STEP = 7.8125e-5


def backbone():
    data = np.load(FILE)
    a, f = data["acceleration"], data["force"]
    start = np.nonzero(np.abs(f) > 0.05 * np.abs(f).max())[0][-1] + 1
    sos = signal.butter(4, [40.0, 160.0], btype="bandpass", fs=1.0 / STEP, output="sos")
    band = signal.sosfiltfilt(sos, a)[start:]
    analytic = signal.hilbert(band)
    envelope = np.abs(analytic)
    phase = np.unwrap(np.angle(analytic))
    omega = np.gradient(phase, STEP)
    # Smooth over one cycle (160 samples) before differentiating the log envelope.
    kernel = np.ones(160) / 160
    log_env = np.convolve(np.log(envelope), kernel, mode="same")
    omega_s = np.convolve(omega, kernel, mode="same")
    zeta = -np.gradient(log_env, STEP) / omega_s
    amplitude = envelope / omega_s**2
    keep = slice(800, len(band) - 800)
    return amplitude[keep], omega_s[keep] / (2 * np.pi), zeta[keep]


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        x, f, z = backbone()
        best = min(best, time.perf_counter() - t0)
    top, low = np.argmax(x), np.argmin(x)
    print(f"scipy backbone (load, band-pass, Hilbert, decrement): best of {repeats} {best * 1e3:.1f} ms")
    print(f"  ζ at X = {x[top]:.3e}: {z[top]:.4e}; at X = {x[low]:.3e}: {z[low]:.4e}; f {f[top]:.3f} Hz")


if __name__ == "__main__":
    main()
