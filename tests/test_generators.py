"""Shape generators and recipes: determinism, simplicity, and the formulas they claim."""

import json

import numpy as np
import pytest
from pydantic import ValidationError
from scipy.spatial import ConvexHull

from attneave.stimuli import Contour, InputError
from attneave.stimuli.batch import recipes
from attneave.stimuli.shapes import generators as g


def rng(seed=0):
    return np.random.default_rng(seed)


def unsigned_angles_deg(p):
    """Angle between the two sides at each vertex, from the law of cosines."""
    a = np.roll(p, 1, axis=0) - p
    b = np.roll(p, -1, axis=0) - p
    cos = (a * b).sum(1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
    return np.degrees(np.arccos(np.clip(cos, -1, 1)))


def polar(points, centre=(0.0, 0.0)):
    """(r, theta) with theta counter-clockwise on the screen (y down)."""
    d = np.asarray(points) - np.asarray(centre)
    return np.hypot(d[:, 0], d[:, 1]), np.arctan2(-d[:, 1], d[:, 0])


# ---------------------------------------------------------------- determinism


RANDOM = [
    ("attneave_polygon", lambda r: g.attneave_polygon(r, n_points=10)),
    ("attneave_curved", lambda r: g.attneave_curved(r, n_points=10)[1:]),
    ("radial_frequency", lambda r: g.radial_frequency(r, frequency=[3, 7], amplitude=[0.1, 0.05])),
    ("fourier_radial", lambda r: g.fourier_shape(r, amplitude=0.2)),
    ("fourier_elliptic", lambda r: g.fourier_shape(r, kind="elliptic", amplitude=0.3)),
    ("blob", lambda r: g.blob(r, sigma=0.3)),
]


@pytest.mark.parametrize("name,make", RANDOM, ids=[n for n, _ in RANDOM])
def test_same_seed_same_shape_and_other_seed_other_shape(name, make):
    c1, p1 = make(rng(7))
    c2, p2 = make(rng(7))
    c3, _ = make(rng(8))
    assert np.array_equal(c1.points, c2.points)
    assert json.dumps(p1, sort_keys=True) == json.dumps(p2, sort_keys=True)
    assert c1.n != c3.n or not np.array_equal(c1.points, c3.points)
    assert c1.closed and c1.is_simple()
    assert c1.signed_area > 0  # counter-clockwise on the screen


# ---------------------------------------------------------------- Attneave & Arnoult


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("n_points", [5, 12, 20])
def test_attneave_polygon_is_method_1(seed, n_points):
    grid = 50
    c, p = g.attneave_polygon(rng(seed), n_points=n_points, grid=grid, min_angle=10, max_angle=170)
    pts = c.points
    # the requested number of vertices, all distinct points of the grid
    assert c.n == n_points == p["n_points"]
    assert np.array_equal(pts, np.round(pts))
    assert pts.min() >= 0 and pts.max() <= grid - 1
    assert len(np.unique(pts, axis=0)) == n_points
    assert c.is_simple()
    # angle limits hold at every vertex
    ang = unsigned_angles_deg(pts)
    assert ang.min() >= 10 - 1e-9 and ang.max() <= 170 + 1e-9
    # Method 1 only ever splits sides of the convex hull: the hull's vertices
    # are all polygon vertices and appear in the polygon in the hull's cyclic order
    hull = ConvexHull(pts).vertices  # indices into pts, counter-clockwise in (x, y)
    assert len(hull) == p["hull_size"] >= 3
    pos = np.sort(hull)
    order = [int(np.flatnonzero(pos == h)[0]) for h in hull]  # rank of each hull vertex along the polygon
    k = len(order)
    steps = {(order[(i + 1) % k] - order[i]) % k for i in range(k)}
    assert steps in ({1}, {k - 1})  # the same cyclic order, one way round or the other


def test_attneave_without_limits_and_impossible_limits():
    c, p = g.attneave_polygon(rng(1), n_points=30, grid=100, min_angle=0, max_angle=180)
    assert c.n == 30 and c.is_simple()
    with pytest.raises(InputError, match="no simple polygon"):
        g.attneave_polygon(rng(1), n_points=12, min_angle=100, max_angle=110, max_tries=5)
    with pytest.raises(InputError, match="grid"):
        g.attneave_polygon(rng(1), n_points=10, grid=3)


def test_curved_versions_through_and_around_the_same_vertices():
    poly, cub, p = g.attneave_curved(rng(3), n_points=10, method="cubic", samples_per_edge=16)
    assert cub.n == 160 and cub.is_simple()
    # the interpolating spline passes through every vertex, exactly
    for v in poly.points:
        assert np.min(np.hypot(*(cub.points - v).T)) == 0.0
    poly2, bsp, _ = g.attneave_curved(rng(3), n_points=10, method="bspline", samples_per_edge=8)
    # uniform cubic B-spline: at a knot the curve is (P[i-1] + 4 P[i] + P[i+1]) / 6
    q = poly2.points
    knots = (np.roll(q, 1, axis=0) + 4 * q + np.roll(q, -1, axis=0)) / 6
    for v in knots:
        assert np.min(np.hypot(*(bsp.points - v).T)) < 1e-9
    # both stay near their polygon (within its box grown by 10%)
    for poly_, curve in ((poly, cub), (poly2, bsp)):
        x0, y0, x1, y1 = poly_.bbox
        cx0, cy0, cx1, cy1 = curve.bbox
        assert cx0 >= x0 - 0.1 * (x1 - x0) and cx1 <= x1 + 0.1 * (x1 - x0)
        assert cy0 >= y0 - 0.1 * (y1 - y0) and cy1 <= y1 + 0.1 * (y1 - y0)


def test_smooth_closed_rejects_unknown_method():
    with pytest.raises(InputError, match="method"):
        g.smooth_closed([[0, 0], [1, 0], [0, 1]], method="spline")


# ---------------------------------------------------------------- radial frequency


@pytest.mark.parametrize(
    "freq,amp,phase",
    [(5, 0.2, 0.3), ([3, 7], [0.1, 0.05], [0.0, 1.0]), ([2, 4, 8], [0.2, 0.1, 0.05], None)],
)
def test_radial_frequency_follows_its_formula(freq, amp, phase):
    c, p = g.radial_frequency(rng(2), r0=80.0, frequency=freq, amplitude=amp, phase=phase, n=720)
    r, th = polar(c.points)
    want = 80.0 * (1 + sum(a * np.sin(w * th + ph) for w, a, ph in zip(p["frequency"], p["amplitude"], p["phase"])))
    np.testing.assert_allclose(r, want, rtol=1e-12)
    # sampled at equally spaced polar angles, counter-clockwise on the screen
    dth = np.mod(np.diff(np.unwrap(th)), 2 * np.pi)
    np.testing.assert_allclose(dth, 2 * np.pi / 720, rtol=1e-9)
    assert c.is_simple() and c.signed_area > 0


def test_radial_frequency_rejects_nonpositive_radius():
    with pytest.raises(InputError, match="sum to < 1"):
        g.radial_frequency(rng(), frequency=[3, 5], amplitude=[0.6, 0.5])
    with pytest.raises(InputError, match=">= 0"):
        g.radial_frequency(rng(), frequency=3, amplitude=-0.1)


# ---------------------------------------------------------------- superformula


def test_superformula_matches_its_formula():
    c, p = g.superformula(m=6, n1=1.0, n2=7.0, n3=8.0, a=1.0, b=1.0, scale=50.0, n=600)
    r, th = polar(c.points)
    t = 6 * th / 4
    want = 50.0 * (np.abs(np.cos(t)) ** 7 + np.abs(np.sin(t)) ** 8) ** (-1.0)
    np.testing.assert_allclose(r, want, rtol=1e-10)


def test_superformula_special_cases():
    # m=4, n1=n2=n3=2: cos^2 + sin^2 = 1, a circle
    c, _ = g.superformula(m=4, n1=2, n2=2, n3=2, scale=30, n=400)
    np.testing.assert_allclose(np.hypot(*c.points.T), 30, rtol=1e-12)
    # m=4, n1=n2=n3=1: r = 1/(|cos|+|sin|), the square |x| + |y| = scale
    c, _ = g.superformula(m=4, n1=1, n2=1, n3=1, scale=30, n=400)
    np.testing.assert_allclose(np.abs(c.points).sum(1), 30, rtol=1e-12)
    with pytest.raises(InputError, match="does not close"):
        g.superformula(m=3, n2=2, n3=3)


# ---------------------------------------------------------------- Fourier, blob


def test_fourier_radial_reproduces_its_coefficients():
    c, p = g.fourier_shape(rng(4), kind="radial", r0=90, amplitude=0.15, falloff=1.0, harmonics=6, n=512)
    r, th = polar(c.points)
    coef = np.array(p["coefficients"])
    want = 90 * (1 + sum(a * np.cos(k * th) + b * np.sin(k * th) for k, a, b in coef))
    np.testing.assert_allclose(r, want, rtol=1e-10)
    assert coef[:, 0].tolist() == [2, 3, 4, 5, 6]


def test_fourier_elliptic_is_simple_and_retries_deterministically():
    c, p = g.fourier_shape(rng(5), kind="elliptic", amplitude=0.6, falloff=0.5, harmonics=5, n=400, max_tries=500)
    assert c.is_simple()
    assert p["tries"] >= 1
    c2, p2 = g.fourier_shape(rng(5), kind="elliptic", amplitude=0.6, falloff=0.5, harmonics=5, n=400, max_tries=500)
    assert p2["tries"] == p["tries"] and np.array_equal(c.points, c2.points)


def test_blob_geometric_mean_radius_and_rms():
    c, p = g.blob(rng(6), r0=70, sigma=0.25, width=0.5, n=1000)
    logr = np.log(np.hypot(*c.points.T))
    # harmonics k >= 2 sum to zero over equally spaced angles: mean log r = log r0
    assert np.exp(logr.mean()) == pytest.approx(70, rel=1e-12)
    assert np.sqrt(np.mean((logr - np.log(70)) ** 2)) == pytest.approx(0.25, rel=1e-12)
    assert c.is_simple()


# ---------------------------------------------------------------- CSV


def test_contour_from_csv(tmp_path):
    path = tmp_path / "c.csv"
    path.write_text("x,y\n0,0\n10,0\n10,5\n0,5\n")
    c, p = g.contour_from_csv(path)
    assert c.n == 4 and p["centre"] == [5.0, 2.5]
    eight = tmp_path / "eight.csv"
    eight.write_text("x,y\n0,0\n10,10\n10,0\n0,10\n")
    with pytest.raises(InputError, match="crosses itself"):
        g.contour_from_csv(eight)
    with pytest.raises(InputError, match="no such file"):
        g.contour_from_csv(tmp_path / "missing.csv")


# ---------------------------------------------------------------- recipes: placement, validation


def test_fit_placement_fills_the_canvas_less_margin():
    canvas = recipes.Canvas(300, 200, 20)
    [it] = recipes.make("attneave_polygon", 3, canvas=canvas, n_points=9)
    x0, y0, x1, y1 = it.contour.bbox
    # the tighter side touches the margins; centred on ((w-1)/2, (h-1)/2)
    assert min(300 - 40 - (x1 - x0), 200 - 40 - (y1 - y0)) == pytest.approx(0, abs=1e-9)
    assert (x0 + x1) / 2 == pytest.approx(149.5) and (y0 + y1) / 2 == pytest.approx(99.5)
    assert x0 >= 20 - 0.5 - 1e-9 and y0 >= 20 - 0.5 - 1e-9


def test_native_placement_keeps_pixels_and_centres_the_origin():
    canvas = recipes.Canvas(256, 256, 8)
    [it] = recipes.make("radial_frequency", 1, canvas=canvas, r0=60, frequency=4, amplitude=0.2, phase=0.0,
                        placement="native", n=360)
    r, th = polar(it.contour.points, centre=(127.5, 127.5))
    np.testing.assert_allclose(r, 60 * (1 + 0.2 * np.sin(4 * th)), rtol=1e-12)
    assert it.params["placement"] == {"placement": "native", "scale": 1.0, "offset": [127.5, 127.5]}


def test_attneave_both_overlays_polygon_and_curve():
    items = recipes.make("attneave_polygon", 2, version="both", smooth_method="cubic", samples_per_edge=8)
    assert [(i.suffix, i.condition, i.parent_suffix) for i in items] == [
        ("polygon", "polygon", None), ("curved", "curved", "polygon")]
    poly, curved = items[0].contour, items[1].contour
    for v in poly.points:  # the same transform: the curve still passes through the vertices
        assert np.min(np.hypot(*(curved.points - v).T)) < 1e-9


@pytest.mark.parametrize("name", sorted(set(recipes.SHAPES) - {"from_csv", "from_image"}))
def test_every_shape_recipe_is_deterministic_and_json(name):
    a = recipes.make(name, 11)
    b = recipes.make(name, 11)
    assert len(a) == len(b) == 1
    assert np.array_equal(a[0].contour.points, b[0].contour.points)
    ja = json.dumps(a[0].params, sort_keys=True, allow_nan=False)
    assert ja == json.dumps(b[0].params, sort_keys=True, allow_nan=False)
    assert a[0].suffix == "" and a[0].contour.is_simple()


def test_from_csv_recipe_records_the_path_as_given(tmp_path):
    path = tmp_path / "sq.csv"
    path.write_text("x,y\n0,0\n4,0\n4,4\n0,4\n")
    [it] = recipes.make("from_csv", 0, path=str(path), draw="outline")
    assert it.params["shape"]["path"] == str(path)
    assert it.contour.area == pytest.approx((512 - 64) ** 2)


def test_params_models_give_clear_errors():
    Model = recipes.RECIPES["radial_frequency"][0]
    with pytest.raises(ValidationError) as e:
        Model.model_validate({"frequency": 5, "amplitude": -0.1})
    err = e.value.errors()[0]
    assert err["loc"][0] == "amplitude" and err["type"] == "greater_than_equal"
    with pytest.raises(ValidationError, match="extra"):
        Model.model_validate({"frequncy": 5})
    with pytest.raises(ValidationError, match="sum to < 1"):
        Model.model_validate({"frequency": [3, 5], "amplitude": [0.5, 0.5]})
    with pytest.raises(InputError, match="n_points"):
        recipes.make("attneave_polygon", 0, n_points=2)
    # nested base shapes are validated by their generator's own model
    D = recipes.RECIPES["deformation"][0]
    with pytest.raises(ValidationError) as e:
        D.model_validate({"base": {"generator": "attneave_polygon", "params": {"n_points": 2}}})
    assert e.value.errors()[0]["loc"] == ("base", "params", "n_points")
    dumped = D.model_validate({"base": {"generator": "blob", "params": {"sigma": 0.1}}}).model_dump(mode="json")
    assert dumped["base"]["params"]["sigma"] == 0.1 and dumped["base"]["params"]["r0"] == 100.0
    S = recipes.Style
    with pytest.raises(ValidationError):
        S.model_validate({"figure": 1.5})
    with pytest.raises(ValidationError):
        S.model_validate({"line_width": -1})
    assert S.model_validate({"figure": [1, 0, 0]}).figure == (1.0, 0.0, 0.0)


def test_canvas_rejects_a_margin_that_leaves_no_room():
    with pytest.raises(InputError, match="margin"):
        recipes.Canvas(100, 100, 50)


def test_contour_type_is_returned():
    c, _ = g.superformula()
    assert isinstance(c, Contour)


def test_from_image_recipe(tmp_path):
    cv2 = pytest.importorskip("cv2")
    img = np.full((80, 100), 255, np.uint8)
    cv2.circle(img, (50, 40), 25, 0, -1)
    path = tmp_path / "disc.png"
    cv2.imwrite(str(path), img)
    canvas = recipes.Canvas(128, 128, 14)
    [it] = recipes.make("from_image", 0, canvas=canvas, path=str(path), resample=200)
    assert it.contour.n == 200 and it.contour.is_simple()
    x0, y0, x1, y1 = it.contour.bbox
    assert x1 - x0 == pytest.approx(100, abs=1e-6) and y1 - y0 == pytest.approx(100, rel=0.02)
    assert it.params["shape"]["path"] == str(path)


def test_native_placement_outside_the_canvas_is_an_error():
    from attneave.stimuli.batch import recipes

    canvas = recipes.Canvas(64, 64, 4)
    with pytest.raises(InputError, match=r"placement: native: .* outside the 64x64 canvas"):
        recipes.make("radial_frequency", 1, canvas=canvas, placement="native", r0=500)
