"""Python-API robustness of attneave.stimuli.geometry: bad input gets an InputError naming the argument,
never an obscure numpy error or a silently wrong (NaN, truncated, flag-inverted) result; a circle
has no surprisal peaks."""

import numpy as np
import pytest

from attneave.stimuli import (
    Contour,
    find_peaks,
    surprisal,
    surprisal_paper,
    surprisal_vonmises,
    turning_angles,
)
from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry import gaussian_curvature, shoelace, surprisal_from_points

SQ = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)


def _ring(a, b, m=4000):
    th = np.linspace(0, 2 * np.pi, m, endpoint=False)
    return np.c_[a * np.cos(th), b * np.sin(th)]


# ------------------------------------------------------------------ fault 1: circles are flat

@pytest.mark.parametrize("m", [1000, 4000])
@pytest.mark.parametrize("radius", [1.0, 50.0, 5000.0])
@pytest.mark.parametrize("n", [16, 64, 100, 256, 250])
@pytest.mark.parametrize("unit", ["sample", "perimeter", "px"])
def test_circle_has_no_surprisal_peaks(m, radius, n, unit):
    for model in ("paper", "vonmises"):
        r = surprisal(_ring(radius, radius, m), n=n, model=model, length_unit=unit)
        assert len(r.peaks) == 0, (m, radius, n, unit, model)


@pytest.mark.parametrize("ratio", [2.0, 1.2, 1.05])
@pytest.mark.parametrize("n", [16, 64, 100])
def test_ellipse_keeps_its_peaks_at_the_ends_of_its_axes(ratio, n):
    r = surprisal(_ring(50 * ratio, 50), n=n)
    assert len(r.peaks) in (2, 4)
    # the two highest at the ends of the major axis (x = +-a)
    ends = np.sort(np.abs(r.contour.points[r.peaks[:2], 0]))
    np.testing.assert_allclose(ends, 50 * ratio, rtol=1e-3)


def test_find_peaks_roundoff_and_floor():
    assert find_peaks(0.4 + 1e-14 * np.sin(np.arange(64.0)))[0].size == 0
    u = np.cos(np.arange(64) * 2 * np.pi / 16)
    assert find_peaks(u)[0].size == 4
    assert find_peaks(u, floor=3.0)[0].size == 0


# ------------------------------------------------------------------ fault 2: zero-area closed contours

@pytest.mark.parametrize("pts", [
    [[0, 0], [1, 0], [2, 0], [3, 0]],
    [[0, 0], [10, 0], [20, 0]],
    [[0, 0], [2, 0], [2, 1], [2, 0]],  # a spike retracing itself
    (np.array([[0, 0], [1, 0], [2, 0]]) + 1e6).tolist(),  # collinear far from the origin
])
def test_closed_contour_without_area_refused(pts):
    with pytest.raises(InputError, match="encloses no area"):
        Contour(pts)
    Contour(pts, closed=False)  # an open line is fine


def test_zero_area_refused_through_curvature_paths():
    from attneave.stimuli.extraction.scalespace import contour_curvature

    with pytest.raises(InputError, match="no area"):
        contour_curvature([[0, 0], [10, 0], [20, 0]])


def test_figure_eight_with_cancelling_lobes_still_accepted():
    bowtie = Contour([[0, 0], [10, 10], [10, 0], [0, 10]])
    assert not bowtie.is_simple()


# ------------------------------------------------------------------ faults 3-6: argument checks

@pytest.mark.parametrize("call, name", [
    (lambda: turning_angles(np.zeros((4, 3))), "points"),
    (lambda: turning_angles(SQ.T), "points"),
    (lambda: turning_angles([[0, 0], [1, np.nan], [1, 1]]), "points"),
    (lambda: turning_angles(np.empty((0, 2))), "points"),
    (lambda: turning_angles(SQ, closed="no"), "closed"),
    (lambda: surprisal_from_points([[0, 0], [1, np.nan], [1, 1]]), "points"),
    (lambda: surprisal_from_points(np.empty((0, 2))), "points"),
    (lambda: surprisal_from_points(np.zeros((4, 3))), "points"),
    (lambda: surprisal_from_points(SQ.T), "points"),
    (lambda: surprisal_from_points([[0, 0]]), "points"),
    (lambda: surprisal_from_points(SQ, bits="no"), "bits"),
    (lambda: gaussian_curvature(SQ, 0), "sigma"),
    (lambda: gaussian_curvature(SQ, np.nan), "sigma"),
    (lambda: gaussian_curvature(np.zeros((4, 3)), 1.0), "points"),
    (lambda: gaussian_curvature(np.empty((0, 2)), 1.0), "points"),
    (lambda: shoelace(np.empty((0, 2))), "points"),
    (lambda: shoelace(np.zeros((4, 3))), "points"),
    (lambda: surprisal_paper(0.1, ds=np.nan, n=10), "ds"),
    (lambda: surprisal_paper([np.nan], ds=1, n=10), "turning_angle"),
    (lambda: surprisal_paper(0.1, ds=1, n=np.inf), "n"),
    (lambda: surprisal_paper(0.1, ds=1, n=10.5), "n"),
    (lambda: surprisal_paper(0.1, ds=1, n=10, A="x"), "A"),
    (lambda: surprisal_vonmises(0.1, n=10, b=None), "b"),
    (lambda: surprisal_vonmises(0.1, n=10, b="4"), "b"),
    (lambda: Contour(SQ).point_at(np.nan), "t"),
    (lambda: Contour(SQ).project([[np.nan, 1]]), "points"),
    (lambda: Contour(SQ).project([1, 2, 3]), "points"),
    (lambda: Contour(SQ).transformed("2"), "scale"),
    (lambda: Contour(SQ).transformed(1, (np.nan, 0)), "offset"),
    (lambda: Contour(SQ).resample(n=3.7), "n"),
    (lambda: Contour(SQ).resample(spacing="1"), "spacing"),
    (lambda: Contour(SQ).curvature("gaussian", sigma="2"), "sigma"),
    (lambda: surprisal(SQ, n=3.5), "n"),
    (lambda: surprisal(SQ, n=np.array([5, 6])), "n"),
    (lambda: surprisal(SQ, A="x"), "A"),
    (lambda: surprisal(SQ, b="1"), "b"),
    (lambda: surprisal(SQ, prominence="1"), "prominence"),
    (lambda: surprisal(SQ, spacing="1"), "spacing"),
    (lambda: surprisal(SQ, bits="no"), "bits"),
    (lambda: find_peaks(np.ones((3, 3))), "u"),
    (lambda: find_peaks([0, np.inf, 0, 1, 0]), "u"),
    (lambda: find_peaks([0, np.nan, 0, 1, 0], closed=False), "u"),
    (lambda: find_peaks([0, 1, 0], prominence="0.1"), "prominence"),
    (lambda: Contour(SQ, closed="no"), "closed"),
    (lambda: Contour(np.array([[1 + 1j, 0], [2, 0], [0, 3]])), "points"),
])
def test_bad_argument_named(call, name):
    with pytest.raises(InputError, match=rf"^(.*: )?{name}\b"):
        call()


def test_good_arguments_still_work():
    assert Contour(SQ, closed=np.bool_(True)).closed
    assert surprisal(SQ, n=10.0).params["n"] == 10
    assert surprisal(SQ, bits=np.True_).params["units"] == "bits"
    # an open curve's ends have no turning angle: NaN there is allowed
    a = turning_angles(SQ, closed=False)
    assert np.isnan(a[[0, -1]]).all()
    u = surprisal_paper(a, ds=1, n=4, closed=False)
    assert np.isnan(u[[0, -1]]).all() and np.isfinite(u[1:-1]).all()
    assert find_peaks(u, closed=False)[0].size == 0  # two equal right angles: flat
    assert find_peaks([np.nan, 1.0, 3.0, 2.0, np.nan], closed=False)[0].tolist() == [2]
    nearest, _t, _d = Contour(SQ).project([5, -1])
    np.testing.assert_allclose(nearest, [[5, 0]])
    assert shoelace(SQ) == 100.0


def test_numbers_beyond_the_float_range_are_input_errors():
    # float(10**400) and int(inf) raise OverflowError, which escaped as a traceback
    from attneave.stimuli.validate import as_int, as_number

    for f, v in ((as_number, 10**400), (as_int, float("inf"))):
        with pytest.raises(InputError, match="^x: must be"):
            f(v, "x")
    assert as_int(10**400, "x") == 10**400  # a whole number, however large
