"""Small records through the map on one core (issue 32): records per second of
`dampid.regressor_rows` called per record, as a campaign's task does, and of `identify` of
the list, with the wall and the CPU time of the whole process (every thread: the work
done, whatever the machine's load) and the CPU time of the calling thread alone (Python
and the library's serial part; the rest runs on rayon's pool).

    RAYON_NUM_THREADS=1 python benches/campaign/map_rate.py [RECORDS] [REPEATS] [campaign|synthetic]

- `campaign`: examples/python/campaign_dask.py's records (the four-mass chain, 4 DOFs ×
  1,000 samples, 100 samples per period, 0.2 % displacement noise), default pipeline.
- `synthetic`: the records of `cargo run --release --example python_overhead -- map
  RECORDS 1000 REPEATS 100` (x_j = (1 + j/4) sin(ω t + 0.01 j), force cos(ω t) on DOF 1,
  linear and quadratic dashpots on every DOF), so the Python map and the library's
  `campaign::rows` are timed on the same records.

Prints the best of REPEATS for each.
"""

import argparse
import math
import pathlib
import sys
import time

import numpy as np

import dampid

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "examples" / "python"))
import campaign_dask as cd  # noqa: E402

# Linear and quadratic dashpots on every DOF, coefficients c and d (python_overhead.rs).
SYNTHETIC_MODEL = "dofs = 4\n" + "".join(
    f'[[terms]]\nkind = "law"\nlaw = "{law}"\nelements = "each_dof"\ncoefficient = "{name}"\n'
    for law, name in (("linear", "c"), ("quadratic", "d")))


def synthetic(n, samples=1000, per_period=100):
    """python_overhead.rs's `small`/`map` records with whole samples per period."""
    out = []
    for k in range(n):
        w = 0.55 + 0.15 * k / n
        h = 2.0 * math.pi / (w * per_period)
        t = np.arange(samples) * h
        x = np.stack([(1.0 + j / 4) * np.sin(w * t + 0.01 * j) for j in range(4)], axis=1)
        out.append(dampid.Record(x=x, t=t, forces=[(np.cos(w * t), 1)], frequency=w, label=f"small {k}"))
    return dampid.Model.from_toml(SYNTHETIC_MODEL), out, {}


def campaign(n):
    args = argparse.Namespace(samples=1000, seed=1, cycles=1, pipeline="default", folder=None)
    records = cd.records_of(cd.simulate_batch(0, n, 1000, 1), args.pipeline)
    return dampid.Model.from_toml(cd.MODEL), records, cd.settings_of(args)


def best(repeats, run):
    """Best wall, process CPU and calling-thread CPU (s) over `repeats` runs."""
    wall = cpu = main = math.inf
    for _ in range(repeats):
        w, c, m = time.perf_counter(), time.process_time(), time.thread_time()
        run()
        wall = min(wall, time.perf_counter() - w)
        cpu = min(cpu, time.process_time() - c)
        main = min(main, time.thread_time() - m)
    return wall, cpu, main


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 500
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    kind = sys.argv[3] if len(sys.argv) > 3 else "campaign"
    model, records, settings = (synthetic if kind == "synthetic" else campaign)(n)

    def rows():
        for k, r in enumerate(records):
            dampid.regressor_rows(model, r, record_index=k, **settings)

    for name, run in [("map", rows), ("identify", lambda: dampid.identify(model, records, **settings))]:
        wall, cpu, main_thread = best(repeats, run)
        print(f"{kind} {name} {n}: {n / wall:.0f} records/s wall, {n / cpu:.0f} records/s of CPU "
              f"({1e6 * cpu / n:.0f} us/record, calling thread {1e6 * main_thread / n:.0f} us/record)")


if __name__ == "__main__":
    main()
