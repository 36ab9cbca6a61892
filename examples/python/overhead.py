"""The overhead of the Python call over the Rust call, measured in one run.

    cargo build --release --example python_overhead
    python examples/python/overhead.py [--repeats 3] [--small-repeats 50] [--dofs 100] [--samples 100000]

Runs the Rust example (examples/python_overhead.rs) and the same identification through
the Python package, from the repository's root, alternating the two so that a load that
changes over the minutes weighs on both alike, and prints for each the best wall time
and the mean CPU time per call (user + system, all threads: the work done, which a
shared machine's load does not inflate), the overheads, and whether the coefficients
agree:

- four_mass: dampid.identify_file("models/four_mass.toml") against the example's load,
  steady-state check, identification and text report of the same file;
- large: one record of --dofs x --samples and dampid.identify (the steady-state check of
  its windows, then the library's identify), against the same two calls in Rust: on a
  record already built ("identify alone"), and with the record built inside the timing
  (Python: dampid.Record from the C-order NumPy array, the one copy into dampid's
  layout; Rust: Record::new of a copy of the parts).
"""

import argparse
import os
import pathlib
import re
import subprocess
import sys
import time

import numpy as np

import dampid

ROOT = pathlib.Path(__file__).resolve().parents[2]


def timed(repeats, run):
    """Best wall time, mean CPU time per run, and the last result."""
    times, out = [], None
    cpu = time.process_time()
    for _ in range(repeats):
        start = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - start)
    return min(times), (time.process_time() - cpu) / repeats, out


def rust(*args):
    """The example's numbers: [(wall, cpu), ...] in the order printed, and c, d."""
    binary = ROOT / "target" / "release" / "examples" / "python_overhead"
    out = subprocess.run([str(binary), *map(str, args)], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    pairs = [(float(w), float(c)) for w, c in re.findall(r"([0-9.]+) s \(cpu ([0-9.]+) s\)", out)]
    c = float(out.split("c = ")[1].split(",")[0])
    d = float(out.split("d = ")[1].strip())
    return pairs, c, d


def overhead(python, rust):
    return f"{100 * (python / rust - 1):+.1f} %"


def share(call):
    """The binding's own share of one Python call, measured inside it: the call's wall
    time minus the time the library's stages took (Report._library_seconds), relative to
    the latter. The load of the machine stretches both alike."""
    start = time.perf_counter()
    report = call()
    wall = time.perf_counter() - start
    return wall - report._library_seconds, report._library_seconds


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=3, help="rounds of the large case")
    parser.add_argument("--small-repeats", type=int, default=50, help="calls per round of the four-mass case")
    parser.add_argument("--dofs", type=int, default=100)
    parser.add_argument("--samples", type=int, default=100_000)
    args = parser.parse_args()
    os.chdir(ROOT)

    # Four-mass: two rounds each, alternating; best wall, mean CPU over both rounds.
    wall, cpu, r_wall, r_cpu = [], [], [], []
    for _ in range(2):
        w, c_time, report = timed(args.small_repeats, lambda: dampid.identify_file("models/four_mass.toml"))
        wall.append(w)
        cpu.append(c_time)
        [(w, c_time)], c, d = rust("four_mass", args.small_repeats)
        r_wall.append(w)
        r_cpu.append(c_time)
    same = (report.coefficients["c"], report.coefficients["d"]) == (c, d)
    shares = [share(lambda: dampid.identify_file("models/four_mass.toml")) for _ in range(args.small_repeats)]
    outside, inside = np.median([s[0] for s in shares]), np.median([s[1] for s in shares])
    print(f"four_mass: wall python {min(wall):.5f} s, rust {min(r_wall):.5f} s, overhead {overhead(min(wall), min(r_wall))}; "
          f"cpu python {np.mean(cpu):.5f} s, rust {np.mean(r_cpu):.5f} s, overhead {overhead(np.mean(cpu), np.mean(r_cpu))}; "
          f"same coefficients bit for bit: {same}")
    print(f"four_mass: binding's share of the Python call (median of {len(shares)}): {1e3 * outside:.3f} ms outside "
          f"the library's stages, {1e3 * inside:.3f} ms inside, {100 * outside / inside:+.2f} %")

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
    record = dampid.Record(x=x, step=h, forces=[(f, 1)], period=period, label="large")
    rows = {key: [] for key in ("alone", "built", "r_alone", "r_built")}
    shares = {"alone": [], "built": []}
    for _ in range(args.repeats):
        *times, report = timed(1, lambda: dampid.identify(
            model, [dampid.Record(x=x, step=h, forces=[(f, 1)], period=period, label="large")]))
        rows["built"].append(times)
        shares["built"].append((times[0] - report._library_seconds, report._library_seconds))
        *times, alone_report = timed(1, lambda: dampid.identify(model, [record]))
        rows["alone"].append(times)
        shares["alone"].append((times[0] - alone_report._library_seconds, alone_report._library_seconds))
        (alone, built), c, d = rust("large", n, samples, 1)
        rows["r_alone"].append(alone)
        rows["r_built"].append(built)
    best = {key: (min(w for w, _ in v), float(np.mean([c for _, c in v]))) for key, v in rows.items()}
    # NumPy's sin and Rust's libm may differ in the last bit: the records agree to
    # rounding, not bit for bit, and so do the coefficients.
    diff = max(abs(report.coefficients["c"] / c - 1), abs(report.coefficients["d"] / d - 1))
    for name, py, rs in (("identify alone", "alone", "r_alone"), ("with the record built", "built", "r_built")):
        (pw, pc), (rw, rc) = best[py], best[rs]
        print(f"large {n} x {samples}, {name}: wall python {pw:.3f} s, rust {rw:.3f} s, overhead {overhead(pw, rw)}; "
              f"cpu python {pc:.3f} s, rust {rc:.3f} s, overhead {overhead(pc, rc)}")
        outside = [o / i for o, i in shares[py]]
        print(f"large, {name}: binding's share of the Python call {', '.join(f'{100 * r:+.2f} %' for r in outside)} "
              f"(outside the library's stages / inside, each round; the record's copy is outside)")
    print(f"large: coefficients agree to {diff:.1e}")


if __name__ == "__main__":
    sys.exit(main())
