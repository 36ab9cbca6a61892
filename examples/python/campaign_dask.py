"""A campaign of many records on Dask: map records to rows, stack them on the workers, fit once.

A regressor row depends on one window of one record, and the fit on the stacked rows
only. So each Dask task gets a batch of records where they are (simulated on the worker,
or read there from a folder of .npz files: never in the client), turns each into its
rows with `dampid.regressor_rows` (the default noise-robust pipeline: the rows carry
their noise model, gross work and steady-state check), and joins them with
`dampid.stack_rows`; partial stacks are joined pairwise on the workers, so the client
receives one `Rows` and fits it with `dampid.fit_rows`. The script then checks the
result against single-process `dampid.identify` of the same records, bit for bit.

    python examples/python/campaign_dask.py --records 200 --workers 2
    python examples/python/campaign_dask.py --records 10000 --no-check --scheduler tcp://host:8786
    python examples/python/campaign_dask.py --folder DATA --scheduler tcp://host:8786

Without --scheduler a LocalCluster of --workers processes runs here; with it, the same
code runs on a real cluster (the workers need dampid and NumPy installed, this folder on
their PYTHONPATH for chain.py, and for --folder the files on a shared file system).
Each worker process runs one task at a time on one core, so it should run dampid's thread
pool at one thread too (RAYON_NUM_THREADS=1, as the LocalCluster here does; start `dask
worker` with it set): with the default pool of one thread per core, the pool's idle
threads spin beside the other workers. Results do not depend on the thread count.

The records are the paper's four-mass chain (C = c K, d v|v| on every mass, a force on
mass 4) at one frequency and amplitudes drawn per record, simulated to steady state in
NumPy (examples/python/chain.py), one period repeated to --samples samples, with 0.2 %
displacement noise: record k is a function of (--seed, k) alone.
"""

import argparse
import pathlib
import resource
import sys
import time

import numpy as np

import dampid

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import chain  # noqa: E402  (the chain's simulator and model, beside this file)

# The chain's model: C = c K and d v|v| on every mass.
MODEL = chain.MODEL

# Samples per period of the simulated records (whole samples per period).
PER_PERIOD = 100

PIPELINES = {
    # The default: displacements only, velocities by harmonic projection, noise-robust
    # rows weighted by their propagated noise, the steady-state check.
    "default": dict(),
    # Measured velocities (plain rows), as a campaign with velocity sensors would run.
    "measured": dict(velocity="measured", quadrature="trapezoid"),
}


def simulate_batch(first, count, samples, seed):
    """Records first..first+count: (label, x, v, t, f) each, from (seed, k) alone."""
    amplitudes = [np.random.default_rng([seed, k]).uniform(0.25, 1.0) for k in range(first, first + count)]
    h = 2.0 * np.pi / (chain.OMEGA * PER_PERIOD)
    t, x, v, f = chain.simulate(amplitudes, [chain.OMEGA] * count, h=h, transient=60 * PER_PERIOD,
                                recorded=PER_PERIOD)
    repeats = -(-samples // PER_PERIOD)
    t = t[0] + h * np.arange(samples)
    out = []
    for j, k in enumerate(range(first, first + count)):
        noise = np.random.default_rng([seed, k, 1])
        xk = np.tile(x[j], (repeats, 1))[:samples]
        xk = xk + 0.002 * np.abs(xk).max(axis=0) * noise.standard_normal(xk.shape)
        vk = np.tile(v[j], (repeats, 1))[:samples]
        fk = np.tile(f[j], repeats)[:samples]
        out.append((f"record{k:05d}", xk, vk, t, fk))
    return out


def load_batch(paths):
    """Records from .npz files (x, v, t, f, omega), read where this runs."""
    out = []
    for path in paths:
        data = np.load(path)
        out.append((pathlib.Path(path).stem, data["x"], data["v"], data["t"], data["f"]))
    return out


def records_of(batch, pipeline):
    """dampid records of a batch; the default pipeline reads displacements only."""
    return [
        dampid.Record(x=x, v=v if pipeline == "measured" else None, t=t, forces=[(f, 4)],
                      frequency=chain.OMEGA, label=label)
        for label, x, v, t, f in batch
    ]


def batch_of(source, first, count, args):
    if args.folder:
        return load_batch(source[first:first + count])
    return simulate_batch(first, count, args.samples, args.seed)


def settings_of(args):
    """The identification settings: the pipeline's, with windows of --cycles periods."""
    return dict(PIPELINES[args.pipeline], cycles=args.cycles)


def rows_of(source, first, count, args):
    """The task: a batch of records → their rows, stacked (runs on a worker)."""
    model = dampid.Model.from_toml(MODEL)
    settings = settings_of(args)
    parts = [dampid.regressor_rows(model, r, record_index=first + j, **settings)
             for j, r in enumerate(records_of(batch_of(source, first, count, args), args.pipeline))]
    return dampid.stack_rows(parts)


def fit_campaign(client, source, args):
    """Map batches on the cluster, stack pairwise on the workers in record order, fit
    the one stack in the client."""
    starts = list(range(0, args.records, args.per_task))
    counts = [min(args.per_task, args.records - s) for s in starts]
    level = client.map(rows_of, [source] * len(starts), starts, counts, [args] * len(starts))
    while len(level) > 1:
        pairs = [level[i:i + 2] for i in range(0, len(level), 2)]
        level = [client.submit(dampid.stack_rows, pair) if len(pair) == 2 else pair[0] for pair in pairs]
    stacked = level[0].result()
    return stacked, dampid.fit_rows(dampid.Model.from_toml(MODEL), stacked, **settings_of(args))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=200)
    parser.add_argument("--samples", type=int, default=400, help="samples per record (default 400)")
    parser.add_argument("--per-task", type=int, default=25, help="records per Dask task (default 25)")
    parser.add_argument("--cycles", type=int, default=1, help="periods per window (default 1)")
    parser.add_argument("--pipeline", choices=sorted(PIPELINES), default="default")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int, default=2, help="LocalCluster processes (without --scheduler)")
    parser.add_argument("--folder", help="a folder of record*.npz files (default: simulate on the workers)")
    parser.add_argument("--scheduler", help="address of a running Dask scheduler")
    parser.add_argument("--wait-workers", type=int, default=0, help="wait for this many workers first")
    parser.add_argument("--no-check", action="store_true", help="skip the single-process identify")
    args = parser.parse_args(argv)

    from dask.distributed import Client, LocalCluster

    source = None
    if args.folder:
        source = [str(p) for p in sorted(pathlib.Path(args.folder).glob("record*.npz"))]
        args.records = len(source)
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                               dashboard_address=None, env={"RAYON_NUM_THREADS": "1"})
        client = Client(cluster)
    with client:
        if args.wait_workers:
            client.wait_for_workers(args.wait_workers, timeout=120)
        workers = len(client.scheduler_info()["workers"])
        started = time.perf_counter()
        stacked, distributed = fit_campaign(client, source, args)
        map_seconds = time.perf_counter() - started
    client_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

    coefficients = distributed.coefficients
    print(f"{args.records} records ({args.pipeline} pipeline), {len(stacked)} rows; "
          f"c = {coefficients['c']!r}, d = {coefficients['d']!r} (truth {chain.C_TRUE}, {chain.D_TRUE})")
    print(f"Dask map + stack + fit: {map_seconds:.2f} s on {workers} workers "
          f"({args.records / map_seconds:.0f} records/s); client peak memory {client_mb:.0f} MB")
    if args.no_check:
        return 0

    # The same records in one process: the library's own identify.
    started = time.perf_counter()
    records = []
    for first in range(0, args.records, args.per_task):
        count = min(args.per_task, args.records - first)
        records += records_of(batch_of(source, first, count, args), args.pipeline)
    generated = time.perf_counter() - started
    model = dampid.Model.from_toml(MODEL)
    started = time.perf_counter()
    single = dampid.identify(model, records, **settings_of(args))
    single_seconds = time.perf_counter() - started

    # One core's throughput of the map (rows of each record, in this process).
    started = time.perf_counter()
    for k, r in enumerate(records):
        dampid.regressor_rows(model, r, record_index=k, **settings_of(args))
    rows_seconds = time.perf_counter() - started

    same = distributed.to_dict() == single.to_dict()
    print(f"single-process identify: {single_seconds:.2f} s ({args.records / single_seconds:.0f} records/s; "
          f"records made in {generated:.2f} s)")
    print(f"one core: {len(stacked) / rows_seconds:.0f} rows/s ({args.records / rows_seconds:.0f} records/s) "
          f"through regressor_rows")
    print("distributed == single-process, bit for bit:", same)
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
