"""The overhead of the Python call over the Rust call, measured in one run.

    cargo build --release --example python_overhead
    python examples/python/overhead.py [--repeats 5] [--dofs 100] [--samples 100000]

Runs the Rust example (examples/python_overhead.rs) and the same identification through
the Python package, best of --repeats each, from the repository's root, and prints both
times, the overhead, and whether the coefficients agree bit for bit:

- four_mass: dampid.identify_file("models/four_mass.toml") against the example's load,
  steady-state check and identify of the same file;
- large: one record of --dofs x --samples built from NumPy arrays (dampid.Record, the
  one copy into dampid's layout included) and dampid.identify, against identify on the
  same record already in dampid's layout in Rust.
"""

import argparse
import pathlib
import subprocess
import sys
import time

import numpy as np

import dampid

ROOT = pathlib.Path(__file__).resolve().parents[2]


def best(repeats, run):
    times, out = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - start)
    return min(times), out


def rust(*args):
    binary = ROOT / "target" / "release" / "examples" / "python_overhead"
    out = subprocess.run([str(binary), *map(str, args)], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    # "rust CASE: SECONDS s, c = C, d = D"
    seconds = float(out.split(": ")[1].split(" s")[0])
    c = float(out.split("c = ")[1].split(",")[0])
    d = float(out.split("d = ")[1].strip())
    return seconds, c, d


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--dofs", type=int, default=100)
    parser.add_argument("--samples", type=int, default=100_000)
    args = parser.parse_args()

    import os
    os.chdir(ROOT)
    seconds, report = best(args.repeats, lambda: dampid.identify_file("models/four_mass.toml"))
    r_seconds, c, d = rust("four_mass", args.repeats)
    same = (report.coefficients["c"], report.coefficients["d"]) == (c, d)
    print(f"four_mass: python {seconds:.4f} s, rust {r_seconds:.4f} s, "
          f"overhead {100 * (seconds / r_seconds - 1):+.1f} %, same coefficients: {same}")

    n, samples, h, omega = args.dofs, args.samples, 0.05, 0.618
    t = np.arange(samples) * h
    j = np.arange(n)
    x = (1.0 + j / n) * np.sin(omega * t[:, None] + 0.01 * j)
    f = np.cos(omega * t)
    model = dampid.Model.from_toml(f"""
dofs = {n}
[[terms]]
kind = "law"
law = "linear"
elements = "each_dof"
coefficient = "c"
[[terms]]
kind = "law"
law = "quadratic"
elements = "each_dof"
coefficient = "d"
""")
    period = 2 * np.pi / omega
    seconds, report = best(args.repeats, lambda: dampid.identify(
        model, [dampid.Record(x=x, step=h, forces=[(f, 1)], period=period, label="large")]))
    record = dampid.Record(x=x, step=h, forces=[(f, 1)], period=period, label="large")
    call_seconds, _ = best(args.repeats, lambda: dampid.identify(model, [record]))
    r_seconds, c, d = rust("large", n, samples, args.repeats)
    # NumPy's sin and Rust's libm may differ in the last bit: the records agree to
    # rounding, not bit for bit, and so do the coefficients.
    diff = max(abs(report.coefficients["c"] / c - 1), abs(report.coefficients["d"] / d - 1))
    print(f"large {n} x {samples}: python {seconds:.4f} s with the Record from NumPy "
          f"({call_seconds:.4f} s identify alone), rust {r_seconds:.4f} s, overhead "
          f"{100 * (seconds / r_seconds - 1):+.1f} % ({100 * (call_seconds / r_seconds - 1):+.1f} % identify alone), "
          f"coefficients agree to {diff:.1e}")


if __name__ == "__main__":
    sys.exit(main())
