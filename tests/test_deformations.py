"""Barenholtz-style deformations: one place changed, matched size, concave vs convex.

Must show: concave and convex versions differ from the base in one place,
with equal displacement and |area change| equal to 1e-9 relative, all simple;
the concave one has a negative turning angle there, the convex one not.
"""

import numpy as np
import pytest

from attneave.stimuli import Contour, InputError
from attneave.stimuli.batch import recipes
from attneave.stimuli.shapes import deformations as dm
from attneave.stimuli.shapes import generators as g


def rng(seed=0):
    return np.random.default_rng(seed)


def placed_polygon(seed, n_points=12):
    c, _ = g.attneave_polygon(rng(seed), n_points=n_points)
    return c.transformed(4.0, (50.0, 50.0))


def placed_rf(seed):
    c, _ = g.radial_frequency(rng(seed), r0=150, frequency=[3, 5], amplitude=[0.1, 0.08], n=600)
    return c.transformed(1.0, (256.0, 256.0))


def n_concave(c):
    return int(np.sum(c.turning_angles() < -1e-9))


def assert_matched(d, displacement):
    base, cc, cv = d.base, d.concave, d.convex
    assert base.n == cc.n == cv.n
    for c in (base, cc, cv):
        assert c.is_simple()
    # equal and opposite displacement vectors
    dc = cc.points - base.points
    dv = cv.points - base.points
    np.testing.assert_array_equal(dc == 0, dv == 0)
    np.testing.assert_allclose(dc, -dv, rtol=0, atol=1e-12)
    moved = np.flatnonzero(np.any(dc != 0, axis=1))
    assert d.index in moved
    mags = np.hypot(*dc.T)
    assert mags.max() == pytest.approx(displacement, rel=1e-12)
    assert mags[d.index] == pytest.approx(displacement, rel=1e-12)
    # |area change| equal to 1e-9 relative, opposite signs, as predicted
    da_c = cc.area - base.area
    da_v = cv.area - base.area
    assert da_c < 0 < da_v
    assert abs(abs(da_c) - abs(da_v)) <= 1e-9 * abs(da_v)
    assert abs(da_v) == pytest.approx(d.params["area_change"], rel=1e-9)
    # concave there, convex there
    assert cc.turning_angles()[d.index] < 0
    assert cv.turning_angles()[d.index] > 0
    # away from the moved vertex the convex version keeps the base's concavities,
    # and the concave version has more concave vertices than the convex one
    tb, tv = base.turning_angles(), cv.turning_angles()
    others = np.arange(base.n) != d.index
    np.testing.assert_array_equal((tv < -1e-9)[others], (tb < -1e-9)[others])
    assert n_concave(cc) > n_concave(cv)
    return moved


@pytest.mark.parametrize("seed", range(8))
def test_edge_mode_changes_one_vertex(seed):
    c = placed_polygon(seed)
    d = dm.deform(c, rng(seed), mode="edge", displacement=10.0)
    moved = assert_matched(d, 10.0)
    assert moved.tolist() == [d.index]  # one place
    assert n_concave(d.concave) == n_concave(d.base) + 1
    assert n_concave(d.convex) == n_concave(d.base)
    # the base is the original polygon with one straight-angle vertex added
    assert d.base.n == c.n + 1
    assert abs(d.base.turning_angles()[d.index]) < 1e-9
    np.testing.assert_array_equal(np.delete(d.base.points, d.index, axis=0), c.points)
    assert d.base.area == pytest.approx(c.area, rel=1e-12)
    # moved along the side's normal: distance to the side's line is the displacement
    a, b = c.points[d.params["edge"]], c.points[(d.params["edge"] + 1) % c.n]
    u = (b - a) / np.hypot(*(b - a))
    for q in (d.concave.points[d.index], d.convex.points[d.index]):
        r = q - a
        assert abs(r[0] * u[1] - r[1] * u[0]) == pytest.approx(10.0, rel=1e-12)


def test_edge_mode_on_a_square_is_exact():
    sq = Contour([[0, 0], [0, 100], [100, 100], [100, 0]])
    d = dm.deform(sq, rng(0), mode="edge", displacement=10)
    # area of the triangle added/removed: base 100, height 10
    assert d.base.area - d.concave.area == 500.0
    assert d.convex.area - d.base.area == 500.0
    assert np.degrees(d.params["turning_angle_convex"]) == pytest.approx(2 * np.degrees(np.arctan(10 / 50)))


def test_vertex_mode_moves_one_existing_vertex():
    found = 0
    for seed in range(8):
        c = placed_polygon(seed, n_points=16)
        try:
            d = dm.deform(c, rng(seed), mode="vertex", displacement=25.0)
        except InputError as exc:
            assert "no place" in str(exc)  # no vertex flat enough for a 25 px move to flip it
            continue
        found += 1
        moved = assert_matched(d, 25.0)
        assert moved.tolist() == [d.index]
        np.testing.assert_array_equal(d.base.points, c.points)
        # one vertex, concave in one version and convex in the other; nothing else changes sign
        assert n_concave(d.concave) == n_concave(d.convex) + 1
        assert n_concave(d.base) in (n_concave(d.concave), n_concave(d.convex))
        # moved along the normal of the chord joining its neighbours
        p = c.points
        chord = p[(d.index + 1) % c.n] - p[d.index - 1]
        step = d.convex.points[d.index] - p[d.index]
        assert abs(step @ chord) < 1e-9 * np.hypot(*chord) * 25
    assert found >= 3


@pytest.mark.parametrize("seed", range(4))
def test_bump_mode_on_a_smooth_contour(seed):
    c = placed_rf(seed)
    d = dm.deform(c, rng(seed), mode="bump", displacement=8.0)
    moved = assert_matched(d, 8.0)
    np.testing.assert_array_equal(d.base.points, c.points)
    # one place: the moved vertices are one run of consecutive vertices around the centre
    n = c.n
    run = {d.index}
    for step in (1, -1):
        j = (d.index + step) % n
        while j in set(moved.tolist()) and j not in run:
            run.add(j)
            j = (j + step) % n
    assert run == set(moved.tolist())
    # every displacement is parallel to the recorded direction
    dv = d.convex.points - d.base.points
    u = np.asarray(d.params["direction"])
    np.testing.assert_allclose(dv[:, 0] * u[1] - dv[:, 1] * u[0], 0, atol=1e-12)
    assert np.all(dv @ u >= 0)
    # the convex bulge adds no concavity anywhere
    assert n_concave(d.convex) == n_concave(d.base)


def test_bump_with_fixed_width_and_no_place():
    c = placed_rf(1)
    d = dm.deform(c, rng(1), mode="bump", displacement=8.0, width=d_width(c, 8.0))
    assert d.params["width"] == pytest.approx(d_width(c, 8.0))
    circle = Contour(np.c_[100 * np.cos(np.linspace(0, 2 * np.pi, 200, endpoint=False)),
                           100 * np.sin(np.linspace(0, 2 * np.pi, 200, endpoint=False))])
    # on a circle of radius 100 a 3 px dent 20 px wide cannot become concave: 12 d / w^2 < 1/100
    with pytest.raises(InputError, match="no place"):
        dm.deform(circle, rng(0), mode="bump", displacement=3.0, width=200.0)


def d_width(c, d):
    # a width that works somewhere on this RF pattern: the automatic one at a convex place
    return dm.deform(c, rng(1), mode="bump", displacement=d).params["width"]


def test_deformation_is_deterministic():
    c = placed_polygon(3)
    a = dm.deform(c, rng(5), mode="edge", displacement=12)
    b = dm.deform(c, rng(5), mode="edge", displacement=12)
    assert a.index == b.index and a.params == b.params
    np.testing.assert_array_equal(a.concave.points, b.concave.points)


def test_min_turn_is_respected():
    c = placed_polygon(2)
    d = dm.deform(c, rng(2), mode="edge", displacement=10, min_turn=15)
    assert np.degrees(-d.params["turning_angle_concave"]) > 15
    assert np.degrees(d.params["turning_angle_convex"]) > 15


def test_bad_parameters():
    c = placed_polygon(0)
    with pytest.raises(InputError, match="displacement"):
        dm.deform(c, rng(), displacement=-1)
    with pytest.raises(InputError, match="mode"):
        dm.deform(c, rng(), mode="twist")


@pytest.mark.parametrize(
    "params",
    [
        {},
        {"mode": "bump", "displacement": 6,
         "base": {"generator": "radial_frequency", "params": {"frequency": [3, 5], "amplitude": [0.1, 0.08]}}},
    ],
    ids=["edge-attneave", "bump-rf"],
)
def test_deformation_recipe_items_and_rendered_area(params):
    canvas = recipes.Canvas(256, 256, 24)
    items = recipes.make("deformation", 4, canvas=canvas, **params)
    assert [(i.suffix, i.condition, i.parent_suffix) for i in items] == [
        ("base", "base", None), ("concave", "concave", "base"), ("convex", "convex", "base")]
    base, cc, cv = (i.contour for i in items)
    da = items[0].params["deformation"]["area_change"]
    assert abs((base.area - cc.area) - da) <= 1e-9 * da
    assert abs((cv.area - base.area) - da) <= 1e-9 * da
    # exact-coverage images: the rendered area changes by the same amount
    style = recipes.Style()
    cover = [float((1 - recipes.draw_item(i, style, canvas)).sum()) for i in items]
    assert cover[0] == pytest.approx(base.area, rel=1e-9)
    assert cover[0] - cover[1] == pytest.approx(da, rel=1e-6)
    assert cover[2] - cover[0] == pytest.approx(da, rel=1e-6)
