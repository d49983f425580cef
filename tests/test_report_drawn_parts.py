"""Guided fragment, dot and polygon stimuli: clicks are judged against what participants saw.

The truth comes from the rendered images, not from the analysis: a click on a
dark pixel of a stimulus's PNG is on something that was drawn; a point of the
contour farther than the tolerance (5% of the image diagonal) from every dark
pixel lies in a gap. The analysis reads what was drawn from the manifest.
"""

import json

import cv2
import numpy as np
import pandas as pd
import pytest
from scipy.spatial import cKDTree

from attneave.cli import main
from attneave.stimuli.stimulus_set import read_stimulus_set

CONFIG = """seed: 1954
canvas: {width: 256, height: 256, margin: 20}
style: {figure: 0.0, ground: 1.0, line_width: 3, dot_radius: 4, cap: flat}
conditions:
  - name: guided
    recipe: guided
    params:
      base: {generator: attneave_curved, params: {n_points: 12}}
      kinds: [base, peaks, troughs, cat, dots]
      n: 256
      min_separation: 12
      n_fragments: 4
      min_gap: 6
      min_contrast: 0.2
      fraction: 0.3
    repeats: 1
"""
TOL = 0.05 * np.hypot(256, 256)
PARTICIPANTS = [f"P{k:02d}" for k in range(5)]


@pytest.fixture(scope="module")
def guided(tmp_path_factory):
    root = tmp_path_factory.mktemp("guided")
    (root / "g.yaml").write_text(CONFIG)
    assert main(["generate", str(root / "g.yaml"), "-o", str(root / "set")]) == 0
    ss = read_stimulus_set(root / "set")
    dark, gaps = {}, {}
    for sid in ss.ids:
        im = cv2.imread(str(ss.images[sid]), cv2.IMREAD_GRAYSCALE)
        ys, xs = np.nonzero(im < 128)
        dark[sid] = np.c_[xs, ys].astype(float)
        pts = ss.contours[sid].point_at(np.linspace(0, 1, 400, endpoint=False))
        far = cKDTree(dark[sid]).query(pts)[0] > TOL + 3  # a margin over the line's half width
        gaps[sid] = pts[far]
        if sid.endswith("_cat"):  # the cat's straight edges cut corners: only its pixels near the contour
            dark[sid] = dark[sid][ss.contours[sid].project(dark[sid])[2] < TOL / 2]
    return dict(root=root, set=ss, dark=dark, gaps=gaps)


def _write(rows, path):
    pd.DataFrame(rows, columns=["participant", "stimulus_id", "trial", "click", "x", "y"]).to_csv(path, index=False)


def _analyze(g, rows, name):
    f = g["root"] / f"{name}.csv"
    _write(rows, f)
    out = g["root"] / name
    assert main(["analyze", str(f), "--stimuli", str(g["root"] / "set"), "-o", str(out), "--no-figures",
                 "--group-simulations", "99", "--permutations", "10"]) == 0
    return json.loads((out / "summary.json").read_text()), pd.read_csv(out / "clicks.csv"), out


def _on_drawn(g, rng, k=4):
    rows = []
    for p in PARTICIPANTS:
        for trial, sid in enumerate(g["set"].ids, 1):
            for c, i in enumerate(rng.choice(len(g["dark"][sid]), k, replace=False), 1):
                x, y = g["dark"][sid][i]
                rows.append([p, sid, trial, c, x, y])
    return rows


def test_the_gaps_of_fragment_and_dot_stimuli_are_larger_than_the_tolerance(guided):
    # the premise of the other tests: each partial stimulus has contour points far from all it drew,
    # and the whole outline has none
    kinds = {sid.rsplit("_", 1)[1]: len(v) for sid, v in guided["gaps"].items()}
    assert kinds["base"] == 0
    assert kinds["peaks"] > 20 and kinds["troughs"] > 20 and kinds["dots"] > 20 and kinds["cat"] > 0


def test_clicks_on_drawn_parts_only_are_all_used(guided):
    s, clicks, _ = _analyze(guided, _on_drawn(guided, np.random.default_rng(0)), "on")
    assert s["n_excluded"] == 0 and s["n_used"] == s["n_clicks"] == 4 * 5 * 5
    assert s["exclusions"]["off_drawn_part"] == 0 and s["drawn_parts"]["n_stimuli"] == 4


def test_clicks_in_the_gaps_are_excluded_and_counted_on_their_own(guided):
    rng = np.random.default_rng(1)
    rows = _on_drawn(guided, rng)
    n_gap = {}
    for p in PARTICIPANTS[:3]:
        for sid in guided["set"].ids:
            gap = guided["gaps"][sid]
            for i in rng.choice(len(gap), min(2, len(gap)), replace=False) if len(gap) else []:
                rows.append([p, sid, 99, 1 + len(rows), *gap[i]])
                n_gap[sid] = n_gap.get(sid, 0) + 1
    s, clicks, out = _analyze(guided, rows, "gaps")
    total = sum(n_gap.values())
    assert total == 4 * 2 * 3  # peaks, troughs, dots and the cat have gaps; the whole outline has none
    assert s["exclusions"]["off_drawn_part"] == total
    assert s["drawn_parts"]["off_drawn_part"] == total and s["drawn_parts"]["choice_set"] == "whole contour"
    assert s["drawn_parts"]["by_mode"] == {"dots": 1, "fragments": 2, "polygon": 1}
    assert s["n_used"] == 4 * 5 * 5 and s["n_excluded"] == total
    # each gap click is named in clicks.csv, on the stimulus it was made on
    off = clicks[clicks["reason"] == "off_drawn_part"]
    assert off["stimulus_id"].value_counts().to_dict() == n_gap
    # the same positions on the whole outline are used: the contour is drawn there
    base, peaks = (next(sid for sid in guided["set"].ids if sid.endswith(k)) for k in ("_base", "_peaks"))
    rows_base = [[p, base, 1, c, *xy] for p in PARTICIPANTS for c, xy in enumerate(guided["gaps"][peaks][:3])]
    s2, _, _ = _analyze(guided, rows_base, "base")
    assert s2["n_excluded"] == 0 and s2["n_used"] == len(rows_base)
    page = (out / "report.html").read_text()
    assert "off drawn part" in page and f"{total} far from every drawn part" in page


def test_repeated_clicks_on_one_point_are_not_called_copies(guided, capsys):
    # a file without trial or click columns: a participant who clicks the same pixel twice writes the
    # same row twice, which is a click, not a copy (44 of 720 simulated clicks were called copies)
    rows = [r[:2] + r[4:] for r in _on_drawn(guided, np.random.default_rng(2), k=2)]
    again = [r for k, r in enumerate(rows) if k % 5 == 0]
    f = guided["root"] / "again.csv"
    pd.DataFrame(rows + again, columns=["participant", "stimulus_id", "x", "y"]).to_csv(f, index=False)
    assert main(["analyze", str(f), "--stimuli", str(guided["root"] / "set"), "-o", str(guided["root"] / "again"),
                 "--no-figures", "--group-simulations", "0", "--permutations", "0"]) == 0
    assert "repeat an earlier row" not in capsys.readouterr().err
    # the same rows pasted twice as a block are still named
    g = guided["root"] / "pasted.csv"
    pd.DataFrame(rows + rows[:6], columns=["participant", "stimulus_id", "x", "y"]).to_csv(g, index=False)
    assert main(["analyze", str(g), "--stimuli", str(guided["root"] / "set"), "-o", str(guided["root"] / "pasted"),
                 "--no-figures", "--group-simulations", "0", "--permutations", "0"]) == 0
    assert "6 row(s) repeat an earlier" in capsys.readouterr().err
