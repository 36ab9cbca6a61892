"""Shared fixtures: the repository's root and the NumPy four-mass simulator."""

import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "examples" / "python"))

import chain  # noqa: E402  (examples/python/chain.py)


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def four_mass():
    """The paper's four records (amplitudes 0.25..1 at omega = 0.618), simulated in NumPy."""
    amplitudes = [0.25, 0.5, 0.75, 1.0]
    t, x, v, f = chain.simulate(amplitudes, [chain.OMEGA] * 4)
    return t, x, v, f


@pytest.fixture(scope="session")
def model():
    import dampid

    return dampid.Model.from_toml(chain.MODEL)
