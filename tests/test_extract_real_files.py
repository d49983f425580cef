"""Audit of ``attneave extract`` on the kinds of files people have (EXIF-rotated
phone JPEGs, framed silhouettes, ...): the outline must lie on the object as
the user sees it, and the verdict must be honest. Every image is built here."""

from __future__ import annotations

import numpy as np
import pytest


def _l_shape(h=90, w=130):
    """Black L-shaped object on white (asymmetric: any turn or flip moves it); its true mask."""
    obj = np.zeros((h, w), bool)
    obj[15:75, 20:45] = True  # the stem, on the left
    obj[55:75, 20:100] = True  # the foot, along the bottom
    return np.where(obj, 0, 255).astype(np.uint8), obj


def _save_with_orientation(path, stored, orientation):
    from PIL import Image

    exif = Image.Exif()
    exif[0x0112] = orientation
    Image.fromarray(stored).save(path, exif=exif.tobytes(), **({"quality": 95} if path.suffix == ".jpg" else {}))


@pytest.mark.parametrize("orientation, to_stored", [
    (6, lambda a: np.rot90(a, 1)),   # shown turned 90 degrees clockwise: stored turned counter-clockwise
    (8, lambda a: np.rot90(a, -1)),
    (3, lambda a: a[::-1, ::-1]),
    (2, lambda a: a[:, ::-1]),
])
@pytest.mark.parametrize("suffix", [".jpg", ".png"])
def test_exif_oriented_file_is_outlined_as_shown(tmp_path, orientation, to_stored, suffix):
    # what viewers and browsers show (EXIF 2.3: orientation 6 = "rotate 90 CW to display") is the
    # L shape; the file stores it turned or flipped. The outline must fit the shape as shown.
    from attneave.stimuli.extraction import extract
    from attneave.stimuli.extraction.imageio import header_size, open_image

    shown, truth = _l_shape()
    path = tmp_path / f"phone{suffix}"
    _save_with_orientation(path, np.ascontiguousarray(to_stored(shown)), orientation)
    f = open_image(path)
    assert f.image.shape[:2] == shown.shape and f.orientation == orientation
    assert header_size(path) == (shown.shape[1], shown.shape[0])
    c = extract(f.image).contour
    ys, xs = np.nonzero(truth)
    # the mask's pixel edges are half a pixel outside its pixel centres
    np.testing.assert_allclose(c.bbox, [xs.min() - 0.5, ys.min() - 0.5, xs.max() + 0.5, ys.max() + 0.5], atol=0.6)
    assert abs(c.area - truth.sum()) < 0.03 * truth.sum()


def test_exif_orientation_reaches_the_outputs_of_the_command(tmp_path, capsys):
    import pandas as pd
    from PIL import Image

    from attneave.cli import main

    shown, truth = _l_shape()
    _save_with_orientation(tmp_path / "p.jpg", np.ascontiguousarray(np.rot90(shown, 1)), 6)
    assert main(["extract", str(tmp_path / "p.jpg"), "-o", str(tmp_path / "out")]) == 0
    xy = pd.read_csv(tmp_path / "out" / "p.contour.csv")
    ys, xs = np.nonzero(truth)
    assert xy.x.min() == pytest.approx(xs.min() - 0.5, abs=0.6) and xy.x.max() == pytest.approx(xs.max() + 0.5, abs=0.6)
    assert xy.y.min() == pytest.approx(ys.min() - 0.5, abs=0.6) and xy.y.max() == pytest.approx(ys.max() + 0.5, abs=0.6)
    with Image.open(tmp_path / "out" / "p.silhouette.png") as im:
        sil = np.asarray(im.convert("L")) < 128
    assert sil.shape == truth.shape and (sil & truth).sum() / (sil | truth).sum() > 0.97


def _framed(width=1, polarity="dark"):
    """An ellipse on a page with a drawn frame line `width` px wide along the image's edge; its true mask."""
    yy, xx = np.mgrid[:120, :160]
    obj = ((xx - 70.0) / 40.0) ** 2 + ((yy - 60.0) / 28.0) ** 2 <= 1.0
    ink = obj.copy()
    ink[:width], ink[-width:], ink[:, :width], ink[:, -width:] = True, True, True, True
    img = np.where(ink, 0, 255).astype(np.uint8)
    return (img if polarity == "dark" else 255 - img), obj


@pytest.mark.parametrize("width", [1, 3])
@pytest.mark.parametrize("ink", ["dark", "light"])
@pytest.mark.parametrize("method", ["otsu", "mask"])
def test_frame_line_around_a_silhouette_is_not_the_object(width, ink, method):
    # a frame drawn around the figure used to be taken for the object (auto polarity: the object is the
    # class inside the frame, so the page was outlined; either polarity gave the whole image)
    from attneave.stimuli.extraction import extract
    from attneave.stimuli.extraction.verdict import judge

    img, obj = _framed(width, ink)
    ex = extract(img, method=method)
    assert ex.params["polarity"] == ink
    assert abs(ex.contour.area - obj.sum()) < 0.02 * obj.sum()
    x0, y0, x1, y1 = ex.contour.bbox
    assert 29 < x0 < 31 and 109 < x1 < 111 and 31 < y0 < 33 and 87 < y1 < 89
    v = judge(img, ex)
    assert v.status == "ok", v.reason


def test_object_cut_by_a_frame_line_is_suspect():
    # the frame line is the image's frame for the verdict: an object running along it is cut
    from attneave.stimuli.extraction import extract
    from attneave.stimuli.extraction.verdict import judge

    img = np.full((100, 140), 255, np.uint8)
    img[30:70, 1:80] = 0  # a bar from the frame line inwards
    img[0], img[-1], img[:, 0], img[:, -1] = 0, 0, 0, 0
    ex = extract(img)
    assert abs(ex.contour.area - 40 * 79) < 0.02 * 40 * 79
    v = judge(img, ex)
    assert v.status == "suspect" and "frame" in v.reason


def test_silhouette_touching_the_edge_is_not_taken_for_a_frame():
    # an object that runs off one side is no frame line: the image's edge ring is not of one class
    from attneave.stimuli.extraction import extract

    img = np.full((100, 140), 255, np.uint8)
    img[20:80, :60] = 0
    ex = extract(img)
    assert ex.params["frame_line"] == 0 and ex.params["polarity"] == "dark"
    assert abs(ex.contour.area - 60 * 60) < 0.02 * 3600


def test_a_failed_file_is_named_on_stderr_one_line_each(tmp_path, capsys):
    from PIL import Image

    from attneave.cli import main

    img, _ = _l_shape()
    Image.fromarray(img).save(tmp_path / "good one.png")
    (tmp_path / "notes.png").write_text("not an image")
    (tmp_path / "empty.jpg").write_bytes(b"")  # (a directory is its image files: see below)
    files = [str(tmp_path / "good one.png"), str(tmp_path / "notes.png"), str(tmp_path / "empty.jpg")]
    assert main(["extract", *files, "-o", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 3
    assert err[0].startswith(f"attneave extract: {files[1]}: failed: ") and "not a readable image" in err[0]
    assert err[1].startswith(f"attneave extract: {files[2]}: failed: ")
    assert "1 ok, 0 suspect, 2 failed" in err[2]


def test_a_line_drawing_is_suspect_not_ok(tmp_path):
    # a drawn circle with a gap in its stroke: the outline runs around the 3-px ink (a thin C),
    # not along the figure, and was 'ok'. Twice area over perimeter is the stroke's width.
    import cv2

    from attneave.stimuli.extraction import extract
    from attneave.stimuli.extraction.verdict import judge

    img = np.full((160, 160), 255, np.uint8)
    cv2.ellipse(img, (80, 80), (50, 50), 0, 20, 340, 0, 2)  # a stroke open over 40 degrees
    width = np.count_nonzero(img < 128) / (2 * np.pi * 50 * 320 / 360)  # ink per length: about 3 px
    ex = extract(img)
    v = judge(img, ex)
    assert v.status == "suspect" and "the object is a thin line (about " in v.reason
    assert v.measures["thickness"] == pytest.approx(width, rel=0.15)
    # the same circle filled is a figure, ok; its thickness is its radius
    filled = np.full((160, 160), 255, np.uint8)
    cv2.circle(filled, (80, 80), 50, 0, -1)
    ex = extract(filled)
    v = judge(filled, ex)
    assert v.status == "ok" and v.measures["thickness"] == pytest.approx(50, rel=0.03)


def test_a_directory_is_its_image_files(tmp_path, capsys):
    import cv2

    from attneave.cli import main

    d = tmp_path / "silhouettes"
    d.mkdir()
    for k, r in enumerate((20, 30)):
        img = np.full((100, 100), 255, np.uint8)
        cv2.circle(img, (50, 50), r, 0, -1)
        cv2.imwrite(str(d / f"disk{k}.PNG"), img)
    (d / "notes.txt").write_text("not an image")
    (d / "sub").mkdir()
    assert main(["extract", str(d), "-o", str(tmp_path / "out")]) == 0
    import pandas as pd

    summary = pd.read_csv(tmp_path / "out" / "summary.csv")
    assert [p.split("/")[-1] for p in summary["image"]] == ["disk0.PNG", "disk1.PNG"]
    assert (summary["status"] == "ok").all()
    empty = tmp_path / "empty"
    empty.mkdir()
    capsys.readouterr()
    assert main(["extract", str(empty), "-o", str(tmp_path / "out2")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "a directory without image files" in err[0]


@pytest.mark.parametrize("size", [32, 48])
def test_a_small_antialiased_silhouette_is_a_silhouette_not_a_photo(size):
    # the antialiased rim of a small render is a large share of its pixels, so Otsu's classes hold
    # under 97 % of the variance and `auto` took it for a photograph (never ok, GrabCut's outline);
    # off the rim it is two flat tones
    from attneave.stimuli.extraction import extract
    from attneave.stimuli.extraction.segment import image_kind
    from attneave.stimuli.extraction.verdict import judge
    from attneave.stimuli.render import coverage

    th = np.linspace(0, 2 * np.pi, 800, endpoint=False)
    r = 0.3 * size * (1 + 0.45 * np.cos(8 * th))  # an eight-armed star: a long rim for its area
    pts = np.c_[size / 2 + r * np.cos(th), size / 2 + r * np.sin(th)]
    img = np.round(255 * (1 - coverage(pts, (size, size)))).astype(np.uint8)
    assert image_kind(img) == "otsu"
    ex = extract(img)
    x, y = pts.T
    exact = 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))
    assert ex.contours[0].area == pytest.approx(exact, rel=0.02)  # sharp arm tips at 32 px lose a little
    assert judge(img, ex).status == "ok"
    # a textured photo-like image with the same shape stays a photograph
    rng = np.random.default_rng(0)
    photo = np.clip(img + rng.normal(0, 40, img.shape), 0, 255).astype(np.uint8)
    assert image_kind(photo) == "photo"
