"""Peaks and prominences in numpy against scipy.signal's definitions."""

import numpy as np
import pytest
import scipy.signal

from attneave.stimuli.geometry.peaks import circular_peaks_and_prominences, peaks_and_prominences


def signals(seed, count=300):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        n = int(rng.integers(3, 60))
        kind = rng.integers(3)
        if kind == 0:
            yield rng.normal(size=n)
        elif kind == 1:  # plateaus and ties: few distinct levels
            yield rng.integers(0, 4, size=n).astype(float)
        else:  # smooth with noise
            t = np.linspace(0, 4 * np.pi, n)
            yield np.sin(t * rng.uniform(0.5, 3)) + 0.1 * rng.normal(size=n)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_linear_matches_scipy(seed):
    for x in signals(seed):
        idx, props = scipy.signal.find_peaks(x, prominence=0.0)
        p, prom = peaks_and_prominences(x)
        assert p.tolist() == idx.tolist(), x
        np.testing.assert_allclose(prom, props["prominences"], rtol=0, atol=1e-12)


@pytest.mark.parametrize("seed", [3, 4])
def test_circular_matches_scipy_on_three_periods(seed):
    for x in signals(seed):
        n = len(x)
        if np.all(x == x[0]):
            continue
        idx, props = scipy.signal.find_peaks(np.tile(x, 3), prominence=0.0)
        keep = (idx >= n) & (idx < 2 * n)
        p, prom = circular_peaks_and_prominences(x)
        assert p.tolist() == (idx[keep] - n).tolist(), x
        np.testing.assert_allclose(prom, props["prominences"][keep], rtol=0, atol=1e-12)


def test_large_signal_matches_scipy():
    x = np.random.default_rng(9).normal(size=200_000).round(1)  # many plateaus
    idx, props = scipy.signal.find_peaks(x, prominence=0.0)
    p, prom = peaks_and_prominences(x)
    assert np.array_equal(p, idx)
    np.testing.assert_allclose(prom, props["prominences"], atol=1e-12)
