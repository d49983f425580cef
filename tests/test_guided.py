"""Information-guided stimuli: Attneave's cat, peak vs trough fragments, dots.

Must show: the peak and trough fragment sets have equal visible length
(within 1 px) and equal fragment counts, the peak fragments contain the
top surprisal peaks and sit on prominent maxima, the recorded peak-trough
contrast is right and never below its minimum, and the cat never crosses
itself, also on shapes with deep narrow notches.
"""


import numpy as np
import pytest
import scipy.signal

from attneave.stimuli import Contour, InputError
from attneave.stimuli.batch import recipes
from attneave.stimuli.geometry.information import find_peaks, surprisal
from attneave.stimuli.shapes import generators as g
from attneave.stimuli.shapes import guided


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
# (fraction, fragments) per shape: as many peak fragments as the shape has prominent peaks
# (an ellipse has two, these RF patterns four with room for fragments 0.4 L / 6 long)
SIZES = {"polygon": [(0.2, 2), (0.3, 4), (0.4, 6)], "rf": [(0.2, 2), (0.3, 4)], "ellipse": [(0.2, 2)]}
CASES = [(k, c, f, m) for k, c in SHAPES for f, m in SIZES[k]]


def nearly_notched(depth=90.0, width=2.0, bend=6.0, k=3, size=200.0):
    """A square (image px, y down) with `k` deep notches from its top edge, narrower than the
    cat's point spacing at their mouth, whose bottoms bend sideways under a wall."""
    x0 = y0 = 30.0
    top = []
    for x in np.linspace(x0, x0 + size, k + 2)[1:-1]:
        top += [[x, y0], [x, y0 + depth], [x + bend, y0 + depth + bend], [x + width, y0 + 0.6 * depth], [x + 8, y0]]
    return Contour(np.array([[x0, y0]] + top + [[x0 + size, y0], [x0 + size, y0 + size], [x0, y0 + size]]))


def crosses(points):
    """True when the closed polygon through `points` crosses or touches itself (by brute force)."""
    p = np.asarray(points, float)
    m = len(p)
    seg = [(p[i], p[(i + 1) % m]) for i in range(m)]

    def orient(a, b, c):
        return np.sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    for i in range(m):
        for j in range(i + 1, m):
            if j == i + 1 or (i == 0 and j == m - 1):
                continue  # neighbours share a vertex
            (a, b), (c, d) = seg[i], seg[j]
            if orient(a, b, c) != orient(a, b, d) and orient(c, d, a) != orient(c, d, b):
                return True
    return False


@pytest.mark.parametrize("kind,c,fraction,m", CASES, ids=[f"{k}{i}" for i, (k, *_) in enumerate(CASES)])
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


@pytest.mark.parametrize("kind,c,fraction,m", CASES, ids=[f"{k}{i}" for i, (k, *_) in enumerate(CASES)])
def test_peak_fragments_sit_on_prominent_maxima_with_the_recorded_contrast(kind, c, fraction, m):
    out = guided.fragments(c, fraction=fraction, n_fragments=m, n=256, min_gap=6.0)
    p = out["params"]
    u = surprisal(c, n=256).surprisal
    lo, span = u.min(), np.ptp(u)
    # prominences computed here, on three laps of the closed contour
    idx, props = scipy.signal.find_peaks(np.tile(u, 3), prominence=0)
    prom = {int(i) - 256: float(v) / span for i, v in zip(idx, props["prominences"]) if 256 <= i < 512}
    for i, pr in zip(p["peaks_indices"], p["peaks_prominence"]):
        assert i in prom and prom[i] >= p["min_contrast"] == 0.2
        assert pr == pytest.approx(prom[i], abs=1e-6)
    height = lambda which: (u[p[f"{which}_indices"]] - lo) / span  # noqa: E731
    assert p["contrast"] == pytest.approx(height("peaks").min() - height("troughs").max(), abs=1e-9)
    assert p["contrast"] >= 0.2
    np.testing.assert_allclose(p["peaks_height"], height("peaks"), atol=1e-12)
    assert p["length_unit"] == "sample"


def test_shapes_without_enough_prominent_peaks_are_refused():
    # a circle has no peaks at all; an ellipse exactly two (the ends of its major axis)
    th = 2 * np.pi * np.arange(500) / 500
    circle = Contour(np.c_[200 + 100 * np.cos(th), 200 + 100 * np.sin(th)])
    with pytest.raises(InputError, match="constant"):
        guided.fragments(circle, fraction=0.3, n_fragments=5, n=100)
    with pytest.raises(InputError, match="only 2 fragments .* on peaks of prominence >= 0.2"):
        guided.fragments(ellipse(), fraction=0.2, n_fragments=3)
    # a square with rounded corners and one tiny bump: its fifth maximum is 1% of the range
    sq = Contour([[0, 0], [0, 100], [100, 100], [100, 0]]).transformed(2.0, (50, 50)).resample(n=800)
    q = sq.points.copy()
    mid = np.argmin(np.hypot(*(q - [150, 50]).T))  # the middle of one side
    q[mid] += [0, 0.35]
    bumped = Contour(q)
    with pytest.raises(InputError, match="only 4 fragments"):
        guided.fragments(bumped, fraction=0.2, n_fragments=5, min_gap=2)
    # ... which min_contrast = 0 accepts, recording the contrast it would have refused
    low = guided.fragments(bumped, fraction=0.2, n_fragments=5, min_gap=2, min_contrast=0)["params"]
    assert low["contrast"] < 0.2 and min(low["peaks_height"]) < 0.2


def test_min_contrast_is_checked(monkeypatch):
    with pytest.raises(InputError, match="min_contrast"):
        guided.fragments(polygon(1), min_contrast=1.0)
    # troughs sit on a shape's many low points (height 0), so that prominent peaks give the
    # contrast; were the trough centres forced onto high points, the shape is refused
    real = guided.rank_candidates

    def troughs_on_high_points(u, which="peaks", span=0, prominence=None):
        return real(u, "peaks" if which == "troughs" else which, span, prominence)

    monkeypatch.setattr(guided, "rank_candidates", troughs_on_high_points)
    with pytest.raises(InputError, match="min_contrast: the peak fragments sit only"):
        guided.fragments(polygon(1), fraction=0.2, n_fragments=2, min_gap=6.0)


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
    assert p["simple"] and not crosses(pts)


NOTCHED = [nearly_notched(depth, width, bend, k) for depth, width, bend, k in
           [(90, 2, 6, 3), (60, 1, 4, 2), (120, 3, 10, 1), (60, 1, 6, 3), (90, 1, 4, 2)]]


@pytest.mark.parametrize("c", NOTCHED, ids=[f"notched{i}" for i in range(len(NOTCHED))])
@pytest.mark.parametrize("k,sep", [(None, 12.0), (None, None), (8, 12.0)])
def test_cat_of_a_deeply_notched_shape_does_not_cross_itself(c, k, sep):
    assert c.is_simple()
    pts, p = guided.attneave_cat(c, k=k, n=256, min_separation=sep)
    assert not crosses(pts) and p["simple"]
    if k is not None:
        assert len(pts) == k
    # the points are the best-ranked that are compatible: the top surprisal peak is among them
    res = surprisal(c, n=256)
    assert int(np.argmax(res.surprisal)) in p["indices"]
    # and the four corners of the square are (within the spacing) when every peak is asked for
    if k is None:
        for corner in ([30, 30], [230, 30], [230, 230], [30, 230]):
            assert np.hypot(*(pts - corner).T).min() <= 2 * p["ds"]


def test_notched_shapes_make_the_unconstrained_cat_cross():
    # the best-ranked separated points alone (what the cat was before) cross on these shapes,
    # so the test above is not vacuous
    crossed = 0
    for c in NOTCHED:
        res = surprisal(c, n=256)
        order, n_ext = guided.rank_candidates(res.surprisal, "peaks", span=1, prominence=1e-3 * np.ptp(res.surprisal))
        chosen = guided.select_separated(order, res.s, c.perimeter, 8, 12.0)
        crossed += crosses(res.contour.points[np.sort(chosen)])
        _, p = guided.attneave_cat(c, k=8, n=256, min_separation=12.0)
        assert p["passed_over"] or not crosses(res.contour.points[np.sort(chosen)])
    assert crossed >= 2


def test_cat_of_random_attneave_polygons_never_crosses():
    for seed in range(12):
        c = polygon(seed, n_points=16)
        for k in (None, 6):
            pts, _ = guided.attneave_cat(c, k=k, n=256, min_separation=6.0)
            assert not crosses(pts)


def test_dots_on_an_ellipse_sit_at_the_ends_of_the_major_axis():
    c = ellipse(160, 70)
    pts, p = guided.dots(c, k=2, n=400)
    assert p["height"] == pytest.approx([1.0, 1.0], abs=1e-3)  # both ends are the maxima
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


def test_guided_recipe_redraws_low_contrast_shapes_and_records_the_contrast():
    base = {"generator": "attneave_curved", "params": {"n_points": 10}}
    tries = []
    for seed in range(4):
        items = recipes.make("guided", seed, canvas=recipes.Canvas(256, 256, 20), base=base, kinds=["peaks", "troughs"],
                             n_fragments=5, fraction=0.2, min_gap=6, min_contrast=0.2)
        g = items[0].params["guided"]
        assert g["contrast"] >= 0.2 and min(g["peaks_prominence"]) >= 0.2
        assert items[1].params["guided"]["contrast"] == g["contrast"]
        tries.append(items[0].params["base_tries"])
        assert len(items[0].params["base_rejected"]) == tries[-1] - 1
        assert all("fragments" in r or "contrast" in r for r in items[0].params["base_rejected"])
    assert max(tries) > 1  # some base shapes were refused and drawn again


def test_deterministic_base_is_not_redrawn_and_its_repeats_are_named(tmp_path):
    src = tmp_path / "shape.csv"
    c = polygon(3)
    c.to_csv(src)
    base = {"generator": "from_csv", "params": {"path": str(src)}}
    runs = [recipes.make("guided", seed, base=base, kinds=["base", "peaks", "troughs"]) for seed in (1, 2, 3)]
    assert all(r[1].params["base_random"] is False for r in runs)
    for a in runs[1:]:  # different seeds, identical stimuli
        assert a[1].params == runs[0][1].params
    items = recipes.make("guided", 1, kinds=["peaks", "troughs"])
    assert items[0].params["base_random"] is True
    # the batch names such copies once per condition, and only when there are repeats
    from attneave.stimuli.batch.runner import run_batch

    for repeats, named in ((3, True), (1, False)):
        cfg = tmp_path / f"g{repeats}.yaml"
        cfg.write_text(f"seed: 1\nconditions:\n  - name: g\n    recipe: guided\n    repeats: {repeats}\n"
                       f"    params:\n      base: {{generator: from_csv, params: {{path: {src}}}}}\n"
                       f"      kinds: [base, peaks, troughs]\n")
        res = run_batch(cfg, tmp_path / f"out{repeats}")
        assert bool(res.notes) is named
        if named:
            assert len(res.notes) == 1 and "condition 'g': its 3 repeats are identical" in res.notes[0]
    # a fixed base that fails fails at once (drawing it again could not help)
    with pytest.raises(InputError, match="from_csv base: n_fragments"):
        recipes.make("guided", 1, base=base, kinds=["peaks"], n_fragments=40, fraction=0.5, min_gap=0)


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
