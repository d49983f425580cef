"""Information-guided stimuli: Attneave's cat, peak vs trough fragments, dots.

Must show: the peak and trough fragment sets have equal visible length
(within 1 px) and equal fragment counts, and the peak fragments contain the
top surprisal peaks.
"""

import numpy as np
import pytest

from stimuli import Contour, InputError
from stimuli.shapes import generators as g
from stimuli.shapes import guided
from stimuli.batch import recipes
from stimuli.geometry.information import find_peaks, surprisal


def rng(seed=0):
    return np.random.default_rng(seed)


def polygon(seed, n_points=12):
    c, _ = g.attneave_polygon(rng(seed), n_points=n_points)
    return c.transformed(4.0, (56.0, 56.0))


def rf(seed):
    c, _ = g.radial_frequency(rng(seed), r0=150, frequency=[3, 5], amplitude=[0.12, 0.06], n=720)
    return c.transformed(1.0, (256.0, 256.0))


def ellipse(a=160.0, b=70.0, n=2000):
    th = 2 * np.pi * np.arange(n) / n
    return Contour(np.c_[256 + a * np.cos(th), 256 + b * np.sin(th)])


def length(q):
    return float(np.hypot(*np.diff(q, axis=0).T).sum())


def arc_centre_distance(t1, t2):
    d = abs(t1 - t2) % 1.0
    return min(d, 1 - d)


SHAPES = [("polygon", polygon(1)), ("polygon", polygon(4)), ("rf", rf(0)), ("rf", rf(2)),
          ("ellipse", ellipse())]


@pytest.mark.parametrize("kind,c", SHAPES, ids=[f"{k}{i}" for i, (k, _) in enumerate(SHAPES)])
@pytest.mark.parametrize("fraction,m", [(0.2, 2), (0.3, 4), (0.4, 6)])
def test_peak_and_trough_fragments_match(kind, c, fraction, m):
    out = guided.fragments(c, fraction=fraction, n_fragments=m, n=256, min_gap=6.0)
    p = out["params"]
    L = c.perimeter
    lp = [length(q) for q in out["peaks"]]
    lt = [length(q) for q in out["troughs"]]
    # equal fragment counts and equal visible length (here to 1e-6 px; the must-show is 1 px)
    assert len(lp) == len(lt) == m
    assert abs(sum(lp) - sum(lt)) < 1.0
    np.testing.assert_allclose(lp, fraction * L / m, rtol=1e-9)
    np.testing.assert_allclose(lt, fraction * L / m, rtol=1e-9)
    assert sum(lp) == pytest.approx(fraction * L, rel=1e-9)
    # every fragment lies on the contour
    for q in out["peaks"] + out["troughs"]:
        _, _, dist = c.project(q)
        assert dist.max() < 1e-6
    # fragments of one set do not overlap or touch: centres >= length + gap apart
    sep = (fraction * L / m + 6.0) / L
    for which in ("peaks", "troughs"):
        t = p[f"{which}_t"]
        for i in range(m):
            for j in range(i + 1, m):
                assert arc_centre_distance(t[i], t[j]) >= sep - 1e-12
    # the peak set carries more information than the trough set
    assert np.mean(p["peaks_surprisal"]) > np.mean(p["troughs_surprisal"])


@pytest.mark.parametrize("kind,c", SHAPES[:4], ids=[f"{k}{i}" for i, (k, _) in enumerate(SHAPES[:4])])
def test_peak_fragments_contain_the_top_peaks(kind, c):
    m, fraction, gap = 4, 0.25, 6.0
    out = guided.fragments(c, fraction=fraction, n_fragments=m, n=256, min_gap=gap)
    res = surprisal(c, n=256)
    peaks, _ = find_peaks(res.surprisal, closed=True)
    assert len(peaks) > 0
    centres = out["params"]["peaks_indices"]
    # the highest peak is always a fragment centre
    assert int(peaks[0]) in centres
    # a higher peak is left out only if a chosen fragment already covers its
    # neighbourhood (closer than a fragment length plus the gap)
    L = c.perimeter
    sep = (fraction * L / m + gap) / L
    lowest = min(res.surprisal[i] for i in centres)
    for pk in peaks:
        if res.surprisal[pk] > lowest and int(pk) not in centres:
            assert min(arc_centre_distance(res.t[pk], res.t[i]) for i in centres) < sep
    # and each fragment contains its peak
    for q, i in zip(out["peaks"], sorted(centres)):
        _, _, dist = Contour(q, closed=False).project(res.contour.points[i][None])
        assert dist[0] < 1e-6


def test_fragments_on_a_circle_still_match():
    th = 2 * np.pi * np.arange(500) / 500
    c = Contour(np.c_[200 + 100 * np.cos(th), 200 + 100 * np.sin(th)])
    out = guided.fragments(c, fraction=0.3, n_fragments=5, n=100)
    assert len(out["peaks"]) == len(out["troughs"]) == 5
    assert sum(map(length, out["peaks"])) == pytest.approx(sum(map(length, out["troughs"])), abs=1e-6)


def test_fragments_that_cannot_fit():
    with pytest.raises(InputError, match="do not fit"):
        guided.fragments(polygon(0), fraction=0.9, n_fragments=10, min_gap=50)


def test_cat_of_a_polygon_finds_its_corners():
    c = polygon(2, n_points=10)
    pts, p = guided.attneave_cat(c, k=10, n=512)
    ds = p["ds"]
    # each chosen point lies within one sample spacing of a distinct vertex
    d = np.hypot(*(pts[:, None, :] - c.points[None, :, :]).transpose(2, 0, 1))
    nearest = d.argmin(axis=1)
    assert len(set(nearest.tolist())) == 10
    assert d.min(axis=1).max() <= ds + 1e-9
    # in contour order
    assert np.all(np.diff(p["t"]) > 0)
    assert p["simple"]


def test_dots_on_an_ellipse_sit_at_the_ends_of_the_major_axis():
    c = ellipse(160, 70)
    pts, p = guided.dots(c, k=2, n=400)
    # curvature is largest (furthest from the mean turn) at (256 +- 160, 256)
    ends = np.array([[96.0, 256.0], [416.0, 256.0]])
    got = pts[np.argsort(pts[:, 0])]
    ds = c.perimeter / 400
    assert np.abs(got - ends).max() <= ds
    lows, pl = guided.dots(c, k=2, which="troughs", n=400)
    assert np.mean(pl["surprisal"]) < np.mean(p["surprisal"])


def test_guided_recipe_items_and_drawing():
    canvas = recipes.Canvas(256, 256, 20)
    kinds = ["base", "cat", "peaks", "troughs", "dots", "dots_troughs"]
    items = recipes.make("guided", 4, canvas=canvas, kinds=kinds, k=8, n_fragments=3, fraction=0.3,
                         min_separation=10.0)
    assert [i.suffix for i in items] == kinds
    assert [i.parent_suffix for i in items] == [None] + ["base"] * 5
    base = items[0].contour
    for it in items:
        np.testing.assert_array_equal(it.contour.points, base.points)  # the full contour everywhere
    peaks, troughs = items[2], items[3]
    assert peaks.params["guided"]["visible_length"] == troughs.params["guided"]["visible_length"]
    assert len(peaks.draw["polylines"]) == len(troughs.draw["polylines"]) == 3
    style = recipes.Style(line_width=2.0, dot_radius=3.0)
    imgs = {it.suffix: 1 - recipes.draw_item(it, style, canvas) for it in items}
    # dots: exact discs, eight of them, apart (the renderer is exact for
    # discs that do not overlap)
    pts = items[4].draw["points"]
    d = np.hypot(*(pts[:, None] - pts[None]).transpose(2, 0, 1))
    assert len(pts) == 8 and d[np.triu_indices(8, 1)].min() > 6.0
    assert imgs["dots"].sum() == pytest.approx(8 * np.pi * 9, rel=1e-9)
    # fragments with flat caps: about length x width of ink (joins at corners add a little)
    vis = peaks.params["guided"]["visible_length"]
    for s in ("peaks", "troughs"):
        assert imgs[s].sum() == pytest.approx(vis * 2.0, rel=0.05)
    assert recipes.item_svg(items[2], style, canvas) == recipes.item_svg(items[2], style, canvas)


def test_guided_recipe_is_deterministic():
    a = recipes.make("guided", 9, kinds=["peaks", "troughs"])
    b = recipes.make("guided", 9, kinds=["peaks", "troughs"])
    assert [i.parent_suffix for i in a] == [None, None]
    for x, y in zip(a, b):
        assert x.params == y.params
        for q1, q2 in zip(x.draw["polylines"], y.draw["polylines"]):
            np.testing.assert_array_equal(q1, q2)


def test_draw_item_silhouette_coverage_is_the_contour_area():
    canvas = recipes.Canvas(200, 160, 12)
    for name in ("attneave_polygon", "radial_frequency", "blob"):
        [it] = recipes.make(name, 5, canvas=canvas)
        img = recipes.draw_item(it, recipes.Style(), canvas)
        assert img.shape == (160, 200)
        assert float((1 - img).sum()) == pytest.approx(it.contour.area, rel=1e-9)
    # colours: an RGB figure on grey
    style = recipes.Style(figure=[1.0, 0.0, 0.0], ground=0.5)
    img = recipes.draw_item(it, style, canvas)
    assert img.shape == (160, 200, 3)
    svg = recipes.item_svg(it, style, canvas)
    assert svg.startswith("<?xml") and 'width="200"' in svg and "#ff0000" in svg
