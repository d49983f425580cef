"""Contour extraction from images: sub-pixel accuracy, curvature, clean-up, batches.

Ground truth comes from analytic shapes rendered with exact area coverage
(``attneave.stimuli.render.coverage``: each pixel's grey level is the exact fraction
of its square inside the shape), so every tolerance below is a property of
the extraction, not of the renderer.

Curvature error is reported as an NRMSE:

    NRMSE = sqrt(mean_i (k_est_i - k_true_i)^2) / (max k_true - min k_true)

over the extracted contour's points i, where k_true_i is the analytic
curvature at the point of the true curve nearest to point i (the same arc
position) and max/min run over the whole true curve. For a circle, whose
true curvature is constant, the denominator is its curvature 1/R instead.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.signal
from scipy.spatial import cKDTree

from attneave.stimuli.errors import InputError
from attneave.stimuli.extraction import (
    contour_curvature,
    curvature_peaks,
    default_sigma,
    describe,
    extract,
    extract_contours,
    read_image,
)
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.render import coverage, render_silhouette, write_png

N = 512


# ----------------------------------------------------------------- true shapes
def ellipse(a, b, cx, cy, rot=0.0, m=100_000):
    """Dense points of an ellipse and the exact curvature at each."""
    u = np.linspace(0, 2 * np.pi, m, endpoint=False)
    x, y = a * np.cos(u), b * np.sin(u)
    k = a * b / (a * a * np.sin(u) ** 2 + b * b * np.cos(u) ** 2) ** 1.5
    c, s = np.cos(rot), np.sin(rot)
    return np.c_[cx + c * x - s * y, cy + s * x + c * y], k


def radial_frequency(r0, amp, freq, cx, cy, phase=0.0, m=100_000):
    """Dense points of r = r0 (1 + amp cos(freq (theta - phase))) and its exact curvature."""
    th = np.linspace(0, 2 * np.pi, m, endpoint=False)
    arg = freq * (th - phase)
    r = r0 * (1 + amp * np.cos(arg))
    r1 = -r0 * amp * freq * np.sin(arg)
    r2 = -r0 * amp * freq**2 * np.cos(arg)
    k = (r * r + 2 * r1 * r1 - r * r2) / (r * r + r1 * r1) ** 1.5
    return np.c_[cx + r * np.cos(th), cy + r * np.sin(th)], k


def true_maxima(k):
    """Indices of the maxima of a dense, periodic, noise-free curvature."""
    n = len(k)
    idx, _ = scipy.signal.find_peaks(np.tile(k, 3), prominence=1e-3 * np.ptp(k))
    return idx[(idx >= n) & (idx < 2 * n)] - n


class Truth:
    """Nearest-point lookup on a dense true curve."""

    def __init__(self, pts, k):
        self.pts, self.k = pts, k
        seg = np.hypot(*np.diff(np.vstack([pts, pts[:1]]), axis=0).T)
        self.s = np.concatenate([[0.0], np.cumsum(seg)])[:-1]
        self.length = seg.sum()
        self.tree = cKDTree(pts)

    def nearest(self, q):
        return self.tree.query(q)

    def nrmse(self, contour, k_est):
        _, j = self.nearest(contour.points)
        err = np.sqrt(np.mean((k_est - self.k[j]) ** 2))
        span = np.ptp(self.k)
        return err / (span if span > 1e-9 * self.k.mean() else self.k.mean())

    def arc_gap(self, q, i_true):
        """Distance along the true curve from the true point i_true to the nearest of points q."""
        _, j = self.nearest(q)
        d = np.abs(self.s[j] - self.s[i_true])
        return np.minimum(d, self.length - d).min()


# ------------------------------------------------------ sub-pixel accuracy
def _disk_stats(c, cx, cy, r):
    p = c.points
    dr = np.hypot(p[:, 0] - cx, p[:, 1] - cy) - r
    return np.sqrt(np.mean(dr**2)), dr.mean(), c.perimeter / (2 * np.pi * r) - 1


def test_antialiased_dark_disk_on_light_subpixel():
    cx, cy, r = 127.37, 130.81, 92.6
    th = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    img = render_silhouette(np.c_[cx + r * np.cos(th), cy + r * np.sin(th)], shape=(260, 256),
                            figure=0.1, ground=0.9)["img"]
    ex = extract(img)
    assert ex.params["polarity"] == "dark"
    assert len(ex.contours) == 1
    rms, bias, perim = _disk_stats(ex.contour, cx, cy, r)
    assert rms <= 0.05
    assert abs(bias) <= 0.02
    assert abs(perim) <= 0.003


def test_antialiased_light_disk_on_dark_subpixel_from_8bit_png(tmp_path):
    cx, cy, r = 140.52, 118.26, 101.3
    th = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    res = render_silhouette(np.c_[cx + r * np.cos(th), cy + r * np.sin(th)], shape=(250, 270),
                            figure=0.95, ground=0.05, dtype="uint8")
    path = write_png(tmp_path / "disk.png", res)
    ex = extract(path)
    assert ex.params["polarity"] == "light"
    rms, bias, perim = _disk_stats(ex.contour, cx, cy, r)
    assert rms <= 0.05
    assert abs(bias) <= 0.02
    assert abs(perim) <= 0.003


def test_uneven_lighting_edge_stays_on_the_50_percent_line():
    # ground graded left to right, figure graded top to bottom: one global
    # level is off the local midpoint almost everywhere
    cx, cy, r = 130.4, 120.7, 80.2
    th = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    cov = coverage(np.c_[cx + r * np.cos(th), cy + r * np.sin(th)], (250, 260))
    yy, xx = np.mgrid[:250, :260]
    img = (20 + 100 * xx / 259) * (1 - cov) + (230 - 40 * yy / 249) * cov
    errors = {}
    for local in (True, False):
        p = extract(img, local_level=local).contour.points
        errors[local] = np.sqrt(np.mean((np.hypot(p[:, 0] - cx, p[:, 1] - cy) - r) ** 2))
    assert errors[True] <= 0.05
    assert errors[False] > 0.1  # what a single level does


def test_contour_conventions_xy_orientation_no_repeat():
    # an ellipse wide in x, centred off the diagonal: (x, y) must not be swapped
    pts, _ = ellipse(80, 30, 150.3, 60.7)
    img = coverage(pts, (130, 260))
    [c] = extract_contours(img)
    assert c.closed
    assert not np.array_equal(c.points[0], c.points[-1])
    assert c.signed_area > 0  # counter-clockwise on the screen
    xmin, ymin, xmax, ymax = c.bbox
    assert xmax - xmin == pytest.approx(160, abs=0.1)
    assert ymax - ymin == pytest.approx(60, abs=0.1)
    assert np.allclose(c.centroid, (150.3, 60.7), atol=0.01)
    assert c.area == pytest.approx(np.pi * 80 * 30, rel=1e-3)


# --------------------------------------------------------------- curvature
ELLIPSE = dict(a=0.4 * N, b=0.2 * N, cx=255.3, cy=256.1, rot=0.37)
RF3 = dict(r0=0.3 * N, amp=0.15, freq=3, cx=255.7, cy=256.2, phase=0.9)


@pytest.fixture(scope="module")
def ellipse_case():
    pts, k = ellipse(**ELLIPSE)
    return Truth(pts, k), coverage(pts, (N, N))


@pytest.fixture(scope="module")
def rf3_case():
    pts, k = radial_frequency(**RF3)
    return Truth(pts, k), coverage(pts, (N, N))


def test_curvature_ellipse_default_settings(ellipse_case):
    truth, img = ellipse_case
    [c] = extract_contours(img)
    assert default_sigma(c) == pytest.approx(0.01 * c.perimeter)
    assert truth.nrmse(c, contour_curvature(c)) <= 0.025
    pk = curvature_peaks(c)
    true_idx = true_maxima(truth.k)
    assert len(true_idx) == 2  # the ends of the major axis
    assert len(pk["t"]) == len(true_idx)
    for i in true_idx:
        assert truth.arc_gap(pk["points"], i) <= 0.003 * truth.length


def test_curvature_radial_frequency_3_lobes(rf3_case):
    truth, img = rf3_case
    [c] = extract_contours(img)
    assert truth.nrmse(c, contour_curvature(c)) <= 0.025
    pk = curvature_peaks(c)
    true_idx = true_maxima(truth.k)
    assert len(true_idx) == 3
    assert len(pk["t"]) == 3
    for i in true_idx:
        assert truth.arc_gap(pk["points"], i) <= 0.003 * truth.length
    # the three concave places are minima with negative curvature
    mins = curvature_peaks(c, minima=True)
    assert len(mins["t"]) == 3 and np.all(mins["curvature"] < 0)


def test_curvature_circle():
    r = 0.35 * N
    pts, k = ellipse(r, r, 255.6, 256.3)
    truth = Truth(pts, k)
    [c] = extract_contours(coverage(pts, (N, N)))
    assert truth.nrmse(c, contour_curvature(c)) <= 0.02
    assert len(curvature_peaks(c)["t"]) == 0  # a circle has no curvature maxima


def test_curvature_from_binary_aliased_mask_of_the_ellipse(ellipse_case):
    truth, _ = ellipse_case
    a, b, cx, cy, rot = (ELLIPSE[k] for k in ("a", "b", "cx", "cy", "rot"))
    yy, xx = np.mgrid[:N, :N].astype(float)
    u = np.cos(rot) * (xx - cx) + np.sin(rot) * (yy - cy)
    v = -np.sin(rot) * (xx - cx) + np.cos(rot) * (yy - cy)
    mask = (u / a) ** 2 + (v / b) ** 2 <= 1.0  # pixel centres inside: aliased
    ex = extract(mask)
    assert ex.params["subpixel"] == "mask"
    assert truth.nrmse(ex.contour, contour_curvature(ex.contour)) <= 0.06


# ------------------------------------------------------- real silhouettes
def test_horse_one_outer_contour_area():
    import skimage.data

    horse = skimage.data.horse()  # the horse is the False pixels
    ex = extract(horse, objects="all")
    assert ex.params["polarity"] == "dark"
    assert len(ex.contours) == 1
    n = np.count_nonzero(~horse)
    assert ex.contour.area == pytest.approx(n, rel=0.01)
    assert ex.contour.is_simple()


# ------------------------------------------------------------- clean-up
def test_holes_kept_apart_and_never_the_outer_contour():
    cx, cy = 100.3, 90.6
    th = np.linspace(0, 2 * np.pi, 2048, endpoint=False)
    outer = np.c_[cx + 70 * np.cos(th), cy + 70 * np.sin(th)]
    hole = np.c_[cx + 50 * np.cos(th), cy + 50 * np.sin(th)]  # a large hole
    img = coverage([outer, hole], (190, 200))
    plain = extract(img)
    assert plain.holes == [[]]
    withh = extract(img, holes=True)
    for ex in (plain, withh):
        assert ex.contour.area == pytest.approx(np.pi * 70**2, rel=1e-3)
    [[h]] = withh.holes
    assert h.area == pytest.approx(np.pi * 50**2, rel=1e-3)
    assert h.signed_area > 0


def test_objects_largest_or_all_above_min_area():
    th = np.linspace(0, 2 * np.pi, 1024, endpoint=False)
    rings = [np.c_[60 + 30 * np.cos(th), 60 + 30 * np.sin(th)],
             np.c_[160 + 40 * np.cos(th), 70 + 40 * np.sin(th)],
             np.c_[200 + 3 * np.cos(th), 150 + 3 * np.sin(th)]]
    img = coverage(rings, (180, 240))
    [big] = extract_contours(img)
    assert big.area == pytest.approx(np.pi * 40**2, rel=1e-3)
    ex = extract(img, objects="all", min_area=10)
    assert [c.area / np.pi for c in ex.contours] == pytest.approx([1600, 900, 9], rel=0.02)
    ex = extract(img, objects="all", min_area=100)
    assert len(ex.contours) == 2


def test_object_touching_the_border_is_closed_along_the_image_edge():
    # a disk cut by the left and top edges
    th = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    ring = np.c_[20.2 + 60 * np.cos(th), 10.7 + 60 * np.sin(th)]
    img = coverage(ring, (150, 160))
    [c] = extract_contours(img)
    assert c.bbox[0] == pytest.approx(-0.5, abs=1e-6)
    assert c.bbox[1] == pytest.approx(-0.5, abs=1e-6)
    assert c.area == pytest.approx(img.sum(), rel=2e-3)


# ---------------------------------------------------------------- methods
def _disk_img(shape=(120, 140), cx=70.4, cy=58.8, r=40.0):
    th = np.linspace(0, 2 * np.pi, 2048, endpoint=False)
    return coverage(np.c_[cx + r * np.cos(th), cy + r * np.sin(th)], shape), np.pi * r * r


def test_threshold_mask_and_alpha_methods():
    cov, area = _disk_img()
    grey = 40 + 160 * cov
    ex = extract(grey, method="threshold", threshold=120.0)
    assert ex.params["level"] == 120.0
    assert ex.contour.area == pytest.approx(area, rel=1e-3)
    # a binary mask of either polarity
    m = cov >= 0.5
    for img in (m, ~m, m.astype(np.uint8) * 255):
        assert extract(img, method="mask").contour.area == pytest.approx(m.sum(), rel=0.01)
    # the alpha channel of a cut-out whose colour under transparency is noise
    rgba = np.zeros(cov.shape + (4,), np.uint8)
    rgba[..., :3] = np.random.default_rng(1).integers(0, 256, cov.shape + (3,))
    rgba[..., 3] = np.round(255 * cov)
    ex = extract(rgba, method="alpha")
    assert ex.params["polarity"] == "opaque"
    assert ex.contour.area == pytest.approx(area, rel=1e-3)
    with pytest.raises(InputError, match="alpha channel"):
        extract(grey, method="alpha")


def test_grabcut_finds_the_object():
    cov, area = _disk_img()
    rng = np.random.default_rng(2)
    rgb = np.empty(cov.shape + (3,))
    rgb[..., 0] = 200 * cov + 30 * (1 - cov)
    rgb[..., 1] = 60 * cov + 140 * (1 - cov)
    rgb[..., 2] = 50
    rgb = np.clip(rgb + rng.normal(0, 5, rgb.shape), 0, 255).astype(np.uint8)
    ex = extract(rgb, method="grabcut")
    assert ex.contour.area == pytest.approx(area, rel=0.03)


def test_no_object_and_everything_object_fail_with_a_reason():
    with pytest.raises(InputError, match="uniform"):
        extract(np.zeros((20, 30), np.uint8))
    with pytest.raises(InputError, match="no object"):
        extract(np.zeros((20, 30), np.uint8), method="mask", polarity="light")
    with pytest.raises(InputError, match="everything is object"):
        extract(np.full((20, 30), 255, np.uint8), method="mask", polarity="light")
    grey = _disk_img()[0] * 100
    with pytest.raises(InputError, match="every pixel is object"):
        extract(grey, method="threshold", threshold=-1.0, polarity="light")
    with pytest.raises(InputError, match="no object of at least"):
        extract(grey, min_area=1e6)


# ----------------------------------------------------------------- reading
@pytest.mark.parametrize("suffix", [".png", ".tif", ".bmp", ".jpg"])
def test_read_image_formats_rgb_order(tmp_path, suffix):
    import cv2

    bgr = np.zeros((40, 50, 3), np.uint8)
    bgr[..., 2] = 200  # red in OpenCV's BGR order
    p = tmp_path / f"red{suffix}"
    assert cv2.imwrite(str(p), bgr)
    img = read_image(p)
    assert img.shape == (40, 50, 3) and img.dtype == np.uint8
    assert abs(int(img[20, 25, 0]) - 200) <= 3 and img[20, 25, 2] <= 3


def test_read_image_16_bit_grey_and_rgba(tmp_path):
    import cv2

    cov, area = _disk_img()
    g16 = np.round(1000 + 60000 * cov).astype(np.uint16)
    cv2.imwrite(str(tmp_path / "g16.png"), g16)
    img = read_image(tmp_path / "g16.png")
    assert img.dtype == np.uint16 and img.ndim == 2
    assert extract(img).contour.area == pytest.approx(area, rel=1e-3)
    bgra = np.zeros(cov.shape + (4,), np.uint8)
    bgra[..., 3] = np.round(255 * cov)
    cv2.imwrite(str(tmp_path / "rgba.png"), bgra)
    assert read_image(tmp_path / "rgba.png").shape == cov.shape + (4,)
    assert extract(tmp_path / "rgba.png", method="alpha").contour.area == pytest.approx(area, rel=1e-3)


def test_read_image_errors_name_the_file(tmp_path):
    with pytest.raises(InputError, match="nope.png: no such file"):
        read_image(tmp_path / "nope.png")
    bad = tmp_path / "bad.png"
    bad.write_bytes(b"\x89PNG\r\n\x1a\n" + b"junk" * 50)
    with pytest.raises(InputError, match="bad.png: not a readable image"):
        read_image(bad)
    (tmp_path / "empty.jpg").write_bytes(b"")
    with pytest.raises(InputError, match="empty.jpg: empty file"):
        read_image(tmp_path / "empty.jpg")


# ---------------------------------------------------- curvature & surprisal
def test_describe_circle_constant_and_ellipse_peaks_at_major_axis_ends():
    r = 80
    pts, _ = ellipse(r, r, 100.4, 99.7)
    [c] = extract_contours(coverage(pts, (200, 200)))
    info = describe(c, n=64)
    assert info.params["n"] == 64 and info.sigma == pytest.approx(0.01 * c.perimeter)
    # a circle's turning angles are all 2 pi / n, up to pixel noise
    assert np.ptp(info.surprisal.turning_angle) < 0.05 * (2 * np.pi / 64)
    assert np.sqrt(np.mean((info.curvature * r - 1) ** 2)) < 0.01
    assert len(info.surprisal.peaks) == 0  # pixel noise makes no peaks
    pts, _ = ellipse(90, 40, 100.2, 60.9)
    [c] = extract_contours(coverage(pts, (130, 200)))
    info = describe(c, n=100)
    top = info.surprisal.contour.points[info.surprisal.peaks[:2]]
    assert sorted(np.round(top[:, 0] - 100.2).tolist()) == pytest.approx([-90, 90], abs=2)
    assert np.allclose(top[:, 1], 60.9, atol=2)


# ----------------------------------------------------------- command line
def _write_inputs(d):
    import cv2

    cov, _ = _disk_img()
    cv2.imwrite(str(d / "good.png"), np.round(255 * (1 - cov)).astype(np.uint8))
    cv2.imwrite(str(d / "blank.png"), np.zeros((30, 40), np.uint8))
    cv2.imwrite(str(d / "full.png"), np.full((30, 40), 255, np.uint8))
    (d / "corrupt.jpg").write_bytes(b"\xff\xd8\xff\xe0" + b"not a jpeg" * 30)
    th = np.linspace(0, 2 * np.pi, 1024, endpoint=False)
    two = coverage([np.c_[40 + 25 * np.cos(th), 40 + 25 * np.sin(th)],
                    np.c_[110 + 15 * np.cos(th), 50 + 15 * np.sin(th)]], (90, 140))
    cv2.imwrite(str(d / "two.png"), np.round(255 * two).astype(np.uint8))


def test_cli_failures_reported_and_others_written(tmp_path):
    import pandas as pd

    from attneave.cli import main
    from attneave.stimuli.tables import read_points

    _write_inputs(tmp_path)
    out = tmp_path / "out"
    files = [str(tmp_path / f) for f in ("blank.png", "good.png", "full.png", "corrupt.jpg")]
    assert main(["extract", *files, "-o", str(out), "-n", "50"]) == 1
    summary = pd.read_csv(out / "summary.csv")
    summary["reason"] = summary["reason"].fillna("")
    assert summary["image"].tolist() == files
    assert summary["status"].tolist() == ["failed", "ok", "failed", "failed"]
    assert all(summary.loc[summary.status == "failed", "reason"].str.len() > 0)
    assert "not a readable image" in summary.loc[3, "reason"]
    for kind in ("contour.csv", "surprisal.csv", "overlay.png", "silhouette.png"):
        assert (out / f"good.{kind}").is_file()
    assert not any(out.glob("blank.*")) and not any(out.glob("full.*")) and not any(out.glob("corrupt.*"))
    pts = read_points(out / "good.contour.csv")
    c = Contour(pts)
    ok = summary.loc[1]
    assert ok["n_points"] == len(pts)
    assert ok["perimeter"] == pytest.approx(c.perimeter, rel=1e-8)
    assert ok["area"] == pytest.approx(np.pi * 40**2, rel=1e-3)
    sur = pd.read_csv(out / "good.surprisal.csv")
    assert list(sur.columns) == ["i", "s", "t", "x", "y", "turning_angle", "curvature", "surprisal", "peak",
                                 "length_unit"]
    assert len(sur) == 50
    sil = read_image(out / "good.silhouette.png")
    assert sil.shape == (120, 140) and (255 - sil.astype(float)).sum() / 255 == pytest.approx(c.area, rel=1e-3)
    ov = read_image(out / "good.overlay.png")
    assert ov.shape == (120, 140, 3)


def test_cli_objects_all_naming_and_workers_give_identical_files(tmp_path):
    from attneave.cli import main

    _write_inputs(tmp_path)
    a, b = tmp_path / "a", tmp_path / "b"
    args = [str(tmp_path / "two.png"), str(tmp_path / "good.png"), "--objects", "all"]
    assert main(["extract", *args, "-o", str(a)]) == 0
    assert main(["extract", *args, "-o", str(b), "--workers", "2"]) == 0
    names = sorted(p.name for p in a.iterdir())
    assert "two.0.contour.csv" in names and "two.1.contour.csv" in names and "two.overlay.png" in names
    assert "good.0.silhouette.png" in names and "good.contour.csv" not in names
    assert Contour.from_csv(a / "two.0.contour.csv").area > Contour.from_csv(a / "two.1.contour.csv").area
    assert names == sorted(p.name for p in b.iterdir())
    for n in names:
        assert (a / n).read_bytes() == (b / n).read_bytes(), n


def test_cli_rerun_removes_outputs_of_an_input_that_now_fails(tmp_path):
    from attneave.cli import main

    _write_inputs(tmp_path)
    img, out = tmp_path / "good.png", tmp_path / "out"
    assert main(["extract", str(img), "-o", str(out)]) == 0
    assert (out / "good.contour.csv").is_file()
    img.write_bytes(b"no longer an image")
    assert main(["extract", str(img), "-o", str(out)]) == 1
    assert sorted(p.name for p in out.iterdir()) == ["summary.csv"]


def test_cli_bad_arguments_exit_2(tmp_path, capsys):
    from attneave.cli import main

    _write_inputs(tmp_path)
    assert main(["extract", str(tmp_path / "good.png"), "-o", str(tmp_path / "o"), "--method", "threshold"]) == 2
    assert "--threshold" in capsys.readouterr().err
    sub = tmp_path / "x"
    sub.mkdir()
    (sub / "good.png").write_bytes((tmp_path / "good.png").read_bytes())
    assert main(["extract", str(tmp_path / "good.png"), str(sub / "good.png"), "-o", str(tmp_path / "o")]) == 2
    assert "collide" in capsys.readouterr().err


def test_cli_threshold_nan_is_a_usage_error(tmp_path):
    from attneave.cli import main

    img = tmp_path / "a.png"
    import cv2

    cv2.imwrite(str(img), np.full((20, 20), 255, np.uint8))
    assert main(["extract", str(img), "-o", str(tmp_path / "out"), "--threshold", "nan"]) == 2
