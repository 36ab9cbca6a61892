"""Parity with the CLI: the HTML report's steady-state table and provenance block, the
`[non_periodic]` section as a keyword setting, and the accepted-transient warning."""

import csv
import hashlib
import json
import os
import re
import subprocess

import numpy as np
import pytest

import chain
import dampid
from test_identify import dampid_binary, records_of


def headings(page):
    return re.findall(r"<h2>(.*?)</h2>", page)


def test_html_from_arrays_has_the_steady_state_table_and_the_provenance(four_mass, model, tmp_path):
    records = records_of(four_mass)
    report = dampid.identify(model, records, cycles=1, nonnegative=True)
    path = tmp_path / "report.html"
    report.write_html(str(path))
    page = path.read_text()
    # The steady-state table: one row per window, each judged.
    assert "<h2>Steady state</h2>" in page and "Not checked for this report" not in page
    windows = len(report.to_dict()["rows"])
    assert re.search(rf"{windows} of {windows} windows steady", page), page.split("<h2>Steady state</h2>")[1][:300]
    # The provenance: where the records came from, each array's shape and SHA-256 of its
    # float64 bytes in C order (what hashlib gives on NumPy's own buffer), the settings
    # of the call and those in effect, the version, the date.
    assert "<h2>Provenance</h2>" in page and "records from Python arrays" in page
    t, x, v, f = four_mass
    for k in range(4):
        assert hashlib.sha256(x[k].tobytes()).hexdigest() in page
        assert hashlib.sha256(f[k].tobytes()).hexdigest() in page
    assert f"{x.shape[1]} × {x.shape[2]}" in page
    assert f"dampid {dampid.__version__}" in page
    assert "cycles=1, nonnegative=True" in page and "harmonic_projection" in page
    # The settings table marks the keys the call set.
    assert re.search(r"<code>cycles</code></td><td[^>]*><code>1</code></td><td[^>]*>keyword argument</td>", page), page.split("<h2>Provenance</h2>")[1][:3000]
    assert re.search(r"Made 20\d\d-\d\d-\d\d \d\d:\d\d:\d\d UTC", page)
    # The model's text, as written.
    assert "law = &quot;quadratic&quot;" in page or 'law = "quadratic"' in page


def test_html_hash_of_a_fortran_order_array_is_of_its_values_in_c_order(four_mass, model, tmp_path):
    t, x, v, f = four_mass
    fortran = np.asfortranarray(x[3])
    report = dampid.identify(model, [dampid.Record(x=fortran, t=t, forces=[(f[3], 4)], frequency=chain.OMEGA)])
    path = tmp_path / "report.html"
    report.write_html(str(path))
    page = path.read_text()
    assert hashlib.sha256(np.ascontiguousarray(fortran).tobytes()).hexdigest() in page
    assert hashlib.sha256(fortran.tobytes(order="F")).hexdigest() not in page


def test_html_of_identify_file_has_the_cli_sections(root, tmp_path):
    binary = dampid_binary(root)
    if binary is None:
        pytest.skip("no dampid binary: build it with `cargo build --release`")
    model = str(root / "models" / "four_mass.toml")
    report = dampid.identify_file(model)
    path = tmp_path / "python.html"
    report.write_html(str(path))
    page = path.read_text()
    subprocess.run([binary, "identify", model, "--report", str(tmp_path / "cli")], check=True, capture_output=True)
    cli = (tmp_path / "cli" / "report.html").read_text()
    assert headings(page) == headings(cli)
    assert "Provenance" in headings(page) and "Steady state" in headings(page)
    assert f"from the model file <code>{model}</code>" in page
    assert "dampid.identify_file(" in page


def test_html_of_fit_rows_names_the_rows(four_mass, model, tmp_path):
    records = records_of(four_mass)
    rows = dampid.regressor_rows(model, records[0], noise="ignore")
    report = dampid.fit_rows(model, rows, noise="ignore")
    a, b = rows.a, rows.b
    path = tmp_path / "rows.html"
    report.write_html(str(path))
    page = path.read_text()
    assert hashlib.sha256(np.ascontiguousarray(a).tobytes()).hexdigest() in page
    assert hashlib.sha256(b.tobytes()).hexdigest() in page


def drive_record(root):
    with open(root / "models" / "data" / "drive" / "drive.csv") as file:
        rows = list(csv.reader(file))
    header, values = rows[0], np.array([[float(v) for v in row] for row in rows[1:]])
    column = {name: values[:, k] for k, name in enumerate(header)}
    return dampid.Record(
        x=column["x"][:, None], t=column["t"], forces=[(column["force"], 1)], label="closed-loop moves"
    )


def test_non_periodic_keywords_match_the_cli_bit_for_bit(root):
    binary = dampid_binary(root)
    if binary is None:
        pytest.skip("no dampid binary: build it with `cargo build --release`")
    path = root / "models" / "drive_nonperiodic.toml"
    model = dampid.Model.from_file(str(path))
    record = drive_record(root)
    report = dampid.identify(
        model,
        [record],
        velocity="central_difference",
        nonnegative=True,
        non_periodic={"window": 0.25, "mass": "each_dof", "stiffness": "none", "offsets": [1]},
    )
    cli = subprocess.run([binary, "identify", str(path), "--json"], capture_output=True, text=True, check=True)
    # Python's float() of Rust's shortest round-trip digits is the same f64, so dict
    # equality is equality bit for bit.
    assert json.loads(cli.stdout)["report"] == report.to_dict()
    assert set(report.coefficients) >= {"viscous", "coulomb"}
    # The defaults of the mode are the model file's: central differences without asking.
    again = dampid.identify(model, [record], nonnegative=True, non_periodic={"window": 0.25, "offsets": [1]})
    assert again.to_dict() == report.to_dict()


def test_non_periodic_keyword_errors(root):
    model = dampid.Model.from_file(str(root / "models" / "drive_nonperiodic.toml"))
    record = drive_record(root)

    def raises(kind, words, **settings):
        with pytest.raises(dampid.DampidError) as e:
            dampid.identify(model, [record], **settings)
        assert e.value.kind == kind, (e.value.kind, str(e.value))
        for word in words:
            assert word in str(e.value), str(e.value)

    raises("invalid_choice", ["cycles", "does not apply beside [non_periodic]"], cycles=2, non_periodic={"window": 0.25})
    raises("invalid_choice", ["[non_periodic]", "windw"], non_periodic={"windw": 0.25})
    raises("invalid_choice", ["[non_periodic]", "window"], non_periodic={"offsets": [1]})
    raises("dof_out_of_range", ["offset"], non_periodic={"window": 0.25, "offsets": [2]})
    raises("unknown_name", ["lumped"], non_periodic={"window": 0.25, "mass": "lumped"})
    raises("argument", ["non_periodic"], non_periodic=0.25)
    # An unknown keyword lists non_periodic among the known ones.
    with pytest.raises(dampid.DampidError) as e:
        dampid.identify(model, [record], non_periodc={"window": 0.25})
    assert "non_periodic" in str(e.value) and "cycles" in str(e.value)
    # The record has no period (its force is not periodic): only windows of whole
    # periods need one, and they say so.
    with pytest.raises(dampid.DampidError) as e:
        dampid.identify(model, [record])
    with pytest.raises(dampid.DampidError):
        record.period
    assert "period" in str(e.value)


def test_non_periodic_velocity_records_need_a_high_pass(root):
    model = dampid.Model.from_file(str(root / "models" / "drive_nonperiodic.toml"))
    record = drive_record(root)
    t = np.arange(record.samples) * record.step
    v = np.cos(2 * t)[:, None] + 0.3 * np.sin(5.3 * t)[:, None]
    force = np.cos(2 * t) + np.sin(0.7 * t)
    measured = dampid.Record(v=v, t=t, forces=[(force, 1)], label="velocity")
    with pytest.raises(dampid.DampidError) as e:
        dampid.identify(model, [measured], non_periodic={"window": 0.25})
    assert e.value.kind == "missing" and "high_pass" in str(e.value)
    report = dampid.identify(model, [measured], non_periodic={"window": 0.25, "high_pass": 0.05})
    assert report.status


def test_accepted_transients_are_warned_about_as_in_the_cli(model):
    # The first period of a record that starts at rest is not steady: accepted, the
    # report says so, as the CLI's does.
    t, x, v, f = chain.simulate([1.0], [chain.OMEGA], transient=0, recorded=600)
    record = dampid.Record(x=x[0], t=t, forces=[(f[0], 4)], frequency=chain.OMEGA)
    with pytest.raises(dampid.DampidError) as e:
        dampid.identify(model, [record])
    assert e.value.kind == "not_steady"
    report = dampid.identify(model, [record], accept_transient=True)
    assert any("transient" in w or "steady" in w for w in report.warnings), report.warnings
