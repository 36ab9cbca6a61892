"""Arrays are read where they are: no copy on the Python side for float64 arrays in C
or Fortran order (nor for strided views); the one copy is into the record's layout.

NumPy reports every array buffer it allocates to tracemalloc, and dampid's Rust side
allocates outside Python's allocator, so the Python-side allocations while a Record is
built are those of any conversion NumPy made: none for float64, one array for float32.
"""

import tracemalloc

import numpy as np

import chain
import dampid

N, DOFS = 200_000, 4  # 6.4 MB of displacements


def python_allocations(make):
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        tracemalloc.reset_peak()
        made = make()
        peak = tracemalloc.get_traced_memory()[1] - before
    finally:
        tracemalloc.stop()
    return made, peak


def motion(order):
    t = np.arange(N) * 0.1
    x = np.empty((N, DOFS), order=order)
    x[:] = np.sin(0.618 * t)[:, None] * np.arange(1, DOFS + 1)
    f = np.cos(0.618 * t)
    return t, x, f


def check_no_copy(order):
    t, x, f = motion(order)
    record, peak = python_allocations(lambda: dampid.Record(x=x, step=0.1, forces=[(f, 4)], frequency=chain.OMEGA))
    assert record.samples == N
    assert peak < x.nbytes / 20, f"{order}-order x: {peak} bytes allocated on the Python side"


def test_c_order_is_not_copied_in_python():
    check_no_copy("C")


def test_fortran_order_is_not_copied_in_python():
    check_no_copy("F")


def test_strided_view_is_not_copied_in_python():
    t, x, f = motion("C")
    wide = np.repeat(x, 2, axis=1)  # columns 0, 2, 4, 6 are x
    view = wide[:, ::2]
    assert not view.flags.c_contiguous and not view.flags.f_contiguous
    record, peak = python_allocations(lambda: dampid.Record(x=view, step=0.1, forces=[(f, 4)], frequency=chain.OMEGA))
    assert peak < x.nbytes / 20


def test_a_conversion_is_the_one_python_copy():
    # The detector works: a float32 array is converted, and tracemalloc sees the
    # float64 copy (8 bytes per value).
    t, x, f = motion("C")
    x32 = x.astype(np.float32)
    _, peak = python_allocations(lambda: dampid.Record(x=x32, step=0.1, forces=[(f, 4)], frequency=chain.OMEGA))
    assert peak >= x.nbytes


def test_orders_give_the_same_report(four_mass, model):
    t, x, v, f = four_mass
    c_records = [dampid.Record(x=np.ascontiguousarray(x[k]), t=t, forces=[(f[k], 4)], frequency=chain.OMEGA) for k in range(4)]
    f_records = [dampid.Record(x=np.asfortranarray(x[k]), t=t, forces=[(f[k], 4)], frequency=chain.OMEGA) for k in range(4)]
    assert dampid.identify(model, c_records).to_dict() == dampid.identify(model, f_records).to_dict()


def test_the_caller_array_is_untouched_and_records_are_reusable(four_mass, model):
    t, x, v, f = four_mass
    before = x.copy()
    records = [dampid.Record(x=x[k], t=t, forces=[(f[k], 4)], frequency=chain.OMEGA) for k in range(4)]
    first = dampid.identify(model, records).to_dict()
    # The same Record objects again, and one listed twice.
    assert dampid.identify(model, records).to_dict() == first
    twice = dampid.identify(model, records + records[:1])
    assert len(twice.to_dict()["rows"]) == 5 * len(first["rows"]) // 4
    assert np.array_equal(x, before)
