"""Free decay from NumPy arrays (`free_decay={...}`) and from a model file
(`identify_file`), against a ringdown simulated here and the shipped hammer test."""

import math
import os

import numpy as np

import dampid

F_HZ, STEP, SAMPLES, SUBSTEPS = 80.0, 1.0 / 12_800.0, 32_768, 4
W = 2 * math.pi * F_HZ
C_TRUE, D_TRUE = 2 * 0.001 * W, 5.0

MODEL = """
dofs = 1

[[terms]]
kind = "viscous"
coefficient = "c"
matrix = "identity"

[[terms]]
kind = "law"
law = "power"
exponent = 1.5
coefficient = "d"
elements = [[1, 0]]
"""


def ringdown(x0=3e-3):
    """Accelerations of x'' + c x' + d|x'|^1.5 sgn x' + w^2 x = 0 from x0 at rest (RK4)."""
    acc = lambda x, v: -C_TRUE * v - D_TRUE * abs(v) ** 1.5 * math.copysign(1.0, v) - W * W * x
    x, v, h = x0, 0.0, STEP / SUBSTEPS
    out = np.empty(SAMPLES)
    for i in range(SAMPLES):
        out[i] = acc(x, v)
        for _ in range(SUBSTEPS):
            k1 = (v, acc(x, v))
            k2 = (v + 0.5 * h * k1[1], acc(x + 0.5 * h * k1[0], v + 0.5 * h * k1[1]))
            k3 = (v + 0.5 * h * k2[1], acc(x + 0.5 * h * k2[0], v + 0.5 * h * k2[1]))
            k4 = (v + h * k3[1], acc(x + h * k3[0], v + h * k3[1]))
            x += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            v += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    return out


def test_a_ringdown_from_numpy_arrays():
    a = ringdown()
    a = a + np.random.default_rng(1).normal(0.0, 0.01 * np.sqrt(np.mean(a * a)), a.size)
    record = dampid.Record(a=a[:, None], step=STEP, forces=[], label="ringdown")
    report = dampid.identify(dampid.Model.from_toml(MODEL), [record], free_decay={"mass": 1.0})
    c, d = report.coefficients["c"], report.coefficients["d"]
    assert abs(c / C_TRUE - 1) < 0.01, c
    assert abs(d / D_TRUE - 1) < 0.01, d
    backbone = report.backbone
    assert len(backbone) > 100
    top = max(backbone, key=lambda p: p["amplitude"])
    assert abs(top["frequency"] / F_HZ - 1) < 0.01
    assert 0.5 < top["measured"] / top["fitted"] < 2.0


def test_several_sensors_through_a_modal_filter():
    """Two accelerometers see the ringdown's mode with shape (1, 0.5) and a second,
    lightly damped mode at 3.1 times its frequency with the orthogonal shape (0.5, -1)
    and a comparable amplitude: `mode_shape` and the record's own POD give the law
    from both channels, as `identify_file` does with `[free_decay] mode_shape`."""
    q = ringdown()
    t = np.arange(SAMPLES) * STEP
    w2 = 3.1 * W
    other = -w2 * w2 * 1e-3 * np.exp(-0.002 * w2 * t) * np.cos(w2 * t)
    a = np.column_stack([q + 0.5 * other, 0.5 * q - other])
    a = a + np.random.default_rng(2).normal(0.0, 0.002 * np.sqrt(np.mean(q * q)), a.shape)
    record = dampid.Record(a=a, step=STEP, forces=[], label="two sensors")
    model = dampid.Model.from_toml(MODEL)
    # The POD coordinate is the projection on the unit-norm shape, |φ| q with
    # |φ|² = 1.25: per unit mass c is unchanged and d|v|^1.5 becomes d |φ|^-0.5.
    for filter, d_true in [
        ({"mode_shape": [1.0, 0.5]}, D_TRUE),
        ({"modal_filter": "pod"}, D_TRUE * 1.25**-0.25),
    ]:
        settings = {"mass": 1.0, "peak_in": [50.0, 150.0], **filter}
        report = dampid.identify(model, [record], free_decay=settings)
        c, d = report.coefficients["c"], report.coefficients["d"]
        assert abs(c / C_TRUE - 1) < 0.01, (filter, c)
        assert abs(d / d_true - 1) < 0.01, (filter, d)
    try:
        dampid.identify(model, [record], free_decay={"mass": 1.0, "mode_shape": [1.0, 0.5, 0.2]})
    except ValueError as e:
        assert "mode_shape" in str(e) and "3" in str(e), str(e)
    else:
        raise AssertionError("a shape of 3 entries for 2 sensors was accepted")


def test_free_decay_settings_are_checked_as_in_a_model_file():
    record = dampid.Record(a=ringdown()[:4096, None], step=STEP, forces=[])
    model = dampid.Model.from_toml(MODEL)
    for kwargs, words in [
        ({"free_decay": {}}, "needs the modal mass"),
        ({"free_decay": {"mass": 1.0}, "cycles": 2}, "does not apply beside [free_decay]"),
        ({"free_decay": {"mass": 1.0, "start": "later"}}, "unknown start"),
    ]:
        try:
            dampid.identify(model, [record], **kwargs)
        except ValueError as e:
            assert words in str(e), str(e)
        else:
            raise AssertionError(f"{kwargs} was accepted")


def test_the_shipped_hammer_test_from_its_file():
    root = os.path.join(os.path.dirname(__file__), "..", "..")
    report = dampid.identify_file(os.path.join(root, "models", "ringdown.toml"))
    assert abs(report.coefficients["c"] / C_TRUE - 1) < 0.01
    assert abs(report.coefficients["d"] / D_TRUE - 1) < 0.01
    value, (low, high) = report.estimated_parameters["d.exponent"]
    assert abs(value - 1.5) < 0.015 and low < 1.5 < high
    assert report.backbone is not None
