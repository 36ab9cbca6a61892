"""Every class of bad input raises dampid.DampidError (a ValueError) with the CLI's
message; none crashes the interpreter."""

import numpy as np
import pytest

import chain
import dampid


@pytest.fixture
def arrays(four_mass):
    t, x, v, f = four_mass
    return t, x[3].copy(), f[3].copy()


def raises(kind, call, *words):
    with pytest.raises(dampid.DampidError) as e:
        call()
    assert isinstance(e.value, ValueError)
    assert e.value.kind == kind, (e.value.kind, str(e.value))
    for word in words:
        assert word in str(e.value), str(e.value)
    return str(e.value)


def test_nan_in_displacements(arrays):
    t, x, f = arrays
    x[7, 2] = np.nan
    raises("non_finite", lambda: dampid.Record(x=x, t=t, forces=[(f, 4)], frequency=chain.OMEGA), "NaN", "row 7", "column 2")


def test_nan_in_a_force(arrays):
    t, x, f = arrays
    f[3] = np.inf
    raises("non_finite", lambda: dampid.Record(x=x, t=t, forces=[(f, 4)], frequency=chain.OMEGA), "force")


def test_wrong_shapes(arrays):
    t, x, f = arrays
    raises("argument", lambda: dampid.Record(x=x[:, 0], t=t, forces=[(f, 4)]), "x must be 2-D", "(400)")
    raises("argument", lambda: dampid.Record(x=x, t=t, forces=[(f[:, None], 4)]), "force 1 must be 1-D")


def test_inconsistent_lengths(arrays):
    t, x, f = arrays
    raises("dimension_mismatch", lambda: dampid.Record(x=x, t=t, forces=[(f[:-1], 4)], frequency=chain.OMEGA), "force 1", "400", "399")
    raises("dimension_mismatch", lambda: dampid.Record(x=x, t=t[:-2], forces=[(f, 4)], frequency=chain.OMEGA), "t", "398")
    v = np.zeros((399, 4))
    raises("dimension_mismatch", lambda: dampid.Record(x=x, v=v, t=t, forces=[(f, 4)], frequency=chain.OMEGA), "velocities")


def test_force_dof_out_of_range_counts_from_one(arrays):
    t, x, f = arrays
    message = raises("dof_out_of_range", lambda: dampid.Record(x=x, t=t, forces=[(f, 5)], frequency=chain.OMEGA), "DOF 5", "1..4")
    assert "force channel 1" in message
    raises("dof_out_of_range", lambda: dampid.Record(x=x, t=t, forces=[(f, 0)], frequency=chain.OMEGA), "DOF 0", "1..4")


def test_time_base(arrays):
    t, x, f = arrays
    raises("invalid_choice", lambda: dampid.Record(x=x, forces=[(f, 4)], frequency=chain.OMEGA), "neither t nor step")
    raises("invalid_choice", lambda: dampid.Record(x=x, t=t, step=0.1, forces=[(f, 4)], frequency=chain.OMEGA), "both")
    jittered = t.copy()
    jittered[10] += 0.03
    raises("time_jitter", lambda: dampid.Record(x=x, t=jittered, forces=[(f, 4)], frequency=chain.OMEGA))
    raises("invalid_parameter", lambda: dampid.Record(x=x, t=t, forces=[(f, 4)], frequency=chain.OMEGA, period=10.0), "at most one")


def test_empty_record_list(model):
    raises("empty", lambda: dampid.identify(model, []), "records")


def test_not_a_record(model):
    raises("argument", lambda: dampid.identify(model, [np.zeros(3)]), "records[0]", "ndarray")


def test_unknown_settings_keyword_lists_the_known_ones(arrays, model):
    t, x, f = arrays
    record = dampid.Record(x=x, t=t, forces=[(f, 4)], frequency=chain.OMEGA)
    message = raises("unknown_name", lambda: dampid.identify(model, [record], cycle=2), "'cycle'")
    assert "cycles" in message and "accept_transient" in message and "quadrature" in message
    raises("invalid_choice", lambda: dampid.identify(model, [record], quadrature="simpson"), "quadrature", "simpson")
    raises("invalid_choice", lambda: dampid.identify(model, [record], cycles="two"), "cycles")


def test_non_float64_arrays_are_converted_or_refused(arrays, model):
    t, x, f = arrays
    as_float32 = dampid.Record(x=x.astype(np.float32), t=t, forces=[(f.astype(np.float32), 4)], frequency=chain.OMEGA)
    assert as_float32.samples == 400
    as_int = dampid.Record(x=(1000 * x).astype(np.int64), t=t, forces=[(f, 4)], frequency=chain.OMEGA)
    assert as_int.dofs == 4
    raises("argument", lambda: dampid.Record(x=x.astype(np.complex128), t=t, forces=[(f, 4)]), "x has dtype complex128", "float64")
    raises("argument", lambda: dampid.Record(x=x.astype(object), t=t, forces=[(f, 4)]), "x has dtype object")
    raises("argument", lambda: dampid.Record(x=np.array([["a", "b"]]), t=t, forces=[(f, 4)]), "dtype <U1")


def test_missing_motion(arrays):
    t, x, f = arrays
    raises("missing", lambda: dampid.Record(t=t, forces=[(f, 4)]), "motion")
    raises("invalid_choice", lambda: dampid.Record(x=x, a=x, t=t, forces=[(f, 4)]), "motion")


def test_model_errors(root, tmp_path):
    raises("model_file", lambda: dampid.Model.from_toml("dofs = 4\n[[terms]]\nkind = 'nope'\n"), "<model text>:")
    raises("model_file", lambda: dampid.Model.from_file(str(tmp_path / "absent.toml")), "absent.toml")


def test_a_transient_is_refused_unless_accepted(four_mass, model):
    # The first recorded sample right after the start: the motion has not settled.
    t, x, v, f = chain.simulate([1.0], [chain.OMEGA], transient=0, recorded=400)
    record = dampid.Record(x=x[0], t=t, forces=[(f[0], 4)], frequency=chain.OMEGA)
    message = raises("not_steady", lambda: dampid.identify(model, [record, record]), "accept_transient=True")
    assert "steady" in message
    dampid.identify(model, [record, record], accept_transient=True)


def test_identify_file_errors(tmp_path):
    raises("model_file", lambda: dampid.identify_file(str(tmp_path / "absent.toml")), "absent.toml")
