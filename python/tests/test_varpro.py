"""identify_file on model files with estimated nonlinear parameters (variable
projection): the estimated parameters with their intervals, the joint intervals of the
coefficients, the CLI's text and JSON, and the HTML page."""

import json
import subprocess

import pytest

import dampid
from test_identify import dampid_binary


def test_estimated_exponent(root):
    # models/four_mass_power.toml: simulated with d.exponent = 1.7, c = 0.15, d = 0.10.
    report = dampid.identify_file(str(root / "models" / "four_mass_power.toml"))
    assert report.is_estimate
    parameters = report.estimated_parameters
    assert list(parameters) == ["d.exponent"]
    value, (low, high) = parameters["d.exponent"]
    assert abs(value - 1.7) < 0.01 * 1.7
    assert low <= value <= high
    joint = report.joint_intervals
    assert set(joint) == {"c", "d"}
    for name, truth in [("c", 0.15), ("d", 0.10)]:
        low, high = joint[name]
        assert low < report.coefficients[name] < high
        assert abs(report.coefficients[name] - truth) < 0.01 * truth
    # The honest intervals are the joint ones.
    assert report.intervals == joint
    assert "d.exponent" in repr(report)


def test_residual_job_agrees_with_the_cli(root):
    model = str(root / "models" / "bolted_joint_stepped_sine_residual.toml")
    report = dampid.identify_file(model)
    parameters = report.estimated_parameters
    assert len(parameters) == 7 and all(name.startswith("r_k (") for name in parameters)
    for value, interval in parameters.values():
        low, high = interval  # joint Wald: no profile for residual receptances
        assert low < value < high
    assert all(interval is not None for interval in report.joint_intervals.values())
    assert "equivalent damping at ω_n" in str(report)
    binary = dampid_binary(root)
    if binary is None:
        pytest.skip("no dampid binary: build it with `cargo build --release`")
    text = subprocess.run([binary, "identify", model], capture_output=True, text=True, check=True).stdout
    assert str(report).strip() == text.strip()
    cli = json.loads(subprocess.run([binary, "identify", model, "--json"], capture_output=True, text=True, check=True).stdout)
    assert cli["report"] == report.to_dict()


def test_html_of_a_residual_job(root, tmp_path):
    report = dampid.identify_file(str(root / "models" / "bolted_joint_stepped_sine_residual.toml"))
    path = tmp_path / "report.html"
    report.write_html(str(path))
    page = path.read_text()
    for needle in ["Estimated nonlinear parameters", "joint (Wald)", "Equivalent damping", "dampid.identify_file("]:
        assert needle in page, needle
    assert "NaN" not in page
