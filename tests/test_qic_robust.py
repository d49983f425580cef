"""The robust QIC spline (issue 9): on jagged outlines reduced to N points it
neither loops nor crosses itself, keeps monotone curvature on every segment,
is G2 at every node it does not list in ``corners``, and relaxes few nodes."""

import numpy as np
import pytest
import shapely
from scipy.spatial import cKDTree

from attneave.stimuli.curves.metrics import interior_extrema, segment_slices, segment_turning, self_intersections
from attneave.stimuli.curves.points import bisector_tangents
from attneave.stimuli.curves.polynomial import polynomial_spline
from attneave.stimuli.curves.qic.rule import segment_bulge
from attneave.stimuli.curves.qic.spline import qic_spline
from attneave.stimuli.geometry.contour import Contour


def jagged_outline(rng, n=1500):
    """A dense closed outline with protrusions (radial Fourier series whose
    amplitudes decay slowly up to frequency 16), counter-clockwise on screen."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = np.ones_like(t)
    for k in range(2, 17):
        r += rng.uniform(-1, 1) * 0.6 / k**0.6 * np.cos(k * t + rng.uniform(0, 2 * np.pi))
    r = np.maximum(r, 0.15)
    return Contour(np.c_[200 + 100 * r * np.cos(t), 200 - 100 * r * np.sin(t)])


def node_jumps(curve):
    """|curvature jump| at the node where each segment starts (closed curve),
    from the samples alone."""
    k = curve.curvature
    sl = segment_slices(curve.segment)
    first = np.array([k[q.start] for q in sl])
    last = np.array([k[q.stop - 1] for q in sl])
    return np.abs(first - np.roll(last, 1))


@pytest.mark.parametrize("n", [12, 20, 40])
def test_robust_qic_on_jagged_outlines(n):
    rng = np.random.default_rng(1000 + n)
    corners = nodes = shapes = 0
    dist, dist_cubic = [], []
    while shapes < 10:
        outline = jagged_outline(rng)
        P = outline.resample(n).points
        if not shapely.is_simple(shapely.LinearRing(P)):
            continue
        shapes += 1
        sp = qic_spline(P)
        c = sp.sample(16)
        assert self_intersections(c.x, c.y) == 0
        assert segment_turning(c.s, c.curvature, c.segment, c.theta).max() <= np.pi
        assert interior_extrema(c.curvature, c.segment).sum() == 0
        smooth = np.ones(n, bool)
        smooth[list(sp.corners)] = False
        assert node_jumps(c)[smooth].max() <= 1e-10 * np.abs(c.curvature).max()
        assert len(sp.corner_kinds) == len(sp.corners) and set(sp.corner_kinds) <= {"G0", "G1"}
        # G1 nodes keep the tangent: held at the bisector of the polygon's turn
        th = bisector_tangents(P, True)
        for node, kind in zip(sp.corners, sp.corner_kinds):
            if kind == "G1":
                assert abs(np.angle(np.exp(1j * (sp.theta0[node] - th[node])))) < 1e-12
            else:
                # a G0 corner turns by less than pi: the pieces meeting there
                # do not fold back onto each other (tangents from the samples)
                sl = segment_slices(c.segment)
                t_in, t_out = c.theta[sl[node - 1].stop - 1], c.theta[sl[node].start]
                assert abs(np.angle(np.exp(1j * (t_out - t_in)))) < np.pi - 0.01
        corners += len(sp.corners)
        nodes += n
        tree = cKDTree(outline.resample(spacing=0.5).points)
        dist.append(tree.query(np.c_[c.x, c.y])[0].max())
        cc = polynomial_spline(P, 3).sample(16)
        dist_cubic.append(tree.query(np.c_[cc.x, cc.y])[0].max())
    # issue 9's limits are 10 / 10 / 5 % of the nodes on MPEG-7 outlines at
    # N = 12 / 20 / 40 (benchmarks/validate_spline.py: 8.2 / 7.9 / 4.1 %,
    # 8.6 / 8.5 / 4.2 % before issue 28's constants).
    # These synthetic outlines are more jagged than MPEG-7's at the same N
    # (polygon turns over 90 degrees: 31 % of the nodes at N = 20 against
    # 18 %, 25 % at N = 40 against 10 %): the rule relaxes 7.5 / 7.0 / 3.2 %
    # here, 5.8 / 6.5 / 3.7 % with 40 shapes (before issue 28: 6.7 / 11.5 /
    # 5.8 and 6.0 / 10.2 / 5.8 %)
    assert corners <= {12: 0.1, 20: 0.125, 40: 0.075}[n] * nodes
    # as faithful to the outline as the periodic cubic within 1.25x (on these
    # synthetic outlines 1.07 / 1.17 / 1.09 at N = 12 / 20 / 40 with 40
    # shapes, 1.21 / 1.05 / 1.04 with these 10; before issue 28 1.08 / 1.11 /
    # 1.08 and 1.23 / 1.09 / 1.07, 1.25 / 1.16 / 1.10 with clothoids only)
    assert np.percentile(dist, 90) <= 1.25 * np.percentile(dist_cubic, 90)


def test_sharp_apex_becomes_a_corner_the_sides_run_into():
    # a thin triangle (apex 8 degrees: the polygon turns by 172 there) with
    # equally spaced points on its sides: G2 makes the segments beside the
    # apex share its large curvature and bulge out (by more than SHARP_BULGE,
    # checked below); the robust spline makes the apex a G0 corner, and its
    # curve keeps close to the triangle
    from attneave.stimuli.curves.qic.rule import SHARP_BULGE

    a = np.radians(4)
    V = np.array([[200, 50], [200 - 300 * np.tan(a), 350], [200 + 300 * np.tan(a), 350]])
    P = np.concatenate([V[i] + np.linspace(0, 1, 4, endpoint=False)[:, None] * (V[(i + 1) % 3] - V[i])
                        for i in range(3)])
    tree = cKDTree(Contour(V).resample(spacing=0.25).points)
    pure, robust = qic_spline(P, robust=False), qic_spline(P)
    far = {name: tree.query(np.c_[c.x, c.y])[0].max() for name, c in (("pure", pure.sample(32)),
                                                                     ("robust", robust.sample(32)))}
    assert segment_bulge(pure.sample(64), P)[[0, len(P) - 1]].min() > SHARP_BULGE
    assert dict(zip(robust.corners, robust.corner_kinds))[0] == "G0"
    assert far["robust"] < 0.7 * far["pure"]
    # beside the corner the curve bulges less than SHARP_BULGE mean chords (rule 3d)
    c = robust.sample(64)
    bulge = segment_bulge(c, P)
    assert bulge[[0, len(P) - 1]].max() <= SHARP_BULGE


def test_segment_bulge_of_a_circular_arc():
    # an arc turning by 2b over a chord c lies c tan(b / 2) / 2 from the chord
    # at most; divided by the mean chord of the closed polygon of its points
    b = np.radians(50)
    t = np.linspace(-b, b, 2001)
    x, y = np.sin(t), np.cos(t)
    P = np.array([[x[0], y[0]], [x[-1], y[-1]], [0.0, -2.0]])
    from types import SimpleNamespace

    c = SimpleNamespace(x=x, y=y, segment=np.zeros(t.size, int))
    sides = np.hypot(*(np.roll(P, -1, axis=0) - P).T)
    expected = (1 - np.cos(b)) / sides.mean()
    assert segment_bulge(c, P)[0] == pytest.approx(expected, rel=1e-6)
    chord = 2 * np.sin(b)
    assert 1 - np.cos(b) == pytest.approx(chord * np.tan(b / 2) / 2)


def test_pure_g2_loops_where_robust_does_not():
    # 12 points of a jagged outline (rounded to 0.1 px): the pure G2 spline
    # has a segment turning by more than pi; the robust one does not
    P = np.array([[221.3, 200.0], [326.0, 128.1], [232.9, 83.6], [184.9, 153.4], [97.0, 130.0],
                  [121.8, 203.1], [73.8, 281.9], [136.3, 301.9], [206.3, 258.6], [280.0, 361.8],
                  [239.9, 245.9], [328.4, 266.2]])
    pure = qic_spline(P, robust=False)
    robust = qic_spline(P)
    assert pure.corners == () and pure.g2_error <= 1e-10
    assert pure.max_segment_turn > np.pi and pure.loops == 1
    assert robust.max_segment_turn <= np.pi and robust.loops == 0 and self_intersections(*_xy(robust)) == 0
    # 6 of the 12 nodes: G0 corners at the two spikes (the polygon turns by
    # 161 and 163 degrees there) and beside them, where the segments bulge
    # (before the bulge rules of issue 9's second round: 3 G1 nodes)
    assert 0 < len(robust.corners) <= 6


def _xy(sp):
    c = sp.sample(24)
    return c.x, c.y


def test_robust_equals_pure_where_pure_is_fine():
    t = np.linspace(0, 2 * np.pi, 15, endpoint=False)
    P = np.c_[50 + 20 * np.cos(t) * (1 + 0.2 * np.cos(3 * t)), 50 - 20 * np.sin(t)]
    a, b = qic_spline(P), qic_spline(P, robust=False)
    assert a.corners == () and a.method == "qic" and b.method == "qic-g2"
    np.testing.assert_array_equal(a.theta0, b.theta0)
    np.testing.assert_array_equal(a.length, b.length)
    # one fit passed every check: its own Newton iterations and time, set without copying the result
    assert a.iterations == b.iterations >= 1 and a.seconds > 0


def near(curve, polygon, slack=0.1):
    """Within the polygon's bounding box grown by 10% of its size on every
    side (the acceptance test of attneave_curved)."""
    lo, hi = polygon.min(axis=0), polygon.max(axis=0)
    g = slack * (hi - lo)
    return bool(np.all(curve.min(axis=0) >= lo - g) and np.all(curve.max(axis=0) <= hi + g))


def test_attneave_curved_qic_accepts_what_cubic_accepts():
    # issue 9: smooth_method 'qic' accepts >= 95% of the Attneave polygons that
    # 'cubic' accepts (simple, near the polygon). A small seeded version: of 12
    # polygons cubic accepts, qic accepts at least 11 (the full measure,
    # benchmarks/validate_spline.py --curved 600: 98.0%, one qic curve of 600 crossing itself)
    from attneave.stimuli.shapes.generators import attneave_polygon, smooth_closed

    rng = np.random.default_rng(7)
    cubic = both = 0
    while cubic < 12:
        poly, _ = attneave_polygon(rng, int(rng.integers(6, 20)))
        p = poly.points
        ok = {}
        for method in ("cubic", "qic"):
            c, _ = smooth_closed(p, method=method)
            ok[method] = c.is_simple() and near(c.points, p)
        cubic += ok["cubic"]
        both += ok["cubic"] and ok["qic"]
    assert both >= 11


def test_sample_by_turn_bounds_the_tangent_step():
    t = np.linspace(0, 2 * np.pi, 9, endpoint=False)
    P = np.c_[100 + 40 * np.cos(t) * (1 + 0.3 * np.cos(2 * t)), 100 - 40 * np.sin(t)]
    sp = qic_spline(P)
    c = sp.sample_by_turn(0.05, 64)
    for sl in segment_slices(c.segment):
        th = c.theta[sl]
        assert 3 <= th.size <= 64
        assert np.abs(np.diff(th)).max() <= 0.05 + 1e-12
    # the samples lie on the curve: the same arc lengths through sample()'s evaluator
    dense = sp.sample(2001)
    x = np.interp(c.s, dense.s, dense.x)
    assert np.abs(x - c.x).max() < 1e-3


def test_robust_pieces_between_corners_are_the_open_g2_splines():
    # Between two consecutive G0 corners (no G1 node between them) the robust
    # curve is the pure G2 open spline through that run of points with natural
    # ends, solved afresh here: whatever the rule's fits shared or reused
    from attneave.stimuli.curves.euler import wrap_angle
    from attneave.stimuli.shapes.generators import attneave_polygon

    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(8):
        P = attneave_polygon(rng, int(rng.integers(8, 14)))[0].points
        sp = qic_spline(P, log_aesthetic=False)  # the clothoid fit (its log-aesthetic form: tests in test_qic_lac)
        kinds = dict(zip(sp.corners, sp.corner_kinds))
        g0 = sorted(c for c in kinds if kinds[c] == "G0")
        N = len(P)
        for a, b in zip(g0, g0[1:] + [g0[0] + N]):
            rows = np.arange(a, b + 1) % N
            if b - a < 2 or any(kinds.get(int(r)) == "G1" for r in rows[1:-1]):
                continue
            ref = qic_spline(P[rows], closed=False, robust=False)
            j = [int(np.flatnonzero(sp.start == r)[0]) for r in rows[:-1]]
            np.testing.assert_allclose(wrap_angle(sp.theta0[j] - ref.theta0), 0, atol=1e-8)
            np.testing.assert_allclose(np.abs(sp.k0[j]), np.abs(ref.k0), rtol=1e-7, atol=1e-12)
            np.testing.assert_allclose(sp.length[j], ref.length, rtol=1e-9)
            checked += 1
    assert checked >= 5


def test_crossing_precheck_agrees_with_the_segment_search():
    # the rule tests GEOS's simplicity on the samples as they are (shared end
    # points repeated) and searches segment by segment only when that fails:
    # a figure eight must be found, with the segments that cross, and a
    # circle sampled the same way must not
    from types import SimpleNamespace

    from attneave.stimuli.curves.qic.rule import bad_segments

    def sampled(points, per=5):
        # straight segments between consecutive points, both ends included
        t = np.linspace(0, 1, per)
        P = np.asarray(points, float)
        Q = np.roll(P, -1, axis=0)
        xy = np.concatenate([P[i] + t[:, None] * (Q[i] - P[i]) for i in range(len(P))])
        return SimpleNamespace(x=xy[:, 0], y=xy[:, 1], segment=np.repeat(np.arange(len(P)), per), closed=True)

    a = (np.arange(12) + 0.5) * np.pi / 6
    circle = np.c_[np.cos(a), np.sin(a)]
    eight = np.c_[np.sin(a), np.sin(a) * np.cos(a)]  # crosses itself at the origin
    seg = dict(start=np.arange(12), turn=np.zeros(12), chord_dev=np.zeros(12))
    assert bad_segments(seg, sampled(circle), np.zeros(12)).size == 0
    # the sides through the origin: a from 165 to 195 degrees (segment 5) and
    # from 345 to 15 degrees (segment 11)
    assert bad_segments(seg, sampled(eight), np.zeros(12)).tolist() == [5, 11]
    # a crossing the polygon of the points has too is not the curve's doing: none then, and whether the
    # polygon is simple is asked only once the samples cross
    from attneave.stimuli.curves.qic.rule import crossing_segments

    asked = []
    c = sampled(eight)
    xy = np.c_[c.x, c.y]
    assert crossing_segments(np.arange(12), xy, True, lambda: c, lambda: asked.append(1) or False).size == 0
    assert crossing_segments(np.arange(12), xy, True, lambda: c, lambda: True).tolist() == [5, 11]
    assert asked == [1]
    ring = np.c_[np.cos(a), np.sin(a)][np.r_[0:12, 0]]  # a simple closed curve: GEOS alone answers
    assert crossing_segments(np.arange(12), ring, True, None, lambda: asked.append(2)).size == 0
    assert asked == [1]


def test_segment_bulge_of_an_open_polyline():
    # open points: the mean chord has N - 1 sides; a right-angled vee of
    # sides 3 and 4 sampled straight has zero bulge, a half circle over the
    # first side bulges by half of it
    from types import SimpleNamespace

    P = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]])
    t = np.linspace(0, 1, 11)
    xy = np.concatenate([P[0] + t[:, None] * (P[1] - P[0]), P[1] + t[:, None] * (P[2] - P[1])])
    c = SimpleNamespace(x=xy[:, 0], y=xy[:, 1], segment=np.repeat([0, 1], 11))
    np.testing.assert_allclose(segment_bulge(c, P, closed=False), 0.0, atol=1e-12)
    u = np.linspace(np.pi, 0, 201)
    arc = SimpleNamespace(x=1.5 + 1.5 * np.cos(u), y=-1.5 * np.sin(u), segment=np.zeros(201, int))
    line = SimpleNamespace(x=np.full(11, 3.0), y=4 * t, segment=np.ones(11, int))
    both = SimpleNamespace(x=np.r_[arc.x, line.x], y=np.r_[arc.y, line.y], segment=np.r_[arc.segment, line.segment])
    np.testing.assert_allclose(segment_bulge(both, P, closed=False), [1.5 / 3.5, 0.0], atol=1e-12)


@pytest.mark.parametrize("P", [
    # two six-pointed stars (MPEG-7 device1-1 and device1-5 reduced to 12
    # points, rounded to 0.1 px): the polygon turns by 105-170 degrees at
    # every node and nearly every segment of the G2 spline is bad
    [[136.9, 473.2], [253.4, 287.4], [383.3, 452.8], [299.9, 276.0], [487.0, 238.0], [285.3, 233.0],
     [373.5, 36.4], [261.4, 205.8], [127.4, 42.1], [225.8, 242.1], [5.2, 259.6], [223.2, 272.2]],
    [[131.1, 472.9], [255.6, 296.7], [381.5, 469.9], [291.7, 273.5], [506.1, 254.4], [298.3, 229.8],
     [376.0, 43.4], [255.0, 206.0], [130.4, 41.6], [215.6, 229.2], [4.3, 256.8], [217.3, 274.5]],
])
def test_star_outlines_end_without_crossing(P):
    # with one relaxation per run of bad segments a round, the rule used up its
    # N + 1 rounds here and returned a curve crossing itself; one per stretch
    # of two segments (MAX_RUN) ends with a simple curve
    P = np.array(P)
    assert shapely.is_simple(shapely.LinearRing(P))
    sp = qic_spline(P)
    c = sp.sample(64)
    assert self_intersections(c.x, c.y) == 0
    assert segment_turning(c.s, c.curvature, c.segment, c.theta).max() <= np.pi


def test_isolated_sharp_turn_becomes_a_g0_corner():
    # MPEG-7 bat-4 reduced to 12 points (rounded to 0.1 px): the polygon turns
    # by 108 and 124 degrees at nodes 3 and 9, below CORNER_TURN (126), but
    # by more than 45 degrees more than at their neighbours (30 / 48 and
    # 61 / 2): sharp nodes (a corner of the outline sampled by one point);
    # the segments beside node 3 bulge (by more than SHARP_BULGE), and the
    # rule makes it a G0 corner; node 9's bulge by less, but the segment from
    # node 8 turns by 0.68 rad more than its end nodes and bulges by 0.33 mean
    # chords (step 3e; limits since issue 28: MAX_EXCESS 0.5, EXCESS_BULGE
    # 0.25 times the polygon's mean turn per node over BULGE_TURN, 1.04 / 0.8):
    # node 9, sharp, becomes a G0 corner too
    from attneave.stimuli.curves.qic.rule import CORNER_TURN, polygon_turns, sharp_nodes

    P = np.array([[464.9, 401.2], [474.9, 263.6], [555.7, 107.2], [551.3, 7.4], [402.2, 64.7],
                  [345.6, 212.9], [286.9, 201.2], [246.9, 242.2], [95.1, 231.4], [20.2, 345.6],
                  [190.8, 344.8], [340.4, 350.0]])
    turns = polygon_turns(P, True)
    assert turns[[3, 9]].max() < CORNER_TURN
    assert np.flatnonzero(sharp_nodes(turns)).tolist() == [0, 3, 9]
    sp = qic_spline(P)
    assert dict(zip(sp.corners, sp.corner_kinds)) == {3: "G0", 9: "G0"}
    # with no G0 corners allowed the same rule holds node 3 at its bisector (G1) instead
    assert "G0" not in qic_spline(P, corner_turn=np.pi).corner_kinds


@pytest.mark.parametrize("per_node, bad", [(0.9, [0]), (1.5, [])])
def test_bulge_limits_grow_with_the_polygons_turn_per_node(per_node, bad):
    # issue 28: step 3e's bulge limit is EXCESS_BULGE mean chords times the
    # polygon's mean turn per node over BULGE_TURN, never less than
    # EXCESS_BULGE: a segment turning by MAX_EXCESS + 0.2 rad more than its
    # end nodes and bulging by 1.2 EXCESS_BULGE is bad where the polygon turns
    # by 0.9 BULGE_TURN per node, not where it turns by 1.5 BULGE_TURN (the
    # points then sample the outline sparsely: its own segments bulge)
    from attneave.stimuli.curves.qic.rule import BULGE_TURN, EXCESS_BULGE, MAX_EXCESS, bad_segments, bulge_scale

    n = 8
    turns = np.full(n, per_node * BULGE_TURN)  # all alike: no sharp node (step 3d)
    assert bulge_scale(turns) == pytest.approx(max(1.0, per_node))
    seg = dict(start=np.arange(n), turn=turns.copy(), chord_dev=np.zeros(n))
    seg["turn"][0] += MAX_EXCESS + 0.2
    bulge = np.zeros(n)
    bulge[0] = 1.2 * EXCESS_BULGE
    assert bad_segments(seg, None, np.zeros(n), bulge, (), turns).tolist() == bad
