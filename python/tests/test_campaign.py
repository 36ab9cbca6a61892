"""The Dask campaign example on a 2-worker LocalCluster over 200 simulated records."""

import subprocess
import sys


def test_campaign_on_two_workers_equals_identify(root):
    script = root / "examples" / "python" / "campaign_dask.py"
    run = subprocess.run([sys.executable, str(script), "--records", "200", "--workers", "2"],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "200 records" in run.stdout
    assert "bit for bit: True" in run.stdout


def test_rows_refuse_the_noise_robust_default(four_mass, model):
    import pytest

    import chain
    import dampid

    t, x, v, f = four_mass
    record = dampid.Record(x=x[0], t=t, forces=[(f[0], 4)], frequency=chain.OMEGA)
    with pytest.raises(dampid.DampidError, match="noise"):
        dampid.regressor_rows(model, record)


def test_rows_stack_to_identify_bit_for_bit(four_mass, model):
    import numpy as np

    import chain
    import dampid

    t, x, v, f = four_mass
    settings = dict(velocity="central_difference", quadrature="rectangular")
    records = [dampid.Record(x=x[k], t=t, forces=[(f[k], 4)], frequency=chain.OMEGA, label=f"a{k}") for k in range(4)]
    parts = [dampid.regressor_rows(model, r, record_index=k, **settings) for k, r in enumerate(records)]
    a = np.vstack([p[0] for p in parts])
    b = np.concatenate([p[1] for p in parts])
    labels = np.concatenate([p[2] for p in parts])
    assert a.shape == (len(b), 2) and labels["record"].tolist()[0] == "a0"
    fitted = dampid.fit_rows(model, a, b, labels=labels, **settings).to_dict()
    single = dampid.identify(model, records, **settings).to_dict()
    # identify adds the velocity-noise assessment of central differences, which reads
    # the records; everything else is the same bits.
    single.pop("velocity_noise", None)
    fitted.pop("velocity_noise", None)
    assert fitted == single
