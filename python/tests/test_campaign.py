"""The campaign trio (regressor_rows, stack_rows, fit_rows) against identify, and the
Dask example on a LocalCluster and on a real scheduler with two worker processes."""

import os
import pathlib
import pickle
import socket
import subprocess
import sys
import time

import numpy as np
import pytest

import chain
import dampid


def noisy_records(four_mass, level=0.002, seed=3):
    """The four records with displacement noise, displacements only (the default
    pipeline estimates velocities by harmonic projection)."""
    t, x, v, f = four_mass
    rng = np.random.default_rng(seed)
    return [
        dampid.Record(x=x[k] + level * np.abs(x[k]).max() * rng.standard_normal(x[k].shape),
                      t=t, forces=[(f[k], 4)], frequency=chain.OMEGA, label=f"a{k}")
        for k in range(len(x))
    ]


@pytest.mark.parametrize("settings", [
    dict(),  # the default: noise-robust rows, propagated weights, steady-state check
    dict(velocity="central_difference", quadrature="rectangular"),
])
def test_rows_stack_to_identify_bit_for_bit(four_mass, model, settings):
    records = noisy_records(four_mass)
    parts = [dampid.regressor_rows(model, r, record_index=k, **settings) for k, r in enumerate(records)]
    assert parts[0].noise_robust == (settings == {})
    single = dampid.identify(model, records, **settings).to_dict()
    # One list, a stack, and a stack of stacks: the same report as identify, every key.
    assert dampid.fit_rows(model, parts, **settings).to_dict() == single
    assert dampid.fit_rows(model, dampid.stack_rows(parts), **settings).to_dict() == single
    tree = dampid.stack_rows([dampid.stack_rows(parts[:1]), dampid.stack_rows(parts[1:])])
    assert dampid.fit_rows(model, tree, **settings).to_dict() == single
    stacked = dampid.stack_rows(parts)
    assert stacked.a.shape == (len(stacked), 2) and stacked.labels["record"].tolist()[0] == "a0"
    assert stacked.labels["record_index"].tolist() == sorted(stacked.labels["record_index"].tolist())


def test_rows_pickle_bit_for_bit(four_mass, model):
    parts = [dampid.regressor_rows(model, r, record_index=k) for k, r in enumerate(noisy_records(four_mass))]
    back = pickle.loads(pickle.dumps(parts))
    assert [p.to_bytes() for p in back] == [p.to_bytes() for p in parts]
    assert dampid.fit_rows(model, back).to_dict() == dampid.fit_rows(model, parts).to_dict()
    # Protocol 5 with a buffer callback (as Dask sends results): the bytes travel out of
    # band, and are read in place from a buffer.
    buffers = []
    data = pickle.dumps(parts[0], protocol=5, buffer_callback=buffers.append)
    assert len(buffers) == 1 and len(data) < 200
    assert pickle.loads(data, buffers=buffers).to_bytes() == parts[0].to_bytes()
    assert dampid.Rows.from_bytes(memoryview(parts[0].to_bytes())).to_bytes() == parts[0].to_bytes()
    with pytest.raises(dampid.DampidError, match="not dampid rows"):
        dampid.Rows.from_bytes(b"\x00\x01")


def test_rows_of_other_settings_or_models_are_refused(four_mass, model):
    records = noisy_records(four_mass)
    robust = dampid.regressor_rows(model, records[0])
    plain = dampid.regressor_rows(model, records[1], record_index=1, noise="ignore")
    with pytest.raises(dampid.DampidError, match="noise model"):
        dampid.stack_rows([robust, plain])
    other = dampid.Model.from_toml(chain.MODEL.replace('"d"', '"e"'))
    with pytest.raises(dampid.DampidError, match="model that built them"):
        dampid.fit_rows(other, robust)


def test_campaign_on_two_workers_equals_identify(root):
    script = root / "examples" / "python" / "campaign_dask.py"
    run = subprocess.run([sys.executable, str(script), "--records", "100", "--workers", "2"],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "100 records" in run.stdout
    assert "bit for bit: True" in run.stdout


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_campaign_on_a_real_scheduler_and_two_worker_processes(root, tmp_path):
    """`dask scheduler` and two `dask worker` processes on localhost (not a LocalCluster):
    records simulated on the workers, the client holding only the stacked rows. The
    workers run dampid's pool at one thread (as the example advises), the client at its
    default: the result must still be the client's own, bit for bit."""
    bin_dir = pathlib.Path(sys.executable).parent
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    env = {**os.environ, "PYTHONPATH": str(root / "examples" / "python")}
    processes = [subprocess.Popen([str(bin_dir / "dask"), "scheduler", "--host", "127.0.0.1", "--port", str(port),
                                   "--no-dashboard"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)]
    try:
        for _ in range(2):
            processes.append(subprocess.Popen(
                [str(bin_dir / "dask"), "worker", address, "--nthreads", "1", "--no-dashboard",
                 "--local-directory", str(tmp_path)],
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env={**env, "RAYON_NUM_THREADS": "1"}))
        script = root / "examples" / "python" / "campaign_dask.py"
        run = subprocess.run([sys.executable, str(script), "--records", "60", "--per-task", "10",
                              "--scheduler", address, "--wait-workers", "2"],
                             capture_output=True, text=True, timeout=600, env=env)
        assert run.returncode == 0, run.stdout + run.stderr
        assert "60 records" in run.stdout and "2 workers" in run.stdout
        assert "bit for bit: True" in run.stdout
    finally:
        for p in processes:
            p.terminate()
        for p in processes:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()

