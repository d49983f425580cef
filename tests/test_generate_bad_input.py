"""`attneave generate` on bad or poor input: one line and exit 2, nothing half-written, poor results flagged.

Each test failed on the code before the fix (audit of generate and experiment).
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest

from attneave.cli import main as cli
from attneave.stimuli.errors import InputError

CANVAS = "canvas: {width: 48, height: 48, margin: 4}\n"


def _config(tmp_path, recipe, params="{}", canvas=CANVAS, name="c.yaml", extra=""):
    cfg = tmp_path / name
    cfg.write_text(f"seed: 1\n{canvas}conditions:\n  - name: c\n    recipe: {recipe}\n    params: {params}\n{extra}")
    return cfg


def _gen(cfg, out, *extra):
    return cli(["generate", str(cfg), "-o", str(out), "--no-progress", *extra])


def _one_error_line(capsys, *words):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err and "Warning:" not in err, err
    assert err.startswith("attneave generate: error: "), err
    for w in words:
        assert w in err, err
    return err


def _disc_png(path, size=40, r=12, cx=None, cy=None):
    import cv2

    img = np.full((size, size), 255, np.uint8)
    cv2.circle(img, (size // 2 if cx is None else cx, size // 2 if cy is None else cy), r, 0, -1)
    cv2.imwrite(str(path), img)
    return path


# ------------------------------------------------------------------ canvas and rendering


def test_a_one_pixel_canvas_is_refused_naming_the_key_and_writes_nothing(tmp_path, capsys):
    cfg = _config(tmp_path, "attneave_polygon", canvas="canvas: {width: 1, height: 1, margin: 0}\n")
    assert _gen(cfg, tmp_path / "out") == 2
    _one_error_line(capsys, "c.yaml:2:", "canvas.width: must be >= 8")
    assert not (tmp_path / "out").exists()


def test_a_margin_that_leaves_no_figure_area_is_refused(tmp_path, capsys):
    cfg = _config(tmp_path, "blob", canvas="canvas: {width: 20, height: 20, margin: 7}\n")
    assert _gen(cfg, tmp_path / "out") == 2
    _one_error_line(capsys, "canvas.margin: must be <= 6")


@pytest.mark.parametrize("dtype", [None, "uint16", "uint8"])
def test_a_one_pixel_image_renders(dtype):
    from attneave.stimuli.render import render_silhouette

    pts = np.array([[0.0, 0.0], [0.5, 0.2], [0.3, 0.9], [-0.2, 0.5]])
    img = render_silhouette(pts, size=1, dtype=dtype)["img"]
    assert img.shape == (1, 1)


def test_an_unexpected_error_removes_a_directory_the_run_made_and_says_so(tmp_path, capsys, monkeypatch):
    from attneave.stimuli.batch import recipes

    def broken(params, rng, canvas):
        raise ValueError("could not broadcast")

    monkeypatch.setitem(recipes.RECIPES, "blob", (recipes.RECIPES["blob"][0], broken))
    cfg = _config(tmp_path, "blob")
    out = tmp_path / "out"
    assert _gen(cfg, out) == 1
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert last.startswith("attneave generate: internal error"), last
    assert "call c_000_000" in last and "ValueError: could not broadcast" in last and "was removed" in last
    assert not out.exists()


def test_an_unexpected_error_in_an_existing_directory_keeps_it_and_says_how_to_finish(tmp_path, capsys,
                                                                                       monkeypatch):
    from attneave.stimuli.batch import recipes

    real = recipes.RECIPES["blob"]
    calls = []

    def flaky(params, rng, canvas):
        calls.append(1)
        if len(calls) == 2:
            raise ValueError("a bug")
        return real[1](params, rng, canvas)

    monkeypatch.setitem(recipes.RECIPES, "blob", (real[0], flaky))
    cfg = _config(tmp_path, "blob", "{n: 64}", extra="    repeats: 2\n")
    out = tmp_path / "out"
    out.mkdir()
    assert _gen(cfg, out) == 1
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert "keeps the stimuli completed so far" in last and "--resume" in last, last
    assert (out / "images" / "c_000_000.png").is_file()
    assert _gen(cfg, out, "--resume") == 0  # the rerun completes it
    assert len(pd.read_csv(out / "manifest.csv")) == 2


# ------------------------------------------------------------------ YAML and output


def test_duplicate_yaml_keys_are_refused_naming_key_and_lines(tmp_path, capsys):
    cfg = tmp_path / "dup.yaml"
    cfg.write_text("seed: 1\nseed: 2\nconditions:\n  - name: p\n    recipe: blob\n")
    assert _gen(cfg, tmp_path / "out") == 2
    _one_error_line(capsys, "dup.yaml:2: duplicate key 'seed' (first given on line 1)")
    assert not (tmp_path / "out").exists()
    # nested, too
    cfg.write_text("seed: 1\nconditions:\n  - name: p\n    recipe: blob\n    params: {n: 64, n: 128}\n")
    assert _gen(cfg, tmp_path / "out") == 2
    _one_error_line(capsys, "dup.yaml:5: duplicate key 'n'")


def test_yaml_merge_keys_are_not_duplicates(tmp_path):
    from attneave.stimuli.batch.config_file import parse_yaml

    _, data = parse_yaml("a: &x {p: 1, q: 2}\nb:\n  <<: *x\n  p: 3\n", "m.yaml")
    assert data == {"a": {"p": 1, "q": 2}, "b": {"p": 3, "q": 2}}


def test_an_empty_output_is_refused(tmp_path, capsys, monkeypatch):
    cfg = _config(tmp_path, "blob", "{n: 64}")
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    assert _gen(cfg, "") == 2
    _one_error_line(capsys, "-o: empty output path")
    assert list(work.iterdir()) == []


def test_the_output_may_not_overwrite_or_force_away_the_config(tmp_path, capsys):
    d = tmp_path / "d"
    d.mkdir()
    cfg = _config(d, "blob", "{n: 64}", name="config.yaml")
    text = cfg.read_text()
    assert _gen(cfg, d) == 2  # its config.yaml would be written over the input
    _one_error_line(capsys, "would overwrite one of its inputs")
    own = _config(d, "blob", "{n: 64}", name="mine.yaml")
    assert _gen(own, d, "--force") == 2
    _one_error_line(capsys, "holds an input of this command")
    assert cfg.read_text() == text and not (d / "images").exists()
    # a set's own resolved config.yaml run again into the set is the same set
    out = tmp_path / "set"
    assert _gen(own, out) == 0
    assert _gen(out / "config.yaml", out) == 0


# ------------------------------------------------------------------ poor results are flagged


def test_suspect_image_outlines_are_flagged_on_stderr_and_in_the_manifest(tmp_path, capsys):
    half = _disc_png(tmp_path / "half.png", cx=0)  # cut by the frame
    ok = _disc_png(tmp_path / "ok.png")
    data = (tmp_path / "ok.png").read_bytes()
    (tmp_path / "trunc.png").write_bytes(data[: len(data) - 30])
    cfg = tmp_path / "c.yaml"
    cfg.write_text("seed: 1\n" + CANVAS + "conditions:\n"
                   "  - name: half\n    recipe: from_image\n    params: {path: half.png}\n"
                   "  - name: ok\n    recipe: from_image\n    params: {path: ok.png}\n"
                   "  - name: trunc\n    recipe: from_image\n    params: {path: trunc.png}\n")
    out = tmp_path / "out"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no raw Python warning on the way
        assert _gen(cfg, out) == 0
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert "Warning:" not in err and "Traceback" not in err, err
    assert [ln.split(":")[2].strip() for ln in lines[:-1]] == ["half_000_000", "trunc_000_000"], err
    assert "touches the image frame" in lines[0] and "decoder: image file is truncated" in lines[1]
    assert "2 flagged" in lines[-1]
    m = pd.read_csv(out / "manifest.csv", dtype=str, keep_default_na=False).set_index("stimulus_id")
    assert "suspect" in m.loc["half_000_000", "warning"] and m.loc["ok_000_000", "warning"] == ""
    assert "truncated" in m.loc["trunc_000_000", "warning"]
    assert ok.is_file() and half.is_file()
    # a rerun of the complete set keeps the column
    assert _gen(cfg, out) == 0
    assert "warning" in pd.read_csv(out / "manifest.csv").columns


def test_a_figure_below_one_pixel_is_refused(tmp_path, capsys):
    cfg = _config(tmp_path, "radial_frequency", "{placement: native, r0: 0.01, n: 64}")
    assert _gen(cfg, tmp_path / "out") == 2
    _one_error_line(capsys, "call c_000_000", "below 1 px", "blank")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("params, words", [
    ("{n1: 1.0e-6, n2: 1.0e+6, n3: 1.0e+6}", ["n1=1e-06", "infinite or undefined"]),
    ("{a: 1.0e-300}", ["a=1e-300", "zero"]),
])
def test_superformula_overflow_is_one_line_naming_the_parameters(tmp_path, capsys, params, words):
    cfg = _config(tmp_path, "superformula", params)
    assert _gen(cfg, tmp_path / "out") == 2
    _one_error_line(capsys, "superformula(m=5", *words)


def test_superformula_overflow_raises_without_numpy_warnings():
    from attneave.stimuli.shapes.generators import superformula

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(InputError, match=r"superformula\(m=5, n1=2, n2=7, n3=7, a=1e-300"):
            superformula(a=1e-300)
        c, _ = superformula()  # the ordinary case is untouched
    assert c.n == 1024


def test_aliasing_and_blob_bounds_are_refused_when_the_config_is_read():
    # the generators' own rules, found before any job runs (one line naming the key)
    from attneave.stimuli.batch.params import SHAPES
    from attneave.stimuli.shapes.generators import MAX_BLOB_SIGMA

    for recipe, params, needle in (("radial_frequency", dict(frequency=[3, 8], amplitude=[0.1, 0.1], n=16),
                                    "alias radial frequency 8"),
                                   ("superformula", dict(m=1e6, n=1024), "alias superformula m"),
                                   ("blob", dict(sigma=MAX_BLOB_SIGMA * 1.01), "less than or equal to 3")):
        with pytest.raises(ValueError, match=needle):
            SHAPES[recipe](**params)
    SHAPES["blob"](sigma=MAX_BLOB_SIGMA)
    SHAPES["radial_frequency"](frequency=8, amplitude=0.1, n=32)
