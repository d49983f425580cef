"""Two-point G1 Hermite curves in biangular coordinates: the end conditions,
the defining biangular relation, the circle as the symmetric case, and the
comparison with the clothoid G1 Hermite curve."""

import numpy as np
import pytest

from attneave.stimuli.curves.biangular import biangular_g1, compare_g1_hermite
from attneave.stimuli.errors import InputError

CASES = [((0, 0), 0.9, (3, 1), -0.2), ((10, 5), -1.856, (4, -1), -3.156), ((0, 0), -0.3, (1, 0), 1.2)]


def _angle(v):
    return np.arctan2(v[1], v[0])


@pytest.mark.parametrize("p0, t0, p1, t1", CASES)
def test_end_conditions_and_biangular_relation(p0, t0, p1, t1):
    c = biangular_g1(p0, t0, p1, t1, 2001)
    z = c["x"] + 1j * c["y"]
    a, b = complex(*p0), complex(*p1)
    assert abs(z[0] - a) < 1e-12 and abs(z[-1] - b) < 1e-12
    # G1: the end tangents, from the samples' first and last chords
    h0, h1 = z[1] - z[0], z[-1] - z[-2]
    assert abs(np.angle(h0 * np.exp(-1j * t0))) < 2e-3
    assert abs(np.angle(h1 * np.exp(-1j * t1))) < 2e-3
    # the biangular angles of every inner sample, measured from the positions
    th0 = np.abs(np.angle((z[1:-1] - a) / (b - a)))
    th1 = np.abs(np.angle((z[1:-1] - b) / (a - b)))
    np.testing.assert_allclose(th0 / c["phi0"] + th1 / c["phi1"], 1.0, atol=1e-12)
    # curvature from the positions (second differences in arc length) matches
    s = c["s"]
    k_fd = np.angle((z[2:] - z[1:-1]) / (z[1:-1] - z[:-2])) / (0.5 * (s[2:] - s[:-2]))
    np.testing.assert_allclose(k_fd[5:-5], c["curvature"][1:-1][5:-5], rtol=1e-3, atol=1e-6)
    # the monotone flag says what the samples show
    dk = np.diff(c["curvature"])
    assert c["monotone"] == bool(np.all(dk <= 1e-9) or np.all(dk >= -1e-9))


def test_symmetric_data_is_the_circle_and_the_clothoid():
    c = compare_g1_hermite((0, 0), 0.7, (4, 0), -0.7)
    R = 2 / np.sin(0.7)
    np.testing.assert_allclose(c["biangular"]["curvature"], -1 / R, rtol=1e-12)
    assert c["max_distance"] < 1e-9 and abs(c["length_ratio"] - 1) < 1e-12
    np.testing.assert_allclose(c["biangular"]["length"], 2 * 0.7 * R, rtol=1e-12)


def test_comparison_with_the_clothoid():
    c = compare_g1_hermite((0, 0), 0.9, (3, 1), -0.2)
    cl = c["clothoid"]
    # the clothoid's curvature is linear in arc length, hence monotone
    assert cl["monotone"] and np.allclose(np.diff(cl["curvature"], 2), 0, atol=1e-12)
    # different curves on the same end conditions, close to each other
    assert 1e-4 < c["max_distance"] < 0.05 * np.hypot(3, 1)
    assert 0.95 < c["length_ratio"] < 1.05


@pytest.mark.parametrize("t0, t1", [(0.4, 0.3), (1.6, -1.7), (0.0, -0.5)])
def test_data_that_are_not_c_shaped_are_refused(t0, t1):
    with pytest.raises(InputError, match="C-shaped"):
        biangular_g1((0, 0), t0, (1, 0), t1)
