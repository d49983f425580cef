"""Python-API robustness of the shape generators, deformations, guided
stimuli, recipes and renderer: bad input raises one `InputError` naming the
argument, never a numpy/scipy exception or a silently wrong result."""

import numpy as np
import pytest

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.shapes import deformations as d
from attneave.stimuli.shapes import generators as g
from attneave.stimuli.shapes import guided as gd

SQ = np.array([(10, 10), (90, 10), (90, 90), (10, 90)], float)
SQC = Contour([[0, 0], [0, 100], [100, 100], [100, 0]])


@pytest.fixture(scope="module")
def rf():
    return g.radial_frequency(r0=100, frequency=5, amplitude=0.2, phase=0.0, n=360)[0]


# ---------------------------------------------------------------- aliasing


def test_radial_frequency_refuses_aliased_sampling():
    # 16 samples of frequency 8 land on the zeros of the sine: a perfect circle, not an RF8 pattern
    with pytest.raises(InputError, match=r"^n: 16 points alias radial frequency 8.*n >= 32.*frequency"):
        g.radial_frequency(0, r0=100, frequency=8, amplitude=0.5, phase=0.0, n=16)
    with pytest.raises(InputError, match=r"^n: .*radial frequency 1000"):
        g.radial_frequency(0, frequency=1000, amplitude=0.5, n=16)
    with pytest.raises(InputError, match=r"^n: "):
        g.radial_frequency(0, frequency=[3, 9], amplitude=[0.1, 0.1], n=32)
    c, _ = g.radial_frequency(0, r0=100, frequency=8, amplitude=0.5, phase=0.0, n=32)
    r = np.hypot(*c.points.T)
    assert np.ptp(r) == pytest.approx(100.0)  # 4 points per cycle reach the peaks: r in [50, 150]


def test_superformula_refuses_aliased_sampling():
    with pytest.raises(InputError, match=r"^n: 1024 points alias .*\(m\).*lower m"):
        g.superformula(m=1e6, n=1024)
    g.superformula(m=6, n=24)


def test_fourier_shares_the_sampling_rule():
    with pytest.raises(InputError, match=r"^n: 16 points alias harmonic 8.*lower harmonics"):
        g.fourier_shape(0, harmonics=8, n=16)


# ---------------------------------------------------------------- seeds


@pytest.mark.parametrize("f", [g.attneave_polygon, g.radial_frequency, g.fourier_shape, g.blob])
def test_generators_take_an_int_seed_as_default_rng(f):
    a = f(7)[0].points
    b = f(np.random.default_rng(7))[0].points
    assert np.array_equal(a, b)


@pytest.mark.parametrize("seed", [None, -1, 1.5, "a", True, np.random.RandomState(0)])
def test_bad_seeds_are_refused_naming_rng(seed):
    with pytest.raises(InputError, match=r"^rng: "):
        g.blob(seed)
    with pytest.raises(InputError, match=r"^rng: "):
        d.deform(SQC, seed)
    from attneave.stimuli.batch import recipes

    with pytest.raises(InputError, match=r"^rng: "):
        recipes.make("radial_frequency", seed)


def test_deform_takes_an_int_seed():
    a = d.deform(SQC, 3).params
    b = d.deform(SQC, np.random.default_rng(3)).params
    assert a == b


def test_make_refuses_a_canvas_that_is_not_one():
    from attneave.stimuli.batch import recipes

    with pytest.raises(InputError, match=r"^canvas: "):
        recipes.make("radial_frequency", 1, canvas=(100, 100, 10))


# ---------------------------------------------------------------- deformations


@pytest.mark.parametrize("kw, name", [
    (dict(displacement="x"), "displacement"), (dict(displacement=None), "displacement"),
    (dict(position="x"), "position"), (dict(mode="bump", width="x"), "width"),
    (dict(min_turn="x"), "min_turn"), (dict(min_turn=np.nan), "min_turn"),
])
def test_deform_names_bad_parameters(kw, name):
    with pytest.raises(InputError, match=rf"^{name}: "):
        d.deform(SQC, 0, **kw)


def test_deform_takes_an_array():
    a = d.deform(SQC.points, 0).params
    assert a == d.deform(SQC, 0).params


@pytest.mark.parametrize("index", [99, 4, -5, 1.5, "a", True])
def test_vertex_indices_are_checked(index):
    with pytest.raises(InputError, match=r"^index: "):
        d.deform_at(SQC, index, 5)
    with pytest.raises(InputError, match=r"^index: "):
        d.move_vertex(SQC, index, (1, 0))


def test_deform_at_takes_an_array_and_negative_indices():
    a = d.deform_at(SQC.points, -1, 5)
    b = d.deform_at(SQC, 3, 5)
    assert np.array_equal(a[0].points, b[0].points) and a[2] == b[2]


def test_deform_at_refuses_a_clockwise_contour():
    with pytest.raises(InputError, match=r"^contour: runs clockwise"):
        d.deform_at(SQC.points[::-1], 0, 5)


def test_move_vertex_checks_the_vector():
    with pytest.raises(InputError, match=r"^vector: "):
        d.move_vertex(SQC, 0, [np.nan, 0])
    with pytest.raises(InputError, match=r"^vector: "):
        d.move_vertex(SQC, 0, [1, 2, 3])


def test_insert_vertex_names_bad_arguments():
    with pytest.raises(InputError, match=r"^edge: "):
        d.insert_vertex(SQC, "a")
    with pytest.raises(InputError, match=r"^position: "):
        d.insert_vertex(SQC, 0, "a")


def test_smooth_closed_names_non_finite_points():
    with pytest.raises(InputError, match=r"^points: row 1: "):
        g.smooth_closed([[0, 0], [1, np.nan], [1, 1]])


# ---------------------------------------------------------------- guided


def test_guided_take_arrays(rf):
    for f in (gd.attneave_cat, gd.dots):
        a, pa = f(rf.points)
        b, pb = f(rf)
        assert np.array_equal(a, b) and pa == pb
    assert gd.fragments(rf.points)["params"] == gd.fragments(rf)["params"]


@pytest.mark.parametrize("f, kw, name", [
    (gd.attneave_cat, dict(k=3.7), "k"), (gd.attneave_cat, dict(k="5"), "k"),
    (gd.attneave_cat, dict(min_separation=np.nan), "min_separation"),
    (gd.attneave_cat, dict(min_separation=-1), "min_separation"),
    (gd.attneave_cat, dict(min_separation="x"), "min_separation"),
    (gd.dots, dict(k=2.5), "k"),
    (gd.fragments, dict(n_fragments=2.7), "n_fragments"), (gd.fragments, dict(fraction="x"), "fraction"),
    (gd.fragments, dict(min_gap=np.inf), "min_gap"),
    (gd.information, dict(n="x"), "n"), (gd.attneave_cat, dict(n=10**9), "n"),
])
def test_guided_names_bad_parameters(rf, f, kw, name):
    with pytest.raises(InputError, match=rf"^{name}: "):
        f(rf, **kw)


# ---------------------------------------------------------------- sizes


def test_generator_sizes_are_capped():
    with pytest.raises(InputError, match=r"^n: must be <= 1000000"):
        g.radial_frequency(0, n=10**9)
    with pytest.raises(InputError, match=r"^sigma: must be <= 3"):
        g.blob(0, sigma=100)
    with pytest.raises(InputError, match=r"^width: .*harmonics at .* points"):
        g.blob(0, width=1e-4, n=10**6)
    with pytest.raises(InputError, match=r"^samples_per_edge: "):
        g.smooth_closed(SQ, samples_per_edge=10**6)
    with pytest.raises(InputError, match=r"^grid: "):
        g.attneave_polygon(0, grid=10**10)


def test_render_size_is_capped():
    from attneave.stimuli.render import render_silhouette

    for dtype in (None, "uint8"):
        with pytest.raises(InputError, match=r"^size: 1000000 x 1000000 is too large"):
            render_silhouette(SQ, size=10**6, dtype=dtype)


# ---------------------------------------------------------------- render


def test_fit_to_image_refuses_a_vanishing_extent():
    from attneave.stimuli.render import fit_to_image

    with pytest.raises(InputError, match=r"^points: the bounding box spans only"):
        fit_to_image(SQ * 1e-310, size=100)
    with pytest.raises(InputError, match=r"^points: the bounding box spans only"):
        fit_to_image(SQ * 1e-12 + 1e6, size=100)
    with pytest.raises(InputError, match=r"^scale: "):
        fit_to_image(SQ, size=100, scale=1e307)
    out = fit_to_image(SQ * 1e-140, size=100, margin=10)["points"]
    assert np.allclose(out, [(9.5, 9.5), (89.5, 9.5), (89.5, 89.5), (9.5, 89.5)])


@pytest.mark.parametrize("dtype", [None, "uint8"])
def test_crossing_rings_are_refused(dtype):
    from attneave.stimuli.render import coverage, render_silhouette

    with pytest.raises(InputError, match=r"^contour_or_points: rings 0 and 1 cross"):
        render_silhouette([SQ, SQ + 5], size=400, dtype=dtype)
    with pytest.raises(InputError, match=r"^rings: rings 0 and 1 cross"):
        coverage([SQ, SQ + 5], (100, 100))
    with pytest.raises(InputError, match=r"coincide"):
        render_silhouette([SQ, SQ[::-1]], size=100, dtype=dtype)


@pytest.mark.parametrize("dtype", [None, "uint8"])
def test_a_hole_touching_its_outline_is_a_hole(dtype):
    # the hole's first point lies on the outer ring: its nesting must still be found
    from attneave.stimuli.render import render_silhouette

    tri = np.array([(10, 10), (50, 30), (30, 50)], float)
    r = render_silhouette([SQ, tri], size=100, dtype=dtype)
    assert r["area"] == pytest.approx(80 * 80 - 600)
    img = r["img"] / (255.0 if dtype else 1.0)
    assert (1 - img).sum() == pytest.approx(80 * 80 - 600, abs=2)


def test_same_direction_rings_refused_with_orient_false():
    from attneave.stimuli.render import render_silhouette

    inner = (SQ - 50) * 0.5 + 50
    with pytest.raises(InputError, match=r"orient=False .*hole must run opposite"):
        render_silhouette([SQ, inner], size=100, orient=False)
    r = render_silhouette([SQ, inner[::-1]], size=100, orient=False)
    assert abs(r["area"]) == pytest.approx(80 * 80 - 40 * 40)


@pytest.mark.parametrize("shape", [(10,), (2, 2, 2, 2), (4, 4, 2), (4, 4, 5), (0, 4)])
def test_quantisation_refuses_what_is_not_an_image(shape):
    from attneave.stimuli.render import to_uint8, to_uint16

    with pytest.raises(InputError, match=r"^image: expected a \(height, width\)"):
        to_uint8(np.zeros(shape))
    with pytest.raises(InputError, match=r"^image: expected a \(height, width\)"):
        to_uint16(np.zeros(shape))


def test_quantisation_keeps_grey_rgb_and_rgba():
    from attneave.stimuli.render import to_uint8

    for shape in [(3, 4), (3, 4, 3), (3, 4, 4)]:
        assert to_uint8(np.ones(shape)).shape == shape


def test_svg_text_refuses_an_array():
    from attneave.stimuli.render import svg_text

    with pytest.raises(InputError, match=r"^result: "):
        svg_text(SQ)


# ---------------------------------------------------------------- package


def test_shapes_package_re_exports_lazily():
    import attneave.stimuli.shapes as shapes

    assert {"radial_frequency", "superformula", "fourier_shape", "blob", "deform", "deform_at", "move_vertex",
            "attneave_cat", "fragments", "dots", "attneave_curved", "smooth_closed"} <= set(shapes.__all__)
    for name in shapes.__all__:
        assert getattr(shapes, name) is not None
    assert shapes.radial_frequency is g.radial_frequency


def test_user_facing_docstrings_have_parameters():
    import inspect

    import attneave.stimuli.render as render
    import attneave.stimuli.shapes as shapes

    missing = []
    for pkg in (shapes, render):
        for name in pkg.__all__:
            obj = getattr(pkg, name)
            if inspect.isfunction(obj) and list(inspect.signature(obj).parameters):
                if "Parameters\n    ----------" not in (obj.__doc__ or ""):
                    missing.append(f"{pkg.__name__}.{name}")
    assert not missing, missing


def test_guided_stimuli_find_no_extrema_on_a_circle_and_four_on_an_ellipse():
    # a densely drawn circle's surprisal ripples by 1e-10 of its value: noise, not 64 extrema
    from attneave.stimuli.shapes import guided

    th = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    circle = np.c_[200 + 50 * np.cos(th), 200 + 50 * np.sin(th)]
    ellipse = np.c_[200 + 80 * np.cos(th), 200 + 40 * np.sin(th)]
    for f in (guided.dots, guided.attneave_cat):
        assert f(circle, k=4)[-1]["n_extrema"] == 0
        assert f(ellipse, k=4)[-1]["n_extrema"] == 4
