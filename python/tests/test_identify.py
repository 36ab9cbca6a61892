"""Identification from NumPy arrays, against simulated truth and against the CLI."""

import json
import os
import shutil
import subprocess

import numpy as np
import pytest

import chain
import dampid


def records_of(four_mass, **kwargs):
    t, x, v, f = four_mass
    return [
        dampid.Record(x=x[k], t=t, forces=[(f[k], 4)], frequency=chain.OMEGA, label=f"a{k}", **kwargs)
        for k in range(x.shape[0])
    ]


def test_four_mass_from_numpy_arrays_within_half_a_percent(four_mass, model):
    # Displacements and forces alone; dampid's defaults (harmonic-projection velocities,
    # trapezoid rule, noise-robust rows). Truth: c = 0.15, d = 0.10 (chain.py).
    report = dampid.identify(model, records_of(four_mass))
    c, d = report.coefficients["c"], report.coefficients["d"]
    assert abs(c - chain.C_TRUE) < 0.005 * chain.C_TRUE, c
    assert abs(d - chain.D_TRUE) < 0.005 * chain.D_TRUE, d
    assert report.status == "Solved"
    assert report.rank == 2
    assert set(report.std_errors) == {"c", "d"}
    low, high = report.intervals["c"]
    assert low < c < high


def test_measured_velocities_and_settings(four_mass, model):
    t, x, v, f = four_mass
    records = [
        dampid.Record(x=x[k], v=v[k], step=t[1] - t[0], forces=[(f[k], 4)], period=2 * np.pi / chain.OMEGA)
        for k in range(4)
    ]
    report = dampid.identify(model, records, velocity="measured", cycles=2, nonnegative=True)
    assert abs(report.coefficients["c"] / chain.C_TRUE - 1) < 0.01
    assert abs(report.coefficients["d"] / chain.D_TRUE - 1) < 0.01
    # Two windows of two periods fit in each 400-sample record (T = 101.7 samples).
    assert len(report.to_dict()["rows"]) == 4 * 1


def test_period_detected_from_the_force(four_mass, model):
    t, x, v, f = four_mass
    record = dampid.Record(x=x[3], t=t, forces=[(f[3], 4)])
    assert abs(record.period - 2 * np.pi / chain.OMEGA) < 0.01 * record.period


def test_report_survives_json(four_mass, model):
    report = dampid.identify(model, records_of(four_mass))
    parsed = json.loads(report.to_json())
    assert parsed == report.to_dict()
    assert [c["name"] for c in parsed["coefficients"]] == ["c", "d"]
    assert parsed["coefficients"][0]["value"] == report.coefficients["c"]
    assert "c" in str(report) and "<table>" in report._repr_html_()
    assert isinstance(report.warnings, list)
    assert report.condition_number > 1


def test_write_html(four_mass, model, tmp_path):
    report = dampid.identify(model, records_of(four_mass))
    path = tmp_path / "report.html"
    report.write_html(str(path))
    page = path.read_text()
    assert page.startswith("<!DOCTYPE html>") and "<svg" in page
    with pytest.raises(dampid.DampidError) as e:
        report.write_html(str(path))
    assert e.value.kind == "output_exists"
    report.write_html(str(path), overwrite=True)


def dampid_binary(root):
    found = shutil.which("dampid")
    if found:
        return found
    for profile in ("release", "debug"):
        candidate = root / "target" / profile / "dampid"
        if candidate.exists():
            return str(candidate)
    return None


def test_identify_file_agrees_with_the_cli_bit_for_bit(root):
    binary = dampid_binary(root)
    if binary is None:
        pytest.skip("no dampid binary: build it with `cargo build --release`")
    cwd = os.getcwd()
    os.chdir(root)
    try:
        report = dampid.identify_file("models/four_mass.toml")
    finally:
        os.chdir(cwd)
    model = str(root / "models" / "four_mass.toml")
    cli = subprocess.run([binary, "identify", model, "--json"], capture_output=True, text=True, check=True)
    # Python's float() of Rust's shortest round-trip digits is the same f64, so dict
    # equality is equality bit for bit.
    assert json.loads(cli.stdout)["report"] == report.to_dict()
    text = subprocess.run([binary, "identify", model], capture_output=True, text=True, check=True).stdout
    assert str(dampid.identify_file(model)).strip() == text.strip()
    assert report.coefficients["c"] == json.loads(cli.stdout)["report"]["coefficients"][0]["value"]


def test_identify_file_relative_paths_resolve_like_the_cli(root, tmp_path):
    os.chdir(root / "models")
    try:
        report = dampid.identify_file("four_mass.toml")
    finally:
        os.chdir(root)
    assert report.coefficients["c"] > 0


def test_model_from_file_and_toml_agree(root):
    from_file = dampid.Model.from_file(str(root / "models" / "four_mass.toml"))
    assert from_file.coefficient_names == ["c", "d"]
    assert dampid.Model.from_toml(chain.MODEL).coefficient_names == ["c", "d"]
