"""Contour geometry against analytic results."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from attneave.stimuli import Contour, InputError


def circle(R=100.0, n=4000, cx=256.0, cy=256.0, phase=0.0):
    th = phase + 2 * np.pi * np.arange(n) / n
    return np.c_[cx + R * np.cos(th), cy + R * np.sin(th)]


def ellipse(a=120.0, b=50.0, n=2000, cx=256.0, cy=256.0):
    th = 2 * np.pi * np.arange(n) / n
    return np.c_[cx + a * np.cos(th), cy + b * np.sin(th)]


def test_circle_perimeter_area_curvature():
    R = 100.0
    c = Contour(circle(R))
    n = 4000
    # a regular n-gon inscribed in the circle
    assert c.perimeter == pytest.approx(2 * n * R * np.sin(np.pi / n), rel=1e-12)
    assert c.area == pytest.approx(0.5 * n * R**2 * np.sin(2 * np.pi / n), rel=1e-12)
    k = c.curvature()
    assert np.all(k > 0)
    assert np.max(np.abs(k * R - 1)) < 0.005
    assert c.turning_angles().sum() == pytest.approx(2 * np.pi, abs=1e-9)


def test_orientation_is_counterclockwise_on_screen():
    # y down: going right along the top then down the right side is clockwise on screen
    cw = [[0, 0], [10, 0], [10, 10], [0, 10]]
    c = Contour(cw)
    assert c.signed_area == pytest.approx(100)
    assert c.points[0].tolist() == [0, 0]  # first point kept
    assert c.points[1].tolist() == [0, 10]  # then down the left side: counter-clockwise on screen
    assert np.all(c.turning_angles() > 0)
    # an input already counter-clockwise is kept exactly as given
    assert Contour(cw[::-1]).points.tolist() == cw[::-1]


@pytest.mark.parametrize("transform", ["none", "reverse", "mirror", "shift"])
def test_curvature_sign_survives_storage_order(transform):
    # a star-shaped contour with a dent at angle 0
    th = 2 * np.pi * np.arange(720) / 720
    r = 100 - 30 * np.exp(-((np.angle(np.exp(1j * th))) ** 2) / (2 * 0.15**2))
    p = np.c_[200 + r * np.cos(th), 200 + r * np.sin(th)]
    if transform == "reverse":
        p = p[::-1]
    elif transform == "mirror":
        p = np.c_[p[:, 0], 400 - p[:, 1]]
    elif transform == "shift":
        p = np.roll(p, 200, axis=0)
    c = Contour(p)
    k = c.curvature()
    dent = np.argmin(np.hypot(*(c.points - [200 + 70, 200]).T))
    far = np.argmin(np.hypot(*(c.points - [100, 200]).T))
    assert k[dent] < 0
    assert k[far] > 0


def test_gaussian_curvature_circle_and_noise():
    R = 80.0
    rng = np.random.default_rng(0)
    # about one point per pixel with 0.2 px jitter, like a pixel-traced outline
    p = circle(R, n=500) + rng.normal(0, 0.2, (500, 2))
    c = Contour(p)
    sigma = 10.0
    k = c.curvature("gaussian", sigma=sigma)
    # Gaussian smoothing shrinks a circle's radius by exp(-sigma^2 / 2R^2)
    expected = 1 / (R * np.exp(-(sigma**2) / (2 * R**2)))
    assert np.sqrt(np.mean((k - expected) ** 2)) / expected < 0.05
    assert k.mean() == pytest.approx(expected, rel=0.01)
    # the exact method on the noisy points is far worse: that is why gaussian exists
    assert np.std(c.curvature()) > 10 * np.std(k)


def test_gaussian_curvature_ellipse_analytic():
    a, b = 120.0, 60.0
    c = Contour(ellipse(a, b, n=3000))
    k = c.curvature("gaussian", sigma=1.0)
    th = np.arctan2((c.points[:, 1] - 256) / b, (c.points[:, 0] - 256) / a)
    exact = a * b / (a**2 * np.sin(th) ** 2 + b**2 * np.cos(th) ** 2) ** 1.5
    assert np.max(np.abs(k - exact)) / exact.max() < 2e-3


def test_resample_is_equally_spaced_and_starts_at_first_point():
    c = Contour(ellipse())
    r = c.resample(n=100)
    assert r.n == 100
    assert np.allclose(r.points[0], c.points[0])
    seg = r.segment_lengths()
    # chords of equal arcs on a 2000-gon: equal to the polygon's own resolution
    assert np.ptp(seg) / seg.mean() < 0.01
    assert c.resample(spacing=c.perimeter / 37).n == 37
    with pytest.raises(InputError):
        c.resample()
    with pytest.raises(InputError):
        c.resample(n=2)


def test_open_contour_resample_and_turning():
    p = np.c_[np.linspace(0, 10, 11), np.zeros(11)]
    p[5, 1] = 0.0
    c = Contour(np.r_[p, [[10, 5]]], closed=False)
    a = c.turning_angles()
    assert np.isnan(a[0]) and np.isnan(a[-1])
    # from heading +x to heading +y (down on screen) is a right turn on the screen
    assert a[-2] == pytest.approx(-np.pi / 2)
    r = c.resample(n=16)
    assert np.allclose(r.points[[0, -1]], [[0, 0], [10, 5]])


def test_project_onto_square():
    sq = Contour([[0, 0], [0, 10], [10, 10], [10, 0]])
    q = np.array([[5, -2], [12, 5], [5, 8.0], [0, 0]])
    nearest, t, dist = sq.project(q)
    assert np.allclose(nearest, [[5, 0], [10, 5], [5, 10], [0, 0]])
    assert np.allclose(dist, [2, 2, 2, 0])
    # (5, 0) lies on the closing edge (10,0) -> (0,0), 35 of 40 px along
    assert t[0] == pytest.approx(0.875)
    assert t[3] == pytest.approx(0.0)
    assert np.allclose(sq.point_at(t), nearest)


@settings(max_examples=30, deadline=None)
@given(st.floats(0.01, 0.99), st.floats(-40, 40), st.floats(-40, 40))
def test_project_recovers_points_on_curve(t0, dx, dy):
    c = Contour(ellipse(80, 40, n=300))
    p = c.point_at([t0])
    nearest, t, dist = c.project(p)
    assert dist[0] < 1e-9
    assert t[0] == pytest.approx(t0, abs=1e-9)
    # a point off the curve is never closer than its true distance to any vertex
    q = p + [dx, dy]
    _, _, d = c.project(q)
    assert d[0] <= np.hypot(*(c.points - q).T).min() + 1e-9


def test_validation_errors():
    with pytest.raises(InputError, match=r"row 1: coordinates must be finite"):
        Contour([[0, 0], [1, np.nan], [2, 0]])
    with pytest.raises(InputError, match="3 distinct"):
        Contour([[0, 0], [1, 1], [0, 0], [1, 1]])
    with pytest.raises(InputError, match="shape"):
        Contour([1, 2, 3])
    # consecutive duplicates and a repeated end point are dropped
    c = Contour([[0, 0], [0, 0], [0, 10], [10, 10], [10, 0], [0, 0]])
    assert c.n == 4


def test_self_intersection_detected_and_reported():
    bowtie = Contour([[0, 0], [10, 10], [10, 0], [0, 10]])
    assert not bowtie.is_simple()
    assert np.allclose(bowtie.self_intersections(), [[5, 5]])
    with pytest.raises(InputError, match=r"crosses itself near \(x=5.000, y=5.000\)"):
        Contour([[0, 0], [10, 10], [10, 0], [0, 10]], simple=True)
    assert Contour(circle(n=100), simple=True).is_simple()


def test_csv_roundtrip_and_errors(tmp_path):
    c = Contour(ellipse(n=50))
    f = tmp_path / "c.csv"
    c.to_csv(f)
    assert np.allclose(Contour.from_csv(f).points, c.points, atol=1e-6)
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y\n0,0\n1,abc\n2,2\n")
    with pytest.raises(InputError, match=r"bad.csv: line 3: column 'y'"):
        Contour.from_csv(bad)
    missing = tmp_path / "missing.csv"
    missing.write_text("x,z\n0,0\n1,1\n2,2\n")
    with pytest.raises(InputError, match="missing column"):
        Contour.from_csv(missing)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([60, 300, 2000]))
def test_project_by_kd_tree_equals_every_segment_tried_and_geos_distance(seed, n):
    """Many clicks on a long contour take the k-d tree's path: the same segment, position and
    distance to the last bit as trying every segment, and GEOS's distance to the polyline."""
    import shapely

    import attneave.stimuli.geometry.polyline as pl

    rng = np.random.default_rng(seed)
    th = np.sort(rng.uniform(0, 2 * np.pi, n))  # uneven segments, some long
    r = 100 * (1 + 0.3 * np.sin(rng.integers(2, 7) * th))
    c = Contour(np.c_[256 + r * np.cos(th), 256 + r * np.sin(th)])
    near = c.points[rng.integers(0, n, 400)] + rng.normal(0, 4, (400, 2))
    q = np.vstack([near, c.points[:20], [[256.0, 256.0]], rng.uniform(-200, 700, (60, 2))])
    assert len(q) * n >= pl._TREE_PAIRS
    by_tree = c.project(q)
    old = pl._TREE_PAIRS
    pl._TREE_PAIRS = 10**18
    try:
        every = c.project(q)
    finally:
        pl._TREE_PAIRS = old
    for a, b in zip(by_tree, every):
        assert np.array_equal(a, b)
    ring = shapely.LinearRing(c.points)
    np.testing.assert_allclose(by_tree[2], shapely.distance(ring, shapely.points(q)), rtol=1e-9, atol=1e-9)
    on = by_tree[0][: len(near)]
    assert np.abs(shapely.distance(ring, shapely.points(on))).max() < 1e-9
