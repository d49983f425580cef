"""Audit of `attneave generate`: stimuli that are silently not what the manifest says.

Each test builds a small config in `tmp_path` and checks a property that
holds without the code: the image shows the whole contour (or says it does
not), a parameter given is used or refused, the manifest row alone says how
the stimulus was drawn.
"""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from attneave.stimuli.batch.config import load_config
from attneave.stimuli.batch.runner import run_batch
from attneave.stimuli.errors import InputError


def _rows(out):
    with open(out / "manifest.csv", newline="", encoding="utf-8") as fh:
        return {r["stimulus_id"]: r for r in csv.DictReader(fh)}


def _shoelace(p):
    x, y = p.T
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _config(tmp_path, text, name="c.yaml"):
    cfg = tmp_path / name
    cfg.write_text(text)
    return cfg


def test_convex_deformation_cut_by_canvas_edge_is_flagged(tmp_path):
    # a 40 px square fitted inside 2 px margins; the convex version moves a new vertex 8 px outward,
    # past the image edge: the image then holds less than the contour's exact area
    import cv2

    (tmp_path / "sq.csv").write_text("x,y\n0,0\n0,40\n40,40\n40,0\n")
    cfg = _config(tmp_path, "seed: 1\ncanvas: {width: 48, height: 48, margin: 2}\nconditions:\n  - name: c\n"
                            "    recipe: deformation\n    params:\n      base: {generator: from_csv, params: "
                            "{path: sq.csv}}\n      displacement: 8\n")
    out = tmp_path / "out"
    res = run_batch(cfg, out, progress=False)
    rows = _rows(out)
    convex = rows["c_000_000_convex"]
    p = np.loadtxt(out / convex["contour"], delimiter=",", skiprows=1)
    img = cv2.imread(str(out / convex["image"]), cv2.IMREAD_UNCHANGED).astype(float) / 255.0
    shown = float((1.0 - img).sum())
    assert shown < _shoelace(p) - 10  # the image really lacks part of the figure ...
    assert "cut off by the canvas edge" in convex["warning"]  # ... and the set says so
    assert [sid for sid, _ in res.warnings] == ["c_000_000_convex"]
    assert not rows["c_000_000_base"].get("warning") and not rows["c_000_000_concave"].get("warning")


def test_outline_stroke_beyond_margin_is_flagged_and_inside_is_not(tmp_path):
    # an outline 8 px wide around a contour fitted 2 px from the edge reaches 2 px beyond it
    cfg = _config(tmp_path, "seed: 1\ncanvas: {width: 64, height: 64, margin: 2}\nstyle: {line_width: 8}\n"
                            "conditions:\n  - name: o\n    recipe: radial_frequency\n    params: {draw: outline}\n"
                            "  - name: s\n    recipe: radial_frequency\n")
    out = tmp_path / "out"
    run_batch(cfg, out, progress=False)
    rows = _rows(out)
    assert "cut off by the canvas edge" in rows["o_000_000"]["warning"]
    assert "2.00 px beyond" in rows["o_000_000"]["warning"]
    assert not rows["s_000_000"].get("warning")  # a silhouette inside the margins is not flagged


def test_figure_touching_the_edge_exactly_is_not_flagged(tmp_path):
    # margin 0: the fitted triangle's bounding box is the image (x, y = -0.5 .. 31.5); nothing is cut
    (tmp_path / "sq.csv").write_text("x,y\n0,0\n0,1\n1,0\n")
    cfg = _config(tmp_path, "seed: 1\ncanvas: {width: 32, height: 32, margin: 0}\nconditions:\n  - name: c\n"
                            "    recipe: from_csv\n    params: {path: sq.csv}\n")
    out = tmp_path / "out"
    res = run_batch(cfg, out, progress=False)
    assert res.warnings == []


def test_base_shape_draw_is_refused_not_ignored(tmp_path):
    # the recipe draws its base with its own `draw`; an outline asked for inside base.params used
    # to be accepted and silently ignored (silhouettes were drawn)
    cfg = _config(tmp_path, "seed: 1\nconditions:\n  - name: c\n    recipe: deformation\n    params:\n"
                            "      base: {generator: blob, params: {draw: outline}}\n")
    with pytest.raises(InputError, match=r"c\.yaml:\d+: .*base\.params\.draw: .*set draw: outline"):
        load_config(cfg)


def test_resolved_guided_config_of_the_earlier_version_still_runs(tmp_path):
    # resolved configs written before the check hold the base's default draw (silhouette) beside
    # base_draw: outline; a resolved config must always read back
    cfg = _config(tmp_path, "seed: 1\nconditions:\n  - name: c\n    recipe: guided\n    params:\n"
                            "      base: {generator: blob, params: {draw: silhouette}}\n      base_draw: outline\n")
    load_config(cfg)


def test_resolved_config_with_outline_deformation_reads_back(tmp_path):
    # the resolved config.yaml must not write the base's unused draw (it would contradict `draw`)
    cfg = _config(tmp_path, "seed: 1\ncanvas: {width: 96, height: 96, margin: 16}\nconditions:\n  - name: c\n"
                            "    recipe: deformation\n    params:\n      base: {generator: attneave_polygon, "
                            "params: {n_points: 6}}\n      draw: outline\n      displacement: 4\n")
    batch = load_config(cfg)
    again = _config(tmp_path, batch.text, "resolved.yaml")
    assert load_config(again).text == batch.text


def test_manifest_row_says_how_the_stimulus_is_drawn(tmp_path):
    cfg = _config(tmp_path, "seed: 1\ncanvas: {width: 64, height: 64, margin: 8}\nconditions:\n"
                            "  - name: o\n    recipe: blob\n    params: {draw: outline}\n"
                            "  - name: s\n    recipe: blob\n")
    out = tmp_path / "out"
    run_batch(cfg, out, progress=False)
    rows = _rows(out)
    assert json.loads(rows["o_000_000"]["params"])["draw"] == "outline"
    assert json.loads(rows["s_000_000"]["params"])["draw"] == "silhouette"


def test_superformula_that_does_not_close_is_refused_with_file_and_line(tmp_path):
    # m = 3 with a != b: r(0) != r(2 pi), the curve does not close; refused when the config is read
    cfg = _config(tmp_path, "seed: 1\nconditions:\n  - name: c\n    recipe: superformula\n"
                            "    grid: {m: [4, 3]}\n    params: {a: 2}\n")
    with pytest.raises(InputError, match=r"c\.yaml:\d+: conditions\[0\].*does not close"):
        load_config(cfg)


def test_repeats_that_come_out_identical_are_named(tmp_path, capsys):
    # a superformula draws no random numbers: its 3 repeats were 3 copies, without a word (and a
    # guided set on a fixed base warned even with repeats: 1)
    from attneave.cli import main

    cfg = _config(tmp_path, "seed: 1\ncanvas: {width: 96, height: 96}\nconditions:\n"
                            "  - name: sf\n    recipe: superformula\n    params: {m: 6}\n    repeats: 3\n"
                            "  - name: bl\n    recipe: blob\n    repeats: 3\n")
    assert main(["generate", str(cfg), "-o", str(tmp_path / "out")]) == 0
    err = capsys.readouterr().err
    assert "condition 'sf': its 3 repeats are identical in 1 of its cells" in err
    assert "condition 'bl'" not in err
    one = _config(tmp_path, "seed: 1\ncanvas: {width: 96, height: 96}\nconditions:\n"
                            "  - name: sf\n    recipe: superformula\n    params: {m: 6}\n", "one.yaml")
    assert main(["generate", str(one), "-o", str(tmp_path / "out1")]) == 0
    assert "identical" not in capsys.readouterr().err
