"""The 'perimeter' length unit as computed: ds = 1/n on a closed contour, 1/(n-1) on an open curve.

The README's table gives 1/n; an open curve's n points, both ends included,
span n - 1 intervals, so its spacing is L/(n-1) and, in perimeters,
1/(n-1). The values below come from that geometry, not from the code.
"""

import numpy as np

from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.geometry.information import surprisal


def test_perimeter_unit_on_an_open_arc_is_one_over_n_minus_one():
    n = 11
    th = np.linspace(0, np.pi, 2001)
    arc = Contour(np.c_[100 * np.cos(th), 100 * np.sin(th)], closed=False)
    r = surprisal(arc, n=n, length_unit="perimeter")
    assert np.isclose(r.params["ds_in_unit"], 1 / (n - 1))
    # eq. 4 at the inner points of a half circle cut into n - 1 equal arcs: each turns by pi/(n-1)
    inner = np.asarray(r.surprisal)[1:-1]
    ds = 1 / (n - 1)
    assert np.allclose(inner, np.log(4) - ds ** 2 * np.cos(np.pi / (n - 1)), atol=1e-6)
    assert not np.allclose(inner, np.log(4) - (1 / n) ** 2 * np.cos(np.pi / (n - 1)), atol=1e-6)


def test_perimeter_unit_on_a_closed_contour_is_one_over_n():
    n = 12
    th = np.linspace(0, 2 * np.pi, 2400, endpoint=False)
    circle = Contour(np.c_[100 * np.cos(th), 100 * np.sin(th)])
    assert np.isclose(surprisal(circle, n=n, length_unit="perimeter").params["ds_in_unit"], 1 / n)
