"""The information model: surprisal on shapes whose answer is known."""

import numpy as np
import pytest

from attneave.stimuli import Contour, InputError, find_peaks, surprisal, surprisal_paper, surprisal_vonmises
from attneave.stimuli.geometry.information import surprisal_from_points

MODELS = ["paper", "vonmises"]


def ellipse(a=150.0, b=60.0, n=3000, cx=256.0, cy=256.0):
    th = 2 * np.pi * np.arange(n) / n
    return np.c_[cx + a * np.cos(th), cy + b * np.sin(th)]


def dented(n=1440, phase=0.0):
    """A circle of radius 100 with a smooth inward dent centred at angle 0."""
    th = phase + 2 * np.pi * np.arange(n) / n
    d = np.angle(np.exp(1j * th))
    r = 100 - 25 * np.exp(-(d**2) / (2 * 0.12**2))
    return np.c_[200 + r * np.cos(th), 200 + r * np.sin(th)]


@pytest.mark.parametrize("model", MODELS)
def test_circle_surprisal_constant(model):
    th = 2 * np.pi * np.arange(4000) / 4000
    c = Contour(np.c_[256 + 100 * np.cos(th), 256 + 100 * np.sin(th)])
    r = surprisal(c, n=80, model=model)
    assert np.ptp(r.surprisal) < 1e-9 * max(1, abs(r.surprisal).max())
    assert len(r.peaks) == 0
    assert np.all(r.curvature > 0)
    assert r.curvature == pytest.approx(np.full(80, 0.01), rel=0.005)


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("transform", ["none", "reverse", "mirror", "roll"])
def test_ellipse_peaks_at_major_axis_ends(model, transform):
    p = ellipse()
    if transform == "reverse":
        p = p[::-1]
    elif transform == "mirror":
        p = np.c_[p[:, 0], 512 - p[:, 1]]
    elif transform == "roll":
        p = np.roll(p, 777, axis=0)
    r = surprisal(Contour(p), n=120, model=model)
    top2 = r.contour.points[np.argsort(r.surprisal)[-2:]]
    cy = 256.0
    ends = np.array([[256 - 150, cy], [256 + 150, cy]])
    for e in ends:
        assert np.min(np.hypot(*(top2 - e).T)) < 150 * 2 * np.pi / 120  # within one sample
    assert len(r.peaks) == 2
    assert np.allclose(np.sort(r.contour.points[r.peaks, 0]), [106, 406], atol=8)


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("order", ["ccw", "cw", "mirror", "roll"])
def test_dent_is_concave_and_most_informative(model, order):
    p = dented()
    if order == "cw":
        p = p[::-1]
    elif order == "mirror":
        p = np.c_[p[:, 0], 400 - p[:, 1]]
    elif order == "roll":
        p = np.roll(p, 500, axis=0)
    r = surprisal(Contour(p), n=144, model=model)
    pts = r.contour.points
    dent = np.argmin(np.hypot(*(pts - [275, 200]).T))
    assert r.curvature[dent] < 0
    far = np.hypot(*(pts - [200, 200]).T) > 99
    assert np.all(r.curvature[far] > 0)
    assert np.argmax(r.surprisal) == dent
    assert r.peaks[0] == dent


@pytest.mark.parametrize("model", MODELS)
def test_concave_more_informative_than_convex_at_equal_magnitude(model):
    a = np.array([0.05, 0.3, 1.0, 2.0])
    n = 50
    if model == "paper":
        conc = surprisal_paper(-a, ds=3.0, n=n)
        conv = surprisal_paper(a, ds=3.0, n=n)
    else:
        conc = surprisal_vonmises(-a, n=n)
        conv = surprisal_vonmises(a, n=n)
    assert np.all(conc > conv)


@pytest.mark.parametrize("model", MODELS)
def test_square_corners_finite_and_top(model):
    sq = Contour([[10, 10], [10, 110], [110, 110], [110, 10]])
    r = surprisal(sq, n=40, model=model)
    assert np.all(np.isfinite(r.surprisal))
    top4 = r.contour.points[np.argsort(r.surprisal)[-4:]]
    corners = {(10, 10), (10, 110), (110, 110), (110, 10)}
    assert {tuple(np.round(p).astype(int)) for p in top4} == corners
    assert len(r.peaks) == 4


def test_paper_form_formula_and_bits():
    a = np.linspace(-np.pi, np.pi, 13)
    u = surprisal_paper(a, ds=10, n=10, A=0.25, b=2)
    assert np.allclose(u, -np.log(0.25) - 2 * 100 * np.cos(a - 2 * np.pi / 10), rtol=0, atol=1e-12)
    assert np.allclose(surprisal_paper(a, 10, 10, bits=True), surprisal_paper(a, 10, 10) / np.log(2))
    u4 = surprisal_paper(a, ds=2, n=10, closed=False)
    assert np.allclose(u4, -np.log(0.25) - 4 * np.cos(a))


def test_vonmises_is_a_normalised_density():
    for b in (0.5, 4.0, 50.0):
        x = np.linspace(-np.pi, np.pi, 20001)[:-1]
        p = np.exp(-surprisal_vonmises(x, n=12, b=b))
        assert p.sum() * (2 * np.pi / len(x)) == pytest.approx(1.0, rel=1e-9)
        # its mode is the mean turn of a closed 12-gon
        assert x[np.argmax(p)] == pytest.approx(2 * np.pi / 12, abs=1e-3)


@pytest.mark.parametrize("unit", ["sample", "perimeter", "radius", "px"])
def test_fast_path_matches_full_path(unit):
    r = surprisal(Contour(ellipse(n=3000)), n=512, length_unit=unit)
    fast = surprisal_from_points(r.contour.points, length_unit=unit)
    assert r.params["length_unit"] == unit
    # the full path: ds in the unit is 1, 1/n, L/(n R) with R the equal-area radius (an
    # ellipse's sqrt(a b), here of its 3000-gon), L/n; the fast path takes L and the area
    # from the resampled 512-gon itself
    for res, poly in ((r.surprisal, Contour(ellipse(n=3000))), (fast, r.contour)):
        ds = poly.perimeter / 512
        ds_unit = {"sample": 1.0, "perimeter": 1 / 512, "radius": ds / np.sqrt(poly.area / np.pi), "px": ds}[unit]
        assert np.allclose(res, surprisal_paper(r.turning_angle, ds_unit, 512), rtol=0, atol=1e-12)
    assert r.params["ds_in_unit"] == pytest.approx(
        {"sample": 1.0, "perimeter": 1 / 512, "radius": 690.4 / 512 / np.sqrt(150 * 60), "px": 690.4 / 512}[unit],
        rel=1e-4)


def test_find_peaks_circular_and_ranked():
    u = np.array([5.0, 1, 1, 3, 1, 1, 4, 1])
    idx, prom = find_peaks(u, closed=True)
    assert idx.tolist() == [0, 6, 3]
    idx_open, _ = find_peaks(u, closed=False)
    assert idx_open.tolist() == [0, 6, 3]
    assert find_peaks(np.ones(10))[0].size == 0


def test_bad_parameters():
    with pytest.raises(InputError):
        surprisal_paper(0.1, ds=1, n=10, A=0)
    with pytest.raises(InputError):
        surprisal(ellipse(n=100), model="bayes")


@pytest.mark.parametrize("prominence", [float("nan"), -1.0, float("inf")])
def test_bad_prominence_is_an_error_not_a_silent_peak_set(prominence, tmp_path, capsys):
    # NaN used to find no peaks at all and -1 every wiggle, both with exit status 0
    u = np.cos(np.linspace(0, 4 * np.pi, 64, endpoint=False))
    with pytest.raises(InputError, match="prominence"):
        find_peaks(u, prominence=prominence)
    from attneave.cli import main

    th = 2 * np.pi * np.arange(100) / 100
    src = tmp_path / "c.csv"
    src.write_text("x,y\n" + "".join(f"{100 + 60 * np.cos(t)},{100 + 30 * np.sin(t)}\n" for t in th))
    out = tmp_path / "o.csv"
    assert main(["surprisal", str(src), "-o", str(out), f"--prominence={prominence}"]) == 2
    assert "prominence" in capsys.readouterr().err and not out.exists()


@pytest.mark.parametrize(
    "model, kw",
    [("paper", dict(A=float("inf"))), ("paper", dict(b=float("inf"))), ("vonmises", dict(b=float("inf"))),
     ("vonmises", dict(b=float("nan")))],
)
def test_infinite_A_or_b_is_an_error(model, kw):
    # A = inf gave -inf in every row and b = inf NaN (von Mises), with exit status 0
    with pytest.raises(InputError):
        surprisal(ellipse(n=100), n=20, model=model, **kw)


def notched_polygon():
    """A polygon with corners, straight sides and a concave notch (image pixels)."""
    return np.array([[40, 40], [40, 200], [110, 200], [120, 120], [130, 200], [220, 200], [220, 40], [150, 60]], float)


@pytest.mark.parametrize("unit", ["sample", "perimeter", "radius"])
def test_one_shape_at_four_scales_has_the_same_surprisal(unit):
    # scale about a point that is not the origin, so that the coordinates change too
    p = notched_polygon()
    runs = [surprisal(Contour(100 + f * (p - 100)), n=120, length_unit=unit) for f in (0.25, 1.0, 2.0, 4.0)]
    for r in runs[1:]:
        np.testing.assert_allclose(r.surprisal, runs[0].surprisal, rtol=0, atol=1e-9)
        np.testing.assert_array_equal(r.peaks, runs[0].peaks)
        assert r.params["length_unit"] == unit
    # ... while the paper's literal pixels scale the contrast with the square of the size
    px = [surprisal(Contour(100 + f * (p - 100)), n=120, length_unit="px").surprisal for f in (1.0, 2.0)]
    assert np.ptp(px[1]) == pytest.approx(4 * np.ptp(px[0]), rel=1e-9)
    assert px[1].min() < 0


def test_default_unit_is_eq3_of_the_turning_angle_and_positive():
    # ds = 1: u = -ln A' - b cos(a - 2 pi/n), inside -ln A' -+ b, so > 0 for b < ln 4
    r = surprisal(Contour(notched_polygon()), n=90)
    assert r.params["length_unit"] == "sample" and r.params["ds_in_unit"] == 1.0
    np.testing.assert_allclose(r.surprisal, np.log(4) - np.cos(r.turning_angle - 2 * np.pi / 90), rtol=0, atol=1e-12)
    assert r.surprisal.min() > np.log(4) - 1 - 1e-12 and r.surprisal.max() < np.log(4) + 1
    # a negative value needs b > ln(1/A') and a turn close to the mean turn (straight sides)
    r3 = surprisal(Contour(notched_polygon()), n=90, b=3.0)
    straight = np.abs(r3.turning_angle) < 1e-9
    assert straight.sum() > 40
    np.testing.assert_allclose(r3.surprisal[straight], np.log(4) - 3 * np.cos(2 * np.pi / 90), rtol=0, atol=1e-9)
    assert np.log(4) - 3 - 1e-12 <= r3.surprisal.min() < 0


def test_bad_length_unit():
    with pytest.raises(InputError, match="length_unit"):
        surprisal(ellipse(n=100), length_unit="inch")
    with pytest.raises(InputError, match="radius"):
        surprisal(Contour(ellipse(n=100), closed=False), length_unit="radius")


def test_cli_length_unit_choices_and_column(tmp_path, capsys):
    from attneave.cli import main
    from attneave.stimuli.geometry.information import LENGTH_UNITS

    src = tmp_path / "c.csv"
    src.write_text("x,y\n" + "".join(f"{x},{y}\n" for x, y in notched_polygon()))
    for unit in LENGTH_UNITS:
        out = tmp_path / f"{unit}.csv"
        assert main(["surprisal", str(src), "-o", str(out), "-n", "40", "--length-unit", unit]) == 0
        text = out.read_text().splitlines()
        assert text[0].endswith(",length_unit") and all(line.endswith("," + unit) for line in text[1:])
    assert main(["surprisal", str(src), "-o", str(tmp_path / "d.csv")]) == 0
    assert (tmp_path / "d.csv").read_text().splitlines()[1].endswith(",sample")
    with pytest.raises(SystemExit) as exc:
        main(["surprisal", str(src), "-o", str(tmp_path / "e.csv"), "--length-unit", "inch"])
    assert exc.value.code == 2 and "length-unit" in capsys.readouterr().err
