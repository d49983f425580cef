"""Rendering: exact area coverage checked against geometry that holds without the code.

References used here are independent of the rasteriser: shoelace areas,
shapely intersections of the shape with each pixel square, analytic disc and
annulus areas, and a 16 x 16 point-sampling scanline reference written below.
"""

from __future__ import annotations

import math
import os
import shutil
import subprocess
import xml.etree.ElementTree as ET

import cv2
import numpy as np
import pytest
import shapely

from attneave.stimuli.errors import InputError
from attneave.stimuli.render import (
    coverage,
    disc_coverage,
    fit_to_image,
    render_dots,
    render_fragments,
    render_outline,
    render_silhouette,
    svg_text,
    to_uint8,
    to_uint16,
    write_png,
    write_svg,
)

# ---------------------------------------------------------------------------
# independent references


def shoelace(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * abs(float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)))


def perimeter(p):
    return float(np.sum(np.hypot(*(np.roll(p, -1, axis=0) - p).T)))


def supersampled(p, shape, k=16):
    """Fraction of k x k sub-pixel centres inside polygon `p` (even-odd rule).

    Pixel (i, j) is [j-0.5, j+0.5] x [i-0.5, i+0.5]; its sample centres are
    at j - 0.5 + (s + 0.5) / k. Each sample row is intersected with every edge
    (half-open in y, so vertices count once), crossings are paired along the
    row, and the samples of each span are counted per pixel with difference
    arrays. Independent of the area-accumulation rasteriser under test.
    """
    h, w = shape
    q = np.roll(p, -1, axis=0)
    y0, y1 = p[:, 1], q[:, 1]
    lo, hi = np.minimum(y0, y1), np.maximum(y0, y1)
    # sample rows m with centre ym = (m + 0.5)/k - 0.5 in [lo, hi)
    m0 = np.clip(np.ceil(k * (lo + 0.5) - 0.5), 0, h * k).astype(int)
    m1 = np.clip(np.ceil(k * (hi + 0.5) - 0.5), 0, h * k).astype(int)
    cnt = m1 - m0
    e = np.repeat(np.arange(len(p)), cnt)
    m = np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt) + m0[e]
    ys = (m + 0.5) / k - 0.5
    t = (ys - y0[e]) / (y1[e] - y0[e])
    xs = p[e, 0] + t * (q[e, 0] - p[e, 0])
    order = np.lexsort((xs, m))
    m, xs = m[order], xs[order]
    assert np.all(m[0::2] == m[1::2]), "odd number of crossings on a sample row"
    row = m[0::2] // k
    ka = np.clip(np.ceil(k * (xs[0::2] + 0.5) - 0.5), 0, w * k).astype(int)
    kb = np.clip(np.ceil(k * (xs[1::2] + 0.5) - 0.5), 0, w * k).astype(int)
    d = np.zeros((h, w + 2))
    for kk, sign in ((kb, 1.0), (ka, -1.0)):
        np.add.at(d, (row, kk // k), sign * (kk % k - k))
        np.add.at(d, (row, kk // k + 1), -sign * (kk % k))
    return np.cumsum(d, axis=1)[:, :w] / (k * k)


def pixel_intersections(geom, shape):
    """Exact area of `geom` inside every pixel square, by shapely."""
    h, w = shape
    jj, ii = np.meshgrid(np.arange(w), np.arange(h))
    boxes = shapely.box(jj - 0.5, ii - 0.5, jj + 0.5, ii + 0.5)
    return shapely.area(shapely.intersection(geom, boxes))


def random_star(rng, n, centre, rmin, rmax):
    """Random simple (star-shaped) polygon, counter-clockwise on screen."""
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = rng.uniform(rmin, rmax, n)
    return np.column_stack([centre[0] + r * np.cos(t), centre[1] - r * np.sin(t)])


# ---------------------------------------------------------------------------
# the Must-show


def test_random_polygons_offset_and_l1_against_supersampling():
    rng = np.random.default_rng(20240603)
    shape = (512, 512)
    for trial in range(20):
        n = int(rng.choice([3, 5, 12, 60, 200, 500, 800]))
        rmax = rng.uniform(40, 240)
        c = rng.uniform(256 - (250 - rmax), 256 + (250 - rmax), 2)
        p = random_star(rng, n, c, rng.uniform(0.2, 0.9) * rmax, rmax)
        cov = coverage(p, shape)
        L = perimeter(p)
        offset = (cov.sum() - shoelace(p)) / L
        assert abs(offset) <= 0.02, (trial, offset)
        assert abs(offset) < 1e-9, (trial, offset)  # in fact exact to round-off
        ref = supersampled(p, shape)
        l1 = np.abs(cov - ref).sum() / L
        assert l1 <= 0.05, (trial, n, l1)


def test_supersampled_reference_agrees_with_matplotlib_point_test():
    # the reference itself, checked against matplotlib's point-in-polygon
    from matplotlib.path import Path as MplPath

    rng = np.random.default_rng(3)
    p = random_star(rng, 9, (12.3, 11.7), 4.0, 11.0)
    ref = supersampled(p, (24, 24), k=8)
    s = (np.arange(8 * 24) + 0.5) / 8 - 0.5
    X, Y = np.meshgrid(s, s)
    inside = MplPath(p).contains_points(np.column_stack([X.ravel(), Y.ravel()]))
    mpl = inside.reshape(24 * 8, 24 * 8).reshape(24, 8, 24, 8).mean(axis=(1, 3))
    assert np.abs(ref - mpl).max() <= 1 / 64 + 1e-12  # at most one sample on an edge


def test_opencv_line_aa_dilates_and_we_do_not():
    # informative: the same two measures fail for OpenCV's antialiased fill
    rng = np.random.default_rng(5)
    ours, theirs, l1 = [], [], []
    for _ in range(5):
        p = random_star(rng, 300, (256, 256), 120, 220)
        img = np.zeros((512, 512), np.uint8)
        cv2.fillPoly(img, [np.round(p * 16).astype(np.int32)], 255, cv2.LINE_AA, shift=4)
        theirs.append((img.sum() / 255.0 - shoelace(p)) / perimeter(p))
        ours.append((coverage(p, (512, 512)).sum() - shoelace(p)) / perimeter(p))
        l1.append(np.abs(img / 255.0 - supersampled(p, (512, 512))).sum() / perimeter(p))
    assert min(theirs) > 0.3  # OpenCV's LINE_AA fill grows the shape by ~0.5 px
    assert min(l1) > 0.05
    assert max(abs(o) for o in ours) < 0.02


# ---------------------------------------------------------------------------
# exactness pixel by pixel


def test_pixel_coverage_equals_shapely_intersection_areas():
    rng = np.random.default_rng(11)
    shape = (40, 56)
    for _ in range(4):
        p = random_star(rng, 40, rng.uniform(-5, 60, 2), 5, 30)  # often crosses the border
        exact = pixel_intersections(shapely.Polygon(p), shape)
        assert np.abs(coverage(p, shape) - exact).max() < 1e-9


def test_polygon_with_hole_matches_shapely_either_orientation():
    rng = np.random.default_rng(2)
    outer = random_star(rng, 30, (30, 30), 20, 28)
    hole = random_star(rng, 20, (31, 29), 5, 9)
    exact = pixel_intersections(shapely.Polygon(outer, [hole]), (60, 60))
    for h in (hole, hole[::-1]):
        for o in (outer, outer[::-1]):
            assert np.abs(coverage([o, h], (60, 60)) - exact).max() < 1e-9
    # a shapely polygon is accepted directly
    assert np.abs(coverage(shapely.Polygon(outer, [hole]), (60, 60)) - exact).max() < 1e-9


def test_transpose_and_integer_shift_symmetry():
    # the rasteriser treats x and y differently (cuts columns first,
    # accumulates down): swapping them must transpose the image exactly
    rng = np.random.default_rng(7)
    p = random_star(rng, 100, (40.3, 33.1), 10, 30)
    a = coverage(p, (80, 80))
    assert np.abs(coverage(p[:, ::-1], (80, 80)) - a.T).max() < 1e-12
    b = coverage(p + [3, -2], (80, 80))
    assert np.abs(b[:-2, 3:] - a[2:, :-3]).max() < 1e-12


def test_additivity_of_two_halves():
    rng = np.random.default_rng(9)
    poly = shapely.Polygon(random_star(rng, 80, (50, 50), 20, 45))
    cut = shapely.box(-100, -100, 51.37, 200)
    a, b = poly.intersection(cut), poly.difference(cut)
    whole = coverage(poly, (100, 100))
    assert np.abs(coverage(a, (100, 100)) + coverage(b, (100, 100)) - whole).max() < 1e-9


# ---------------------------------------------------------------------------
# simple shapes with known answers


def test_pixel_aligned_square_covers_exactly_its_pixels():
    sq = np.array([(2.5, 3.5), (5.5, 3.5), (5.5, 4.5), (2.5, 4.5)])
    cov = coverage(sq, (8, 8))
    want = np.zeros((8, 8))
    want[4, 3:6] = 1.0
    assert np.array_equal(cov, want)


def test_half_pixel_offset_square_gives_half_on_edges():
    sq = np.array([(2.0, 3.5), (5.0, 3.5), (5.0, 6.5), (2.0, 6.5)])
    cov = coverage(sq, (10, 10))
    assert np.allclose(cov[4:7, 2], 0.5) and np.allclose(cov[4:7, 5], 0.5)
    assert np.allclose(cov[4:7, 3:5], 1.0)
    assert np.isclose(cov.sum(), 9.0) and cov[:4].sum() == 0 and cov[7:].sum() == 0


def test_shape_crossing_the_border_is_clipped():
    shape = (30, 40)
    image = shapely.box(-0.5, -0.5, 39.5, 29.5)
    tri = np.array([(-25.0, 10.0), (60.0, -20.0), (30.0, 55.0)])  # crosses all four edges
    cov = coverage(tri, shape)
    assert math.isclose(cov.sum(), shapely.Polygon(tri).intersection(image).area, rel_tol=1e-12)
    big = np.array([(-100.0, -100.0), (100.0, -100.0), (100.0, 100.0), (-100.0, 100.0)])
    assert np.array_equal(coverage(big, shape), np.ones(shape))
    far = big / 10 + 500
    assert np.array_equal(coverage(far, shape), np.zeros(shape))


def test_polygonised_disc_area():
    R = 100.0
    t = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    p = np.column_stack([256.2 + R * np.cos(t), 255.7 - R * np.sin(t)])
    assert math.isclose(coverage(p, (512, 512)).sum(), math.pi * R * R, rel_tol=1e-3)


def test_exact_disc_coverage():
    R = 37.3
    cov = disc_coverage([(100.3, 120.7)], R, (256, 256))
    assert math.isclose(cov.sum(), math.pi * R * R, rel_tol=1e-12)
    # a quarter disc in the corner: centre on the image corner (-0.5, -0.5)
    cov = disc_coverage([(-0.5, -0.5)], 20.0, (64, 64))
    assert math.isclose(cov.sum(), math.pi * 400.0 / 4, rel_tol=1e-12)
    # inside one pixel
    cov = disc_coverage([(3.0, 4.0)], 0.3, (8, 8))
    assert math.isclose(cov[4, 3], math.pi * 0.09, rel_tol=1e-12) and cov.sum() == cov[4, 3]
    # r = 0.7 centred on a pixel: disc minus the four caps beyond the pixel edges
    r, a = 0.7, 0.5
    cap = r * r * math.acos(a / r) - a * math.sqrt(r * r - a * a)
    cov = disc_coverage([(3.0, 4.0)], r, (8, 8))
    assert math.isclose(cov[4, 3], math.pi * r * r - 4 * cap, rel_tol=1e-12)
    # pixel by pixel against a very fine polygon
    t = np.linspace(0, 2 * np.pi, 20000, endpoint=False)
    c, R = np.array([10.37, 9.81]), 6.4
    fine = coverage(np.column_stack([c[0] + R * np.cos(t), c[1] + R * np.sin(t)]), (20, 20))
    assert np.abs(disc_coverage([c], R, (20, 20)) - fine).max() < 1e-5


def test_outline_of_circle_has_annulus_area():
    R, w = 150.0, 3.0
    t = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    p = np.column_stack([256 + R * np.cos(t), 256 - R * np.sin(t)])
    res = render_outline(p, w, size=512, figure=1.0, ground=0.0)
    assert math.isclose(res["img"].sum(), 2 * math.pi * R * w, rel_tol=1e-3)
    assert math.isclose(res["img"].sum(), res["area"], rel_tol=1e-9)
    assert res["img"][256, 256] == 0.0 and res["img"][256, 256 + 150] == 1.0
    assert res["join"] == "round" and res["closed"] and res["quad_segs"] >= 8


def test_fragments_are_stroked_rectangles_and_overlaps_counted_once():
    a = np.array([(10.0, 20.0), (50.0, 20.0)])
    res = render_fragments([a], 2.0, size=(64, 40), figure=1.0, ground=0.0)
    assert math.isclose(res["img"].sum(), 40.0 * 2.0, rel_tol=1e-12)
    assert res["img"][20, 30] == 1.0 and res["img"][20, 9] == 0.0
    b = np.array([(30.0, 5.0), (30.0, 35.0)])
    res = render_fragments([a, b], 2.0, size=(64, 40), figure=1.0, ground=0.0)
    assert math.isclose(res["img"].sum(), 80.0 + 60.0 - 4.0, rel_tol=1e-12)
    round_caps = render_fragments([a], 2.0, size=(64, 40), cap="round", figure=1.0, ground=0.0)
    assert math.isclose(round_caps["img"].sum(), 80.0 + math.pi, rel_tol=1e-3)


def test_dots_are_exact_discs_clipped_at_the_border():
    centres = np.array([(10.0, 10.0), (30.2, 12.7), (-1.0, 20.0)])
    res = render_dots(centres, 2.5, size=(48, 32), figure=1.0, ground=0.0)
    # third dot: centre 0.5 px left of the image edge x = -0.5, so what shows
    # is the circular cap beyond a chord at distance 0.5 from the centre
    cap = 2.5**2 * math.acos(0.5 / 2.5) - 0.5 * math.sqrt(2.5**2 - 0.25)
    visible = 2 * math.pi * 2.5**2 + cap
    assert math.isclose(res["img"].sum(), visible, rel_tol=1e-12)
    assert res["radius"] == 2.5 and res["centers"].shape == (3, 2)


# ---------------------------------------------------------------------------
# images, colours, files


def test_figure_ground_grey_and_rgb_and_integer_paths_agree():
    rng = np.random.default_rng(4)
    p = random_star(rng, 50, (32, 30), 10, 25)
    cov = coverage(p, (64, 64))
    res = render_silhouette(p, shape=(64, 64), figure=0.2, ground=0.9)
    assert np.allclose(res["img"], 0.9 + cov * (0.2 - 0.9))
    assert res["figure"] == 0.2 and res["ground"] == 0.9 and res["size"] == (64, 64)
    u16 = render_silhouette(p, shape=(64, 64), figure=0.2, ground=0.9, dtype="uint16")["img"]
    assert u16.dtype == np.uint16 and np.array_equal(u16, to_uint16(res["img"]))
    # 8 bits: coverage rounded to 1/255 first, so a pixel may move by one level
    u8 = render_silhouette(p, shape=(64, 64), figure=0.2, ground=0.9, dtype="uint8")["img"]
    assert u8.dtype == np.uint8 and np.abs(u8.astype(int) - to_uint8(res["img"])).max() <= 1
    assert np.all(u8[cov == 0] == to_uint8(np.full((1, 1), 0.9))[0, 0]) and np.all(u8[cov == 1] == 51)
    for f, g in ((0.0, 1.0), (1.0, 0.0)):  # black and white: 255 * coverage, rounded
        b = render_silhouette(p, shape=(64, 64), figure=f, ground=g, dtype="uint8")["img"]
        ink = np.rint(255 * cov)
        assert np.array_equal(b, ink if f == 1.0 else 255 - ink)
    rgb = render_silhouette(p, shape=(64, 64), figure=(1.0, 0.0, 0.0), ground=0.5)
    assert rgb["img"].shape == (64, 64, 3) and rgb["ground"] == (0.5, 0.5, 0.5)
    assert np.allclose(rgb["img"][..., 0], 0.5 + 0.5 * cov)
    assert np.allclose(rgb["img"][..., 1], 0.5 - 0.5 * cov)
    rgb8 = render_silhouette(p, shape=(64, 64), figure=(1.0, 0.0, 0.0), ground=0.5, dtype="uint8")
    assert np.abs(rgb8["img"].astype(int) - to_uint8(rgb["img"])).max() <= 1


def test_png_round_trips_8_and_16_bit(tmp_path):
    rng = np.random.default_rng(6)
    p = random_star(rng, 60, (40, 30), 10, 28)
    img = render_silhouette(p, size=(80, 60))["img"]
    for depth, q in ((8, to_uint8), (16, to_uint16)):
        path = write_png(tmp_path / f"a{depth}.png", img, bit_depth=depth)
        back = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
        assert back.dtype == q(img).dtype and np.array_equal(back, q(img))
    assert np.abs(to_uint16(img) / 65535.0 - img).max() <= 0.5 / 65535 + 1e-12
    # RGB is written in RGB order (OpenCV reads back BGR)
    red = render_silhouette(p, size=(80, 60), figure=(1.0, 0.0, 0.0), ground=0.0)
    back = cv2.imread(str(write_png(tmp_path / "red.png", red)), cv2.IMREAD_UNCHANGED)
    assert back[..., 2].max() == 255 and back[..., 0].max() == 0
    # same image, same bytes; no temporary files left behind
    write_png(tmp_path / "b8.png", img)
    assert (tmp_path / "a8.png").read_bytes() == (tmp_path / "b8.png").read_bytes()
    assert not [f for f in tmp_path.iterdir() if f.name.startswith(".")]


def _path_points(d):
    subpaths = []
    for part in d.split("M")[1:]:
        nums = [float(v) for v in part.replace("L", " ").replace("Z", " ").split()]
        subpaths.append(np.array(nums).reshape(-1, 2))
    return subpaths


def test_svg_is_well_formed_and_in_pixel_coordinates(tmp_path):
    ns = {"s": "http://www.w3.org/2000/svg"}
    rng = np.random.default_rng(8)
    p = random_star(rng, 30, (40.25, 30.5), 8, 25)
    res = render_silhouette(p, size=(80, 60), figure=0.0, ground=1.0)
    path = write_svg(tmp_path / "s.svg", res)
    root = ET.parse(path).getroot()
    assert root.get("width") == "80" and root.get("height") == "60"
    assert root.get("viewBox") == "0 0 80 60"
    g = root.find("s:g", ns)
    assert g.get("transform") == "translate(0.5 0.5)"
    (pts,) = _path_points(g.find("s:path", ns).get("d"))
    assert np.abs(pts - p).max() < 1e-6
    # pixel (i, j) of the PNG is [j, j+1] x [i, i+1] in SVG user units:
    # a point at a pixel centre (j, i) lands at (j + 0.5, i + 0.5)
    assert root.find("s:rect", ns).get("fill") == "#ffffff"
    assert g.find("s:path", ns).get("fill") == "#000000"
    # deterministic text
    write_svg(tmp_path / "t.svg", res)
    assert (tmp_path / "s.svg").read_bytes() == (tmp_path / "t.svg").read_bytes()
    # outlines, fragments and dots
    out = render_outline(p, 2.0, size=(80, 60), join="bevel")
    el = ET.fromstring(svg_text(out)).find("s:g/s:path", ns)
    assert el.get("stroke-width") == "2" and el.get("stroke-linejoin") == "bevel"
    assert el.get("fill") == "none" and el.get("d").endswith("Z")
    # mitre joins: the exact stroke region, filled (SVG's mitre fallback differs)
    out = render_outline(p, 2.0, size=(80, 60), join="miter")
    el = ET.fromstring(svg_text(out)).find("s:g/s:path", ns)
    assert el.get("fill") == "#000000" and el.get("stroke") is None
    rings = _path_points(el.get("d"))
    area = sum(shoelace(r) * (1 if k == 0 else -1) for k, r in enumerate(rings))
    assert len(rings) == 2 and math.isclose(area, out["area"], rel_tol=1e-6)
    fr = render_fragments([p[:5], p[10:14]], 1.5, size=(80, 60))
    el = ET.fromstring(svg_text(fr)).find("s:g/s:path", ns)
    assert el.get("stroke-linecap") == "butt" and len(_path_points(el.get("d"))) == 2
    dots = render_dots(p[:4], 1.25, size=(80, 60))
    circles = ET.fromstring(svg_text(dots)).findall("s:g/s:circle", ns)
    assert len(circles) == 4 and float(circles[0].get("cx")) == pytest.approx(p[0, 0], abs=1e-6)
    # plain rings with a size
    write_svg(tmp_path / "r.svg", [p], size=(80, 60))
    assert ET.parse(tmp_path / "r.svg").getroot().get("width") == "80"


def test_fit_to_image_centres_and_keeps_margin():
    pts = np.array([(0.0, 0.0), (4.0, 0.0), (4.0, 2.0), (0.0, 2.0)])
    r = fit_to_image(pts, size=(100, 80), margin=10)
    q = r["points"]
    # width limits: 100 - 2*10 = 80 px for 4 units -> scale 20
    assert r["scale"] == 20.0
    assert np.allclose(q.min(axis=0), [9.5, 19.5]) and np.allclose(q.max(axis=0), [89.5, 59.5])
    assert np.allclose((q.min(axis=0) + q.max(axis=0)) / 2, [49.5, 39.5])
    assert np.allclose(pts * r["scale"] + r["offset"], q)
    assert fit_to_image(pts, 64)["margin"] == pytest.approx(6.4)
    assert fit_to_image(pts, 64, scale=2.0)["scale"] == 2.0


@pytest.mark.parametrize(
    "call",
    [
        lambda: coverage([(0, 0), (1, float("nan")), (1, 1)], (4, 4)),
        lambda: coverage([(0, 0), (1, 1), (0, 0), (1, 1)], (4, 4)),
        lambda: coverage([(0, 0), (1, 0), (1, 1)], (0, 4)),
        lambda: render_silhouette([(0, 0), (1, 0), (1, 1)]),
        lambda: render_silhouette([(0, 0), (1, 0), (1, 1)], size=4, shape=(4, 4)),
        lambda: render_silhouette([(0, 0), (1, 0), (1, 1)], size=4, figure=2.0),
        lambda: render_silhouette([(0, 0), (1, 0), (1, 1)], size=4, dtype="int8"),
        lambda: render_outline([(0, 0), (1, 0), (1, 1)], -1.0, size=4),
        lambda: render_outline([(0, 0), (1, 0), (1, 1)], 1.0, size=4, join="pointy"),
        lambda: render_fragments(np.zeros((3, 2)), 1.0, size=4),
        lambda: render_dots([(1, 1)], 0.0, size=4),
        lambda: fit_to_image([(1, 1), (1, 1), (1, 1)], 10),
        lambda: to_uint8(np.array([[0.5, 1.5]])),
    ],
)
def test_bad_input_raises_input_error(call):
    with pytest.raises(InputError):
        call()


def test_bad_output_raises_input_error(tmp_path):
    img = np.zeros((4, 4))
    with pytest.raises(InputError, match="bit_depth"):
        write_png(tmp_path / "a.png", img, bit_depth=12)
    with pytest.raises(InputError, match="does not exist"):
        write_png(tmp_path / "missing" / "a.png", img)
    assert list(tmp_path.iterdir()) == []


def test_self_intersecting_ring_fills_both_lobes_in_every_path():
    bowtie = np.array([(2.0, 2.0), (20.0, 14.0), (20.0, 2.0), (2.0, 14.0)])  # crosses at (11, 8)
    lobes = shapely.make_valid(shapely.Polygon(bowtie))  # the two triangles
    assert math.isclose(lobes.area, 2 * 0.5 * 12 * 9)
    exact = pixel_intersections(lobes, (16, 24))
    cov = coverage(bowtie, (16, 24))
    bad = np.zeros((16, 24), bool)
    bad[7:10, 10:13] = True  # only the pixels at the crossing may differ
    assert np.abs(cov - exact)[~bad].max() < 1e-9
    assert math.isclose(cov.sum(), lobes.area, abs_tol=1.0)
    f = render_silhouette(bowtie, shape=(16, 24))["img"]
    u8 = render_silhouette(bowtie, shape=(16, 24), dtype="uint8")["img"]
    assert np.allclose(f, 1.0 - cov) and np.array_equal(u8, 255 - np.rint(255 * cov))


def test_svg_rasterised_by_librsvg_matches_png(tmp_path):
    if shutil.which("rsvg-convert") is None:
        if os.environ.get("ATTNEAVE_REQUIRE_RSVG") == "1":
            pytest.fail("rsvg-convert (Debian librsvg2-bin) is required here but not installed")
        pytest.skip("librsvg's rsvg-convert not installed")
    rng = np.random.default_rng(1)
    p = random_star(rng, 40, (40.3, 30.2), 10, 25)
    for res in (
        render_silhouette(p, size=(80, 60)),
        render_outline(p, 3.0, size=(80, 60), join="mitre"),
        render_fragments([p[:8], p[15:25]], 2.0, size=(80, 60), cap="square"),
    ):
        write_png(tmp_path / "a.png", res)
        write_svg(tmp_path / "a.svg", res)
        subprocess.run(["rsvg-convert", "-o", str(tmp_path / "b.png"), str(tmp_path / "a.svg")], check=True)
        a = cv2.imread(str(tmp_path / "a.png"), cv2.IMREAD_GRAYSCALE).astype(float)
        b = cv2.imread(str(tmp_path / "b.png"), cv2.IMREAD_GRAYSCALE).astype(float)
        assert a.shape == b.shape
        assert np.abs(a - b).mean() < 0.5  # grey levels; a one-pixel shift gives > 4
        assert abs(a.sum() - b.sum()) / 255 < 0.01 * perimeter(p)


def test_huge_and_far_dots_are_clipped_exactly():
    # a disc much larger than the image, centred outside it: the visible part
    # is the image minus the part outside the circle (checked with a fine polygon)
    c, R = np.array([-300.3, 20.2]), 330.0
    cov = disc_coverage([c], R, (40, 50))
    t = np.linspace(0, 2 * np.pi, 200000, endpoint=False)
    fine = coverage(np.column_stack([c[0] + R * np.cos(t), c[1] + R * np.sin(t)]), (40, 50))
    assert np.abs(cov - fine).max() < 1e-5
    assert np.array_equal(disc_coverage([(1e6, 1e6)], 5.0, (8, 8)), np.zeros((8, 8)))
    full = disc_coverage([(3.5, 3.5)], 1e5, (8, 8))
    assert np.allclose(full, 1.0)
