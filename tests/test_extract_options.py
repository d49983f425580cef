"""``attneave extract`` option faults found by an audit: several boxes on one
image, output directories that cannot be made, options for another method
refused up front, a cut-out's verdict, and stale files of an earlier run."""

from __future__ import annotations

import numpy as np
import pytest


def _png(path, img):
    import cv2

    from attneave.stimuli.render import write_png

    if img.ndim == 3 and img.shape[2] == 4:  # RGBA, 8 or 16 bit
        assert cv2.imwrite(str(path), np.ascontiguousarray(img[..., [2, 1, 0, 3]]))
    else:
        write_png(path, img)
    return str(path)


def _disks(shape=(80, 160), centres=((40, 40), (120, 40)), r=22, rgb=False, seed=0):
    """Dark antialiased-free disks on a light, lightly noisy background (8 bit)."""
    yy, xx = np.mgrid[: shape[0], : shape[1]]
    img = np.full(shape, 210.0)
    for cx, cy in centres:
        img[(xx - cx) ** 2 + (yy - cy) ** 2 <= r * r] = 40.0
    img += np.random.default_rng(seed).normal(0, 3, shape)
    img = np.clip(np.round(img), 0, 255).astype(np.uint8)
    return np.dstack([img, img // 2 + 60, img]) if rgb else img


def _run(args):
    from attneave.cli import main

    return main(["extract", *map(str, args)])


def _one_line_exit_2(args, capsys, message):
    assert _run(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert message in err, err
    return err


# 1. several boxes for one image ------------------------------------------------------------------


def test_two_boxes_on_one_image_give_two_outlines(tmp_path, capsys):
    import pandas as pd

    img = _png(tmp_path / "two.png", _disks(rgb=True))
    boxes = tmp_path / "boxes.csv"
    boxes.write_text("image,x,y,width,height\ntwo.png,10,10,60,60\ntwo.png,90,10,60,60\n")
    out = tmp_path / "ex"
    assert _run([img, "-o", out, "--boxes", boxes, "--objects", "all"]) == 0, capsys.readouterr().err
    s = pd.read_csv(out / "summary.csv")
    assert s["n_objects"].tolist() == [2]
    for k, cx in ((0, 40), (1, 120)):
        xy = pd.read_csv(out / f"two.{k}.contour.csv")
        assert abs(xy["x"].mean() - cx) < 3 and abs(xy["y"].mean() - 40) < 3


def test_read_boxes_keeps_every_row_of_an_image(tmp_path):
    from attneave.stimuli.extraction.figure_ground.assists import read_boxes

    img = _png(tmp_path / "two.png", _disks())
    f = tmp_path / "b.csv"
    f.write_text("image,x,y,width,height\ntwo,10,10,60,60\ntwo.png,90,10,60,60\ntwo,0,0,20,20\n")
    assert read_boxes(f, [img], "all") == {img: [(10, 10, 60, 60), (90, 10, 60, 60), (0, 0, 20, 20)]}


# 2. output directories that cannot be made -------------------------------------------------------


def test_output_directory_that_cannot_be_made_is_one_line(tmp_path, capsys, monkeypatch):
    img = _png(tmp_path / "ok.png", _disks(centres=((80, 40),)))
    (tmp_path / "file.csv").write_text("x\n")
    _one_line_exit_2([img, "-o", tmp_path / "file.csv" / "ex"], capsys, "cannot be created")
    _one_line_exit_2([img, "-o", tmp_path / "file.csv"], capsys, "not a directory")
    monkeypatch.chdir(tmp_path)
    _one_line_exit_2([img, "-o", ""], capsys, "empty output path")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file.csv", "ok.png"]  # nothing written here


def test_outputs_that_would_overwrite_an_input_are_refused(tmp_path, capsys):
    a = _png(tmp_path / "a.png", _disks(centres=((80, 40),)))
    b = _png(tmp_path / "a.overlay.png", _disks(centres=((80, 40),)))  # a's overlay would replace it
    before = (tmp_path / "a.overlay.png").read_bytes()
    _one_line_exit_2([a, b, "-o", tmp_path], capsys, "is an input of this command")
    assert (tmp_path / "a.overlay.png").read_bytes() == before


# 3 and 4. options for another method, or bad, refused before any image ---------------------------


@pytest.mark.parametrize("extra, message", [
    (["--method", "grabcut", "--rect", "0", "0", "0", "0"], "--rect 0 0 0 0"),
    (["--method", "grabcut", "--rect", "100", "10", "80", "40"], "inside the 160x80 image"),
    (["--method", "otsu", "--boxes", "BOXES"], "--boxes applies to --method auto, photo, model or rembg only"),
    (["--method", "otsu", "--scribbles", "SCRIBBLES"], "--scribbles applies to --method auto or photo only"),
    (["--method", "model", "--model-file", "TEXT"], "TEXT"),
    (["--threshold", "50"], "--threshold applies to --method threshold or alpha only, not --method auto"),
    (["--rect", "1", "1", "50", "50"], "--rect applies to --method grabcut only, not --method auto"),
    (["--boxes", "HEADER"], "no boxes"),
    (["--sigma", "inf"], "--sigma must be a finite number"),
])
def test_option_mistakes_are_refused_up_front(tmp_path, capsys, extra, message):
    img = _png(tmp_path / "ok.png", _disks(centres=((80, 40),)))
    (tmp_path / "boxes.csv").write_text("image,x,y,width,height\nok.png,50,10,60,60\n")
    (tmp_path / "header.csv").write_text("image,x,y,width,height\n")
    (tmp_path / "scr").mkdir()
    scr = np.zeros((80, 160, 3), np.uint8)
    scr[40, 80] = (255, 0, 0)
    _png(tmp_path / "scr" / "ok.png", scr)
    (tmp_path / "text.onnx").write_text("not a network\n")
    names = {"BOXES": tmp_path / "boxes.csv", "HEADER": tmp_path / "header.csv", "SCRIBBLES": tmp_path / "scr",
             "TEXT": tmp_path / "text.onnx"}
    extra = [str(names.get(e, e)) for e in extra]
    message = str(names.get(message, message))
    out = tmp_path / "ex"
    _one_line_exit_2([img, "-o", out, *extra], capsys, message)
    assert not out.exists()  # nothing written, not even the directory


def test_sigma_over_half_the_perimeter_names_sigma(tmp_path, capsys):
    import pandas as pd

    img = _png(tmp_path / "ok.png", _disks(centres=((80, 40),)))
    assert _run([img, "-o", tmp_path / "ex", "--sigma", "1e9"]) == 1
    reason = pd.read_csv(tmp_path / "ex" / "summary.csv")["reason"][0]
    assert "--sigma" in reason and "perimeter" in reason
    assert _run([img, "-o", tmp_path / "ex2", "--sigma", "20"]) == 0  # under half of about 138 px


# 5. a cut-out's verdict measures its alpha channel -----------------------------------------------


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
def test_uniform_colour_cut_out_is_ok(tmp_path, dtype):
    from attneave.stimuli.extraction.pipeline import extract_images
    from attneave.stimuli.render import coverage

    full = np.iinfo(dtype).max
    t = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    alpha = np.round(full * coverage(np.c_[60 + 30 * np.cos(t), 50 + 30 * np.sin(t)], (100, 120)))
    img = np.zeros((100, 120, 4), dtype)
    img[..., :3] = full // 3  # one colour everywhere: the object is in alpha only
    img[..., 3] = alpha.astype(dtype)
    s = extract_images([_png(tmp_path / "cut.png", img)], tmp_path / "ex", progress=False)
    assert s["resolved"][0] == "alpha"
    assert s["status"][0] == "ok", s["reason"][0]
    assert s["contrast"][0] > 10


# 6. files of an earlier run -----------------------------------------------------------------------


def _names(d):
    return sorted(p.name for p in d.iterdir())


def test_switching_objects_mode_leaves_no_stale_outputs(tmp_path, capsys):
    img = _png(tmp_path / "ok.png", _disks(centres=((80, 40),)))
    out = tmp_path / "ex"
    assert _run([img, "-o", out, "--objects", "all"]) == 0
    assert "ok.0.contour.csv" in _names(out)
    assert _run([img, "-o", out]) == 0
    assert _names(out) == ["ok.contour.csv", "ok.overlay.png", "ok.silhouette.png", "ok.surprisal.csv",
                           "summary.csv"]
    assert _run([img, "-o", out, "--objects", "all"]) == 0
    assert _names(out) == ["ok.0.contour.csv", "ok.0.silhouette.png", "ok.0.surprisal.csv", "ok.overlay.png",
                           "summary.csv"]
    assert "warning" not in capsys.readouterr().err


def test_fewer_objects_than_before_removes_the_extra_ones(tmp_path):
    two = _disks()
    img = _png(tmp_path / "two.png", two)
    out = tmp_path / "ex"
    assert _run([img, "-o", out, "--objects", "all", "--method", "otsu"]) == 0
    assert "two.1.contour.csv" in _names(out)
    one = two.copy()
    one[:, 80:] = 210  # the second disk gone
    _png(tmp_path / "two.png", one)
    assert _run([img, "-o", out, "--objects", "all", "--method", "otsu"]) == 0
    assert not [n for n in _names(out) if n.startswith("two.1.")]


def test_another_images_per_object_names_are_left_and_named(tmp_path, capsys):
    a = _png(tmp_path / "ok.png", _disks(centres=((80, 40),)))
    b = _png(tmp_path / "ok.0.png", _disks(centres=((70, 40),)))
    out = tmp_path / "ex"
    assert _run([b, "-o", out]) == 0  # ok.0.contour.csv, ... of the image ok.0.png
    theirs = {n: (out / n).read_bytes() for n in _names(out) if n.startswith("ok.0.")}
    assert _run([a, "-o", out]) == 0
    assert {n: (out / n).read_bytes() for n in theirs} == theirs  # not removed: they are ok.0.png's
    capsys.readouterr()
    # without the overlay that marks them as an image's, they cannot be told from ok.png's objects
    (out / "ok.0.overlay.png").unlink()
    (out / "summary.csv").unlink()
    assert _run([a, "-o", out]) == 0
    err = capsys.readouterr().err
    assert "warning: left ok.0.contour.csv" in err and err.count("\n") == 2
    assert "ok.0.contour.csv" in _names(out)
    # both in one run: neither removes nor warns about the other's files
    assert _run([a, b, "-o", out]) == 0
    assert "warning" not in capsys.readouterr().err
    assert {"ok.contour.csv", "ok.0.contour.csv", "ok.overlay.png", "ok.0.overlay.png"} <= set(_names(out))
