"""The compiled rasteriser kernel against the numpy path, the reference.

Random simple (star), self-intersecting (random points), multi-ring (holes)
and border-crossing polygons and discs (chord polygons plus circular
segments) are rendered through both paths: float coverage must agree to
1e-12 and 16-bit images exactly. 8-bit images may differ by one level, and
only where 255 * coverage lies within 1e-4 of a half-integer: the numpy
route rounds it after OpenCV's convertScaleAbs, which computes in float32
(and 8-bit images of 65536 pixels or more integrate in float32, which moves
coverage by up to 1e-5, i.e. 2.6e-3 levels), while the kernel rounds the
float64 value. The kernel's 8-bit pixels must equal the
level table applied to rint(255 * the numpy path's float64 coverage).

The other render tests run on whichever path is loaded; CI runs them with
both (``ATTNEAVE_NUMPY_RENDER=1`` forces numpy).
"""

from __future__ import annotations

import os

import numpy as np
import pytest

import attneave.stimuli.render.raster as raster
from attneave.stimuli.render import KERNEL, coverage, disc_coverage, render_dots, render_silhouette

if KERNEL != "c":
    if os.environ.get("ATTNEAVE_REQUIRE_KERNEL") == "1":
        raise RuntimeError("ATTNEAVE_REQUIRE_KERNEL=1 but the compiled kernel is not loaded")
    pytest.skip("the compiled kernel is not built or is disabled", allow_module_level=True)


def both(make):
    """(kernel result, numpy result) of make()."""
    a = make()
    lib, raster.LIB = raster.LIB, None
    try:
        b = make()
    finally:
        raster.LIB = lib
    return a, b


def shapes(rng, h, w):
    """A star, a self-intersecting polygon and a star with a hole, often
    crossing the image's border. The star has a vertex at least every
    quarter turn, at least 1 px from its centre, so it holds the hole (rings
    that cross each other are refused)."""
    n = int(rng.integers(3, 40))
    c = rng.uniform(-10.0, [w + 10.0, h + 10.0])
    t = np.sort(np.concatenate([rng.uniform(0.0, 2.0 * np.pi, n), 0.5 * np.pi * np.arange(4)]))
    r = rng.uniform(1.0, 40.0, n + 4)
    star = np.column_stack([c[0] + r * np.cos(t), c[1] + r * np.sin(t)])
    tangle = rng.uniform(-20.0, [w + 20.0, h + 20.0], (n, 2))
    hole = np.column_stack([c[0] + 0.4 * np.cos(t), c[1] + 0.4 * np.sin(t)])
    return star, tangle, [star, hole]


def check_u8(kern, ref, cov, lut, tie=1e-4):
    """8-bit images of both paths against the float64 coverage `cov`; they
    may differ where 255 * cov is within `tie` of a half-integer."""
    diff = np.abs(kern.astype(int) - ref.astype(int))
    assert diff.max() <= 1
    scaled = 255.0 * cov
    near_half = np.abs(scaled - np.floor(scaled) - 0.5) < tie
    assert np.all(near_half[diff > 0])
    # rint rounds half to even, as the kernel does; a float64 tie between
    # the two paths' round-off (1e-14) is not seen with random coordinates
    assert np.array_equal(kern, lut[np.rint(scaled).astype(int)])


def test_random_polygons_and_discs_agree():
    rng = np.random.default_rng(13)
    levels = np.arange(256.0)
    grey = np.rint(255.0 * 0.9 + (0.2 - 0.9) * levels).astype(np.uint8)
    for _ in range(60):
        h, w = (int(v) for v in rng.integers(4, 70, 2))
        for shp in shapes(rng, h, w):
            cov, ref = both(lambda: coverage(shp, (h, w)))
            np.testing.assert_allclose(cov, ref, rtol=0, atol=1e-12)
            for dt in ("float64", "uint16"):
                a, b = both(lambda: render_silhouette(shp, shape=(h, w), dtype=dt, figure=0.2, ground=0.9)["img"])
                np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 if dt == "float64" else 0)
            a, b = both(lambda: render_silhouette(shp, shape=(h, w), dtype="uint8", figure=0.2, ground=0.9)["img"])
            check_u8(a, b, ref, grey)
            a, b = both(lambda: render_silhouette(shp, shape=(h, w), dtype="uint8")["img"])
            check_u8(a, b, ref, 255 - levels.astype(np.uint8))
        centres = rng.uniform(-5.0, [w + 5.0, h + 5.0], (4, 2))
        radius = float(rng.uniform(0.3, 20.0))
        cov, ref = both(lambda: disc_coverage(centres, radius, (h, w)))
        np.testing.assert_allclose(cov, ref, rtol=0, atol=1e-12)
        a, b = both(lambda: render_dots(centres, radius, shape=(h, w), dtype="uint8")["img"])
        check_u8(a, b, ref, 255 - levels.astype(np.uint8))


def test_rgb_and_float32_route_agree():
    """RGB 8-bit images (one pass per channel) and a 512 x 512 spiky star,
    which the numpy path integrates in float32."""
    rng = np.random.default_rng(5)
    t = np.sort(rng.uniform(0.0, 2.0 * np.pi, 500))
    r = rng.uniform(50.0, 250.0, 500)
    star = np.column_stack([256.0 + r * np.cos(t), 256.0 + r * np.sin(t)])
    cov = both(lambda: coverage(star, (512, 512)))[1]
    a, b = both(lambda: render_silhouette(star, size=512, dtype="uint8")["img"])
    # float32 integration: coverage within 1e-5, i.e. 255 * 1e-5 levels
    tie = 255.0 * 1e-5
    check_u8(a, b, cov, np.arange(255, -1, -1).astype(np.uint8), tie)
    fig, ground = (1.0, 0.25, 0.0), (0.0, 0.5, 1.0)
    a, b = both(lambda: render_silhouette(star, size=512, dtype="uint8", figure=fig, ground=ground)["img"])
    for ch in range(3):
        lut = np.rint(255.0 * ground[ch] + (fig[ch] - ground[ch]) * np.arange(256.0)).astype(np.uint8)
        check_u8(a[..., ch], b[..., ch], cov, lut, tie)


def test_shapes_off_the_image_add_nothing():
    """Wholly above, below, left or right of the image: all ground, area 0."""
    sq = np.array([(0.0, 0.0), (5.0, 0.0), (5.0, 5.0), (0.0, 5.0)])
    for shift in ((0.0, -9.0), (0.0, 12.0), (-9.0, 0.0), (12.0, 0.0)):
        out = render_silhouette(sq + shift, shape=(6, 7), dtype="uint8")
        assert out["area"] == 0.0 and np.all(out["img"] == 255)


def test_band_seams_of_wide_images_agree():
    """8-bit images of wide shapes are painted in bands of a few rows (the
    band buffer holds 128 KB of deposits: 18-27 rows here); shapes crossing
    many band seams
    and the image's border must agree with the numpy path, area included."""
    rng = np.random.default_rng(21)
    levels = np.arange(256.0)
    for _ in range(4):
        h, w = int(rng.integers(60, 160)), int(rng.integers(600, 900))
        cx, cy = rng.uniform([0.0, 0.0], [w, h])
        n = 60
        t = np.sort(rng.uniform(0.0, 2.0 * np.pi, n))
        r = rng.uniform(0.2, 1.0, n)[:, None] * [w / 2, h]
        star = np.column_stack([cx + r[:, 0] * np.cos(t), cy + r[:, 1] * np.sin(t)])
        hole = np.column_stack([cx + 0.2 * r[:, 0] * np.cos(t), cy + 0.2 * r[:, 1] * np.sin(t)])
        for shp in (star, [star, hole]):
            cov = both(lambda: coverage(shp, (h, w)))[1]
            a, b = both(lambda: render_silhouette(shp, shape=(h, w), dtype="uint8"))
            check_u8(a["img"], b["img"], cov, 255 - levels.astype(np.uint8))
            assert a["area"] == pytest.approx(b["area"], rel=1e-12, abs=1e-9)


def test_rectangle_across_bands_has_its_analytic_coverage():
    """An axis-aligned rectangle's pixel coverage is the product of its
    overlaps with the pixel's row and column intervals, through every band."""
    h, w = 150, 700
    x0, x1, y0, y1 = 10.3, 600.7, 5.2, 140.65
    rect = np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)])
    out = render_silhouette(rect, size=(w, h), dtype="uint8")

    def overlap(lo, hi, n):
        c = np.arange(n)
        return np.clip(np.minimum(hi, c + 0.5) - np.maximum(lo, c - 0.5), 0.0, 1.0)

    cov = np.outer(overlap(y0, y1, h), overlap(x0, x1, w))
    assert np.array_equal(out["img"], (255 - np.rint(255.0 * cov)).astype(np.uint8))
    assert out["area"] == pytest.approx((x1 - x0) * (y1 - y0), rel=1e-12)


def test_plain_rings_take_the_same_route_as_any_other_input():
    """One float64 ring goes straight to the kernel, which checks its points:
    a repeated closing point, duplicates, a Contour-like object or a list
    give the same image, rings and area, and bad points the usual error."""
    from attneave.stimuli.errors import InputError

    ring = np.array([(3.2, 2.5), (20.7, 4.1), (17.0, 19.4), (5.5, 15.0)])
    ref = render_silhouette(ring.tolist(), size=24, dtype="uint8")
    for given in (ring, np.vstack([ring, ring[:1]]), np.vstack([ring[:1], ring]),
                  type("C", (), {"points": ring})()):
        out = render_silhouette(given, size=24, dtype="uint8")
        assert np.array_equal(out["img"], ref["img"]) and out["area"] == pytest.approx(ref["area"])
        assert out["dtype"] == "uint8" and out["shape"] == (24, 24)
    assert np.array_equal(render_silhouette(ring, size=24, dtype="uint8")["rings"][0], ring)
    with pytest.raises(InputError, match="row 2"):
        render_silhouette(np.array([(0.0, 0.0), (5.0, 0.0), (np.nan, 5.0)]), size=8, dtype="uint8")
    with pytest.raises(InputError, match="3 distinct"):
        render_silhouette(np.array([(0.0, 0.0), (5.0, 0.0), (0.0, 0.0), (5.0, 0.0)]), size=8, dtype="uint8")
