"""Batch configs: validation messages, grids, seeds, the resolved config."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

from attneave.stimuli.batch.config import load_config, stimulus_seed
from attneave.stimuli.errors import InputError

# batch configs; configs/experiment.yaml holds the experiment page settings
CONFIGS = sorted(p for p in (Path(__file__).resolve().parents[1] / "configs").glob("*.yaml") if p.stem != "experiment")

GOOD = """\
seed: 5
canvas: {width: 64, height: 64, margin: 4}
conditions:
  - name: poly
    recipe: attneave_polygon
    params: {version: both}
    grid: {n_points: [5, 8]}
    repeats: 2
  - name: rf
    recipe: radial_frequency
    params: {n: 256}
    grid:
      frequency: [3, 5]
      amplitude: [0.05, 0.1, 0.2]
"""


def _write(tmp_path, text, name="cfg.yaml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def _error(tmp_path, text):
    with pytest.raises(InputError) as exc:
        load_config(_write(tmp_path, text))
    msg = str(exc.value)
    assert "\n" not in msg
    return msg


def test_shipped_configs_validate_and_resolve_to_a_fixed_point(tmp_path):
    assert len(CONFIGS) >= 4
    names = {p.stem for p in CONFIGS}
    assert {"attneave_polygons", "radial_frequency", "barenholtz_deformations", "guided_fragments"} <= names
    for p in CONFIGS:
        b = load_config(p)
        assert 0 < b.n_jobs <= 60  # kept small: the README runs one of them
        again = load_config(_write(tmp_path, b.text, p.name))
        assert again.text == b.text


def test_dotted_grid_keys_reach_nested_parameters(tmp_path):
    text = ("seed: 1\nconditions:\n  - name: g\n    recipe: guided\n"
            "    params: {base: {generator: blob, params: {sigma: 0.1}}}\n"
            "    grid: {base.params.n: [64, 128], fraction: [0.2, 0.3]}\n")
    b = load_config(_write(tmp_path, text))
    cells = b.conditions[0].cells
    assert [(c["base"]["params"]["n"], c["fraction"]) for c in cells] == [(64, 0.2), (64, 0.3), (128, 0.2), (128, 0.3)]
    assert all(c["base"]["params"]["sigma"] == 0.1 for c in cells)
    assert "n" not in b.conditions[0].params["base"]["params"]  # a grid axis, not a fixed value
    assert load_config(_write(tmp_path, b.text, "again.yaml")).text == b.text


@pytest.mark.parametrize(
    "text, where",
    [
        # unknown key at the top (a typo), with a suggestion
        ("seed: 1\nconditons: []\n", "cfg.yaml:2: conditons: unknown key (did you mean 'conditions'?)"),
        # unknown key in a condition
        ("seed: 1\nconditions:\n  - name: a\n    recipe: blob\n    repeat: 2\n",
         "cfg.yaml:5: conditions[0].repeat: unknown key (did you mean 'repeats'?)"),
        # unknown recipe parameter
        ("seed: 1\nconditions:\n  - name: a\n    recipe: blob\n    params: {sigmma: 0.1}\n",
         "cfg.yaml:5: conditions[0].params.sigmma: unknown key (did you mean 'sigma'?)"),
        # wrong type
        ("seed: 1\ncanvas:\n  width: abc\nconditions:\n  - name: a\n    recipe: blob\n",
         "cfg.yaml:3: canvas.width: must be an integer, got 'abc'"),
        ("seed: 1.5\nconditions:\n  - name: a\n    recipe: blob\n", "cfg.yaml:1: seed: must be an integer"),
        # negative size
        ("seed: 1\ncanvas: {width: -64}\nconditions:\n  - name: a\n    recipe: blob\n",
         "cfg.yaml:2: canvas.width: must be >= 8, got -64"),
        # a recipe parameter out of range, in a grid: the path names the list item
        ("seed: 1\nconditions:\n  - name: a\n    recipe: radial_frequency\n    grid:\n"
         "      amplitude: [0.05,\n                  -0.1]\n",
         "cfg.yaml:7: conditions[0].grid.amplitude[1]: must be >= 0"),
        # ... in a nested base shape
        ("seed: 1\nconditions:\n  - name: a\n    recipe: deformation\n    params:\n"
         "      base: {generator: attneave_polygon, params: {n_points: 2}}\n",
         "cfg.yaml:6: conditions[0].params.base.params.n_points: must be >= 3, got 2"),
        # ... in a nested base shape through a dotted grid key
        ("seed: 1\nconditions:\n  - name: a\n    recipe: guided\n    grid:\n      base.params.n_points: [6, 1]\n",
         "cfg.yaml:6: conditions[0].grid.base.params.n_points[1]: must be >= 3, got 1"),
        # condition-level overrides are blamed, not the top-level values
        ("seed: 1\nconditions:\n  - name: a\n    recipe: blob\n    style: {figure: 2}\n",
         "cfg.yaml:5: conditions[0].style.figure: must be a grey level in [0, 1] or an [r, g, b] triple of them, got 2"),
        ("seed: 1\nstyle: {figure: abc}\nconditions:\n  - name: a\n    recipe: blob\n",
         "cfg.yaml:2: style.figure: must be a grey level in [0, 1] or an [r, g, b] triple of them, got 'abc'"),
        ("seed: 1\ncanvas: {width: 64}\nconditions:\n  - name: a\n    recipe: blob\n    canvas: {margin: 40}\n",
         "cfg.yaml:6: conditions[0].canvas.margin: must be <= 28"),
        ("seed: 1\nconditions:\n  - name: a\n    recipe: blobb\n",
         "cfg.yaml:4: conditions[0].recipe: unknown recipe 'blobb' (did you mean 'blob'?)"),
        ("seed: 1\nconditions:\n  - name: a\n    recipe: blob\n  - name: a\n    recipe: blob\n",
         "cfg.yaml:5: conditions[1].name: condition name 'a' is used twice"),
        ("seed: 1\nconditions:\n  - name: ../up\n    recipe: blob\n", "cfg.yaml:3: conditions[0].name: must match"),
        ("seed: 1\nconditions:\n  - name: a\n    recipe: blob\n    params: {n: 64}\n    grid: {n: [64, 128]}\n",
         "cfg.yaml:6: conditions[0].grid.n: 'n' is also in params"),
        ("seed: 1\nconditions:\n  - name: a\n    recipe: blob\n    grid: {n: 64}\n",
         "cfg.yaml:5: conditions[0].grid.n: must be a list, got 64"),
        ("seed: 1\nconditions:\n  - name: a\n    recipe: from_csv\n    params: {path: nothere.csv}\n",
         "cfg.yaml:5: conditions[0].params.path: no such file 'nothere.csv'"),
        ("seed: 1\noutput: {png_bit_depth: 12}\nconditions:\n  - name: a\n    recipe: blob\n",
         "cfg.yaml:2: output.png_bit_depth: must be 8 or 16, got 12"),
        ("conditions:\n  - name: a\n    recipe: blob\n", "cfg.yaml:1: seed: required key is missing"),
        # broken YAML: the line (and column) of the problem
        ("seed: 1\nconditions:\n  - name: a\n   recipe: blob\n", "cfg.yaml:4:4: invalid YAML"),
        ("seed: [1, 2\n", "cfg.yaml:2:1: invalid YAML"),
        ("", "cfg.yaml: the config is empty"),
        ("- seed\n", "cfg.yaml: the config must be a mapping"),
    ],
)
def test_errors_are_one_line_naming_file_line_and_key_path(tmp_path, text, where):
    msg = _error(tmp_path, text)
    assert msg.startswith(str(tmp_path / "cfg.yaml")[: -len("cfg.yaml")]), msg
    assert where in msg, msg


def test_grid_is_the_product_of_its_lists_first_key_slowest(tmp_path):
    b = load_config(_write(tmp_path, GOOD))
    poly, rf = b.conditions
    assert [c["n_points"] for c in poly.cells] == [5, 8]
    assert poly.n_jobs == 4 and rf.n_jobs == 6 and b.n_jobs == 10
    expected = list(itertools.product([3, 5], [0.05, 0.1, 0.2]))
    # the recipe turns a lone frequency/amplitude into a one-element list
    got = [(c["frequency"][0], c["amplitude"][0]) for c in rf.cells]
    assert got == expected
    # fixed params go to every cell, recipe defaults are filled in
    assert all(c["n"] == 256 and c["r0"] == 100.0 for c in rf.cells)


def test_resolved_config_has_defaults_version_and_is_a_fixed_point(tmp_path):
    b = load_config(_write(tmp_path, GOOD))
    text = b.text
    assert "attneave_version: " in text
    assert "line_width: 3.0" in text  # a Style default
    assert "min_angle: 10.0" in text  # a recipe default
    assert "margin: 4.0" in text
    assert str(tmp_path) not in text
    # grid axes stay in `grid`, not in `params`
    assert "frequency: [3, 5]" in text
    # the resolved config, read back, resolves to itself byte for byte
    again = load_config(_write(tmp_path, text, "resolved.yaml"))
    assert again.text == text and again.sha256 == b.sha256
    # and a different seed gives a different config identity
    other = load_config(_write(tmp_path, GOOD.replace("seed: 5", "seed: 6"), "other.yaml"))
    assert other.sha256 != b.sha256


def test_relative_paths_resolve_against_the_config_and_are_recorded_as_written(tmp_path):
    sub = tmp_path / "shapes"
    sub.mkdir()
    (sub / "tri.csv").write_text("x,y\n0,0\n10,0\n0,10\n")
    cfgdir = tmp_path / "cfgs"
    cfgdir.mkdir()
    text = "seed: 1\nconditions:\n  - name: c\n    recipe: from_csv\n    params: {path: ../shapes/tri.csv}\n"
    b = load_config(_write(cfgdir, text))
    cond = b.conditions[0]
    assert Path(cond.cells[0]["path"]).is_absolute()
    assert Path(cond.cells[0]["path"]).samefile(sub / "tri.csv")
    assert cond.recorded_cells[0]["path"] == "../shapes/tri.csv"
    assert "path: ../shapes/tri.csv" in b.text and str(tmp_path) not in b.text


def test_stimulus_seed_is_the_documented_seedsequence():
    # computed here independently of the module: SeedSequence(seed, spawn_key=(c, k, r))
    for c, k, r in [(0, 0, 0), (2, 7, 3)]:
        want = int(np.random.SeedSequence(42, spawn_key=(c, k, r)).generate_state(1, np.uint64)[0])
        assert stimulus_seed(42, c, k, r) == want
    seeds = {stimulus_seed(42, c, k, r) for c in range(3) for k in range(4) for r in range(5)}
    assert len(seeds) == 60


def test_config_and_make_say_the_same_for_the_same_mistake(tmp_path):
    from attneave.stimuli.batch.recipes import make

    for params, key in [({"sigmma": 0.1}, "sigmma"), ({"sigma": -0.5}, "sigma"), ({"n": "many"}, "n")]:
        text = f"seed: 1\nconditions:\n  - name: a\n    recipe: blob\n    params: {params}\n"
        from_config = _error(tmp_path, text).split(f"conditions[0].params.{key}: ", 1)[1]
        with pytest.raises(InputError) as exc:
            make("blob", 1, **params)
        assert str(exc.value) == f"blob: {key}: {from_config}"
