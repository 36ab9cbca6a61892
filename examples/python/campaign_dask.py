"""A campaign of many records on Dask: map records to regressor rows, fit once.

A regressor row depends on one window of one record, and the fit on the stacked rows
only. So each Dask task reads one record file (lazily: the file is opened on the worker
that needs it, never in the client), returns its rows with `dampid.regressor_rows`, and
the client stacks them in record order and fits them with `dampid.fit_rows`. The script
then checks that the result equals single-process `dampid.identify` bit for bit.

    python examples/python/campaign_dask.py --records 200 --workers 2
    python examples/python/campaign_dask.py --folder DATA --scheduler tcp://host:8786

With --scheduler the same code runs on a real cluster (the workers need dampid and
NumPy installed and the record folder on a shared file system); without it, a
LocalCluster of --workers processes runs here. Without --folder, the records are
simulated first (the paper's four-mass chain at 200 amplitudes and frequencies).
"""

import argparse
import pathlib
import sys
import tempfile
import time

import numpy as np

import dampid

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import chain  # noqa: E402  (the chain's simulator and model, beside this file)

# The chain's model: C = c K and d v|v| on every mass.
MODEL = chain.MODEL

# Plain rows (measured velocities): a row is then a function of its window alone. The
# noise-robust rows share a noise model across rows, which (A, b) cannot carry, so
# regressor_rows refuses them.
SETTINGS = dict(velocity="measured", quadrature="trapezoid", cycles=1)


def simulate_campaign(folder, count, seed=1):
    """`count` steady records of the chain, one .npz file each (x, v, t, f, omega)."""
    rng = np.random.default_rng(seed)
    amplitudes = rng.uniform(0.25, 1.0, count)
    omegas = rng.uniform(0.55, 0.7, count)
    t, x, v, f = chain.simulate(amplitudes, omegas, transient=3000, recorded=400)
    paths = []
    for k in range(count):
        path = pathlib.Path(folder) / f"record{k:04d}.npz"
        np.savez(path, x=x[k], v=v[k], t=t, f=f[k], omega=omegas[k])
        paths.append(path)
    return paths


def load_record(path):
    """One record from its file (runs on the worker)."""
    data = np.load(path)
    return dampid.Record(
        x=data["x"], v=data["v"], t=data["t"], forces=[(data["f"], 4)],
        frequency=float(data["omega"]), label=pathlib.Path(path).stem,
    )


def rows_of(path, index):
    """The task: one record file → its rows (A, b, labels)."""
    model = dampid.Model.from_toml(MODEL)
    return dampid.regressor_rows(model, load_record(path), record_index=index, **SETTINGS)


def fit_campaign(client, paths):
    """Map on the cluster, stack in record order, fit once."""
    futures = client.map(rows_of, [str(p) for p in paths], range(len(paths)))
    parts = client.gather(futures)
    a = np.vstack([p[0] for p in parts])
    b = np.concatenate([p[1] for p in parts])
    labels = np.concatenate([p[2] for p in parts])
    return dampid.fit_rows(dampid.Model.from_toml(MODEL), a, b, labels=labels, **SETTINGS)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=200)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--folder", help="a folder of record*.npz files (default: simulate)")
    parser.add_argument("--scheduler", help="address of a running Dask scheduler")
    args = parser.parse_args(argv)

    from dask.distributed import Client, LocalCluster

    with tempfile.TemporaryDirectory() as scratch:
        if args.folder:
            paths = sorted(pathlib.Path(args.folder).glob("record*.npz"))
        else:
            paths = simulate_campaign(scratch, args.records)
        if args.scheduler:
            client = Client(args.scheduler)
        else:
            cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
            client = Client(cluster)
        with client:
            started = time.perf_counter()
            distributed = fit_campaign(client, paths)
            map_seconds = time.perf_counter() - started

        # The same records in one process: the library's own identify.
        started = time.perf_counter()
        records = [load_record(p) for p in paths]
        single = dampid.identify(dampid.Model.from_toml(MODEL), records, **SETTINGS)
        single_seconds = time.perf_counter() - started

        # One core's throughput of the map, and the memory one record holds.
        model = dampid.Model.from_toml(MODEL)
        started = time.perf_counter()
        rows = sum(dampid.regressor_rows(model, r, **SETTINGS)[1].size for r in records)
        rows_seconds = time.perf_counter() - started
        data = np.load(paths[0])
        arrays = sum(data[k].nbytes for k in ("x", "v", "f"))

    same = distributed.to_dict() == single.to_dict()
    print(f"{len(paths)} records, {rows} rows; c = {single.coefficients['c']!r}, d = {single.coefficients['d']!r}")
    print(f"Dask map + fit: {map_seconds:.2f} s on {args.workers if not args.scheduler else 'the cluster'} workers; "
          f"single-process identify: {single_seconds:.2f} s")
    print(f"one core: {rows / rows_seconds:.0f} rows/s ({len(records) / rows_seconds:.0f} records/s); "
          f"one record: {arrays} bytes of arrays (x, v, force) + the same again in dampid's layout")
    print("distributed == single-process, bit for bit:", same)
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
