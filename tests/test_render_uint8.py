"""The 8-bit rendering path (float32 integration, per-thread scratch buffers),
the orientation of single rings and both ways of entering deposits.

References: the float64 path (exact to about 1e-13, itself checked against
shapely and analytic areas in test_render.py), shoelace and shapely areas.
Images here have at least 65536 pixels, so that 8-bit renders take the
float32 route.
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
import shapely

from attneave.stimuli.geometry.polyline import shoelace
from attneave.stimuli.render import coverage, render_silhouette
from attneave.stimuli.render.raster import FLOAT32_MIN_PIXELS, sum_dtype
from attneave.stimuli.shapes.generators import fourier_shape

SHAPE = (300, 320)  # 96000 pixels


def smooth(seed, centre=(160.0, 150.0), r0=110.0):
    pts = fourier_shape(np.random.default_rng(seed), r0=r0, amplitude=0.25, n=400)[0].points
    return pts - pts.mean(axis=0) + centre


def spiky(seed, n=300, centre=(160.0, 150.0)):
    """Star with independent random radii: a long, jagged boundary."""
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0.0, 2.0 * np.pi, n))
    r = rng.uniform(40.0, 140.0, n)
    return np.column_stack([centre[0] + r * np.cos(t), centre[1] - r * np.sin(t)])


def agrees_with_float64(u8, cov):
    """u8 (black on white) is 255 - rint(255 cov) except, by one level, where
    255 cov lies within 0.01 of a tie (float32 sums are good to ~1e-5)."""
    ref = 255.0 - np.rint(255.0 * cov)
    diff = np.abs(u8.astype(float) - ref)
    near_tie = np.abs((255.0 * cov) % 1.0 - 0.5) < 0.01
    return diff.max() <= 1 and not np.any(diff[~near_tie])


def test_large_8bit_images_integrate_in_float32_small_and_others_in_float64():
    assert FLOAT32_MIN_PIXELS <= SHAPE[0] * SHAPE[1]
    assert sum_dtype(np.uint8, *SHAPE) is np.float32
    assert sum_dtype(np.uint8, 16, 24) is np.float64
    assert sum_dtype(np.float64, *SHAPE) is np.float64
    assert sum_dtype(np.uint16, *SHAPE) is np.float64


@pytest.mark.parametrize("make", [smooth, spiky])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_uint8_matches_the_float64_path_and_the_exact_area(make, seed):
    p = make(seed)
    res = render_silhouette(p, shape=SHAPE, dtype="uint8")
    cov = coverage(p, SHAPE)
    assert agrees_with_float64(res["img"], cov)
    # the area is still computed in float64, exactly
    assert math.isclose(res["area"], abs(shoelace(p)), rel_tol=1e-12)
    # and the 8-bit image loses at most half a level per boundary pixel
    boundary = np.count_nonzero((cov > 0) & (cov < 1))
    assert abs((255 - res["img"].astype(float)).sum() / 255 - abs(shoelace(p))) <= boundary / 510


def test_uint8_hole_and_border_crossing_match_float64():
    outer = smooth(3, centre=(40.0, 280.0), r0=150.0)  # runs off the left and bottom
    hole = shapely.Point(60.0, 250.0).buffer(40.0, quad_segs=32)
    shape = shapely.Polygon(outer).difference(hole)
    u8 = render_silhouette(shape, shape=SHAPE, dtype="uint8")["img"]
    cov = coverage(shape, SHAPE)
    assert 0 < cov[:, 0].sum() and 0 < cov[-1].sum()  # it does cross two borders
    assert agrees_with_float64(u8, cov)
    clipped = shape.intersection(shapely.box(-0.5, -0.5, SHAPE[1] - 0.5, SHAPE[0] - 0.5))
    assert math.isclose(cov.sum(), clipped.area, rel_tol=1e-9)


def test_uint8_self_intersection_by_the_nonzero_rule_matches_float64():
    # a pentagram: the centre has winding 2 and must be filled, not left empty
    k = np.arange(5) * 4 * np.pi / 5
    star = np.column_stack([160 + 140 * np.sin(k), 150 - 140 * np.cos(k)])
    u8 = render_silhouette(star, shape=SHAPE, dtype="uint8")["img"]
    assert u8[150, 160] == 0
    assert agrees_with_float64(u8, coverage(star, SHAPE))


def test_scratch_buffers_leave_no_trace_between_calls():
    # a spiky shape (the accumulator is cleared with one fill) and a smooth
    # one (cleared by scatter) in turn, at two sizes: each render must
    # equal a first render of the same shape
    a, b = spiky(4), smooth(5)
    first = render_silhouette(a, shape=SHAPE, dtype="uint8")["img"]
    render_silhouette(b, shape=SHAPE, dtype="uint8")
    render_silhouette(b * 2.0, shape=(640, 600), dtype="uint8")
    again = render_silhouette(a, shape=SHAPE, dtype="uint8")["img"]
    assert np.array_equal(first, again)
    f1 = render_silhouette(b, shape=SHAPE)["img"]
    render_silhouette(a, shape=SHAPE)
    assert np.array_equal(f1, render_silhouette(b, shape=SHAPE)["img"])


def test_threads_render_independently():
    shapes = [spiky(s) if s % 2 else smooth(s) for s in range(8)]
    serial = [render_silhouette(p, shape=SHAPE, dtype="uint8")["img"] for p in shapes]
    with ThreadPoolExecutor(4) as pool:
        parallel = list(pool.map(lambda p: render_silhouette(p, shape=SHAPE, dtype="uint8")["img"], shapes * 3))
    assert all(np.array_equal(img, serial[i % 8]) for i, img in enumerate(parallel))


@pytest.mark.parametrize("centre", [(160.0, 150.0), (20.0, 290.0)])  # inside; across two edges
def test_either_orientation_gives_the_same_image_and_the_clipped_area(centre):
    # one ring is rasterised as given (only its area's sign depends on the
    # orientation); reference: shapely's area of the shape inside the image
    p = smooth(6, centre=centre)
    image = shapely.box(-0.5, -0.5, SHAPE[1] - 0.5, SHAPE[0] - 0.5)
    want = shapely.Polygon(p).intersection(image).area
    ccw, cw = (render_silhouette(q, shape=SHAPE, dtype="uint8") for q in (p, p[::-1]))
    assert np.array_equal(ccw["img"], cw["img"])
    for res in (ccw, cw):
        assert math.isclose(res["area"], want, rel_tol=1e-12)


def test_sparse_and_dense_deposits_both_give_exact_pixels():
    # few pieces for their box (a large smooth ring: deposits entered twice)
    # and many (a small spiky star: entered once, columns differenced); both
    # against shapely's area of the shape in every pixel
    def exact(poly, shape):
        h, w = shape
        jj, ii = np.meshgrid(np.arange(w), np.arange(h))
        return shapely.area(shapely.intersection(poly, shapely.box(jj - 0.5, ii - 0.5, jj + 0.5, ii + 0.5)))

    t = np.linspace(0.0, 2.0 * np.pi, 90, endpoint=False)
    ring = np.column_stack([60.3 + 50.0 * np.cos(t), 55.1 - 50.0 * np.sin(t)])  # ~490 pieces, 100^2 box
    star = spiky(7, n=60, centre=(20.0, 18.0)) * 0.12 + [0.8, 1.7]  # ~250 pieces, 20^2 box
    for p, shape in ((ring, (112, 120)), (star, (40, 44))):
        assert np.abs(coverage(p, shape) - exact(shapely.Polygon(p), shape)).max() < 1e-9
