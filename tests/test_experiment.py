"""`attneave experiment`: options, calibration maths, seeded order, Latin square, files, PsychoPy export, CLI."""

import json
import math
import os
import py_compile
import shutil
import subprocess

import numpy as np
import pandas as pd
import pytest

from attneave.analysis.experiment import calibration, order
from attneave.analysis.experiment.options import ExperimentOptions, load_options
from attneave.cli import main
from attneave.stimuli.errors import InputError

from helpers import W


def test_57_cm_gives_one_cm_per_degree():
    d_mm = 5.0 / math.tan(math.radians(0.5))  # 57.29 cm
    assert d_mm == pytest.approx(572.943, abs=1e-3)
    assert calibration.px_per_degree(1.0, d_mm) == pytest.approx(10.0, rel=1e-12)  # 10 px of 1 mm = 1 cm


def test_px_per_degree_by_hand():
    # 4 px/mm at 60 cm: 4 * 2 * 600 * tan(0.5 deg) = 41.8883 px (hand computed: tan(0.5 deg) = 0.00872687)
    assert calibration.px_per_degree(4.0, 600.0) == pytest.approx(4 * 2 * 600 * 0.00872687, rel=1e-6)
    assert calibration.degrees_to_px(6.0, 41.8883) == pytest.approx(251.33, abs=0.01)


def test_card_calibration():
    # a card drawn 323.5 CSS px wide on a 96-dpi screen (3.7795 px/mm) is 85.6 mm
    assert calibration.px_per_mm_from_card(323.5) == pytest.approx(96 / 25.4, rel=1e-3)
    assert calibration.CARD_WIDTH_MM == 85.60
    with pytest.raises(ValueError):
        calibration.px_per_mm_from_card(0)


def test_linear_scale_error_against_exact_size():
    # exact width of a centred 10-deg stimulus at 57.29 cm: 2 * d * tan(5 deg) = 100.25 mm, not 100
    d_mm = 5.0 / math.tan(math.radians(0.5))
    assert calibration.exact_degrees_to_mm(10.0, d_mm) == pytest.approx(100.252, abs=1e-3)
    assert calibration.linear_error(10.0) == pytest.approx(0.00252, abs=1e-5)
    assert calibration.linear_error(1.0) == pytest.approx(0.0, abs=1e-12)


# ------------------------------------------------------------------ order

def test_fnv_and_mulberry_reference_values():
    assert order.fnv1a32("") == 0x811C9DC5
    assert order.fnv1a32("a") == 0xE40C292C           # FNV reference test vector
    assert order.fnv1a32("foobar") == 0xBF9CF968      # FNV reference test vector
    r = order.mulberry32(1)
    # first outputs of mulberry32(1) as printed by the reference JavaScript
    assert [r() for _ in range(3)] == [0.6270739405881613, 0.002735721180215478, 0.5274470399599522]


def test_shuffle_is_a_reproducible_permutation():
    ids = [f"s{i}" for i in range(30)]
    a = order.trial_order("P01", ids)
    assert sorted(a) == sorted(ids) and a != ids
    assert order.trial_order("P01", ids) == a
    assert order.trial_order("P02", ids) != a
    assert order.trial_order("P01", ids, seed="study2") != a
    assert order.trial_order("P01", ids, order="fixed") == ids


def test_shuffle_is_uniform():
    # each of the 6 orders of 3 items about 1/6 of the time over 6000 participants
    counts = {}
    for p in range(6000):
        o = tuple(order.trial_order(f"p{p}", "abc"))
        counts[o] = counts.get(o, 0) + 1
    assert len(counts) == 6
    assert all(abs(c - 1000) < 4 * math.sqrt(1000 * 5 / 6) for c in counts.values())


def test_blocked_order_keeps_conditions_together():
    ids = [f"{c}{i}" for c in "xyz" for i in range(4)]
    conds = [s[0] for s in ids]
    o = order.trial_order("P7", ids, conds, order="blocked")
    runs = [k for k, _ in __import__("itertools").groupby(s[0] for s in o)]
    assert sorted(runs) == ["x", "y", "z"]
    assert sorted(o) == sorted(ids)


NODE = shutil.which("node")


@pytest.mark.skipif(NODE is None, reason="node is not installed (the browser test also checks the order)")
def test_javascript_and_python_orders_are_equal():
    from importlib import resources

    js = resources.files("attneave.analysis.experiment").joinpath("static", "task.js")
    ids = [f"s{i}" for i in range(12)]
    conds = ["p" if i % 3 else "t" for i in range(12)]
    participants = ["P01", "p,02", "Zoë", "日本", "", "x" * 50]
    script = (
        f"const a = require({json.dumps(str(js))});"
        f"const ids = {json.dumps(ids)}, conds = {json.dumps(conds)};"
        f"const out = {json.dumps(participants)}.map(p => [a.fnv1a32(p), a.trialOrder(p, ids, conds, 'random', 's'),"
        f" a.trialOrder(p, ids, conds, 'blocked', ''), a.participantList(p, 3, 's')]);"
        "console.log(JSON.stringify(out));"
    )
    got = json.loads(subprocess.run([NODE, "-e", script], capture_output=True, text=True, check=True).stdout)
    for p, (h, rand, blocked, lst) in zip(participants, got):
        assert h == order.fnv1a32(p)
        assert rand == order.trial_order(p, ids, conds, "random", "s")
        assert blocked == order.trial_order(p, ids, conds, "blocked", "")
        assert lst == order.participant_list(p, 3, "s")


def test_latin_square_separates_conditions_of_an_item():
    ids = ["a_p", "a_t", "b_p", "b_t", "c_p", "c_t", "f"]
    items = ["a", "a", "b", "b", "c", "c", "f"]
    conds = ["p", "t", "p", "t", "p", "t", "filler"]
    lists = order.latin_square_lists(ids, items, conds, 2)
    assert lists == {"a_p": [1], "a_t": [2], "b_p": [2], "b_t": [1], "c_p": [1], "c_t": [2], "f": [1, 2]}
    for k in (1, 2):
        seen = [s for s in ids if k in lists[s]]
        # one stimulus per item in each list, and both conditions in each list
        assert len({items[ids.index(s)] for s in seen}) == len(seen)
        assert {"p", "t"} <= {conds[ids.index(s)] for s in seen}


def test_latin_square_three_conditions_is_balanced():
    ids = [f"{i}{c}" for i in range(6) for c in "xyz"]
    lists = order.latin_square_lists(ids, [s[0] for s in ids], [s[1] for s in ids], 3)
    for k in (1, 2, 3):
        mine = [s for s in ids if lists[s] == [k]]
        assert len(mine) == 6 and sorted(s[1] for s in mine) == sorted("xxyyzz")
        assert len({s[0] for s in mine}) == 6


def test_latin_square_refuses_too_few_lists():
    with pytest.raises(InputError, match="item 'a' has 3 stimuli"):
        order.latin_square_lists(["1", "2", "3"], ["a"] * 3, ["x", "y", "z"], 2)


# ------------------------------------------------------------------ options

def test_options_defaults_and_done_mode():
    o = load_options(overrides={"clicks": "done", "min_clicks": "2", "max_clicks": "6"})
    assert (o.clicks, o.min_clicks, o.max_clicks, o.size_deg) == ("done", 2, 6, 10.0)
    assert ExperimentOptions(size_px=300).size_deg is None
    assert ExperimentOptions(background=0.5).grey == "#808080"
    assert ExperimentOptions(background="#abc").grey == "#aabbcc"
    assert ExperimentOptions(practice="a, b").practice == ["a", "b"]


@pytest.mark.parametrize("overrides, expected", [
    ({"clicks": "0"}, "--clicks: expected a whole number >= 1 or 'done'"),
    ({"clicks": "many"}, "--clicks: expected a whole number >= 1 or 'done'"),
    ({"size_deg": -2.0}, "--size-deg: Input should be greater than 0"),
    ({"break_every": "-1"}, "--break-every: expected a whole number >= 0"),
    ({"background": "red"}, "--background: expected 'auto', '#rrggbb' or a grey level"),
    ({"submit_url": "ftp://x"}, "--submit-url: expected an http(s) URL"),
    ({"size_deg": 5.0, "size_px": 200.0}, "size_deg and size_px: give one of them"),
    ({"min_clicks": "2"}, "min_clicks and max_clicks apply only with clicks: done"),
    ({"clicks": "done", "min_clicks": "3", "max_clicks": "2"}, "max_clicks (2) is smaller than min_clicks (3)"),
])
def test_bad_option_values_name_the_flag(overrides, expected):
    with pytest.raises(InputError) as exc:
        load_options(overrides=overrides)
    assert expected in str(exc.value)
    assert "\n" not in str(exc.value)


def test_yaml_errors_name_file_line_and_key(tmp_path):
    f = tmp_path / "exp.yaml"
    f.write_text("clicks: 3\nbreak_evry: 4\n")
    with pytest.raises(InputError, match=r"exp.yaml: line 2: break_evry: unknown key \(did you mean 'break_every'\?\)"):
        load_options(f)
    f.write_text("clicks: 3\n\nfixation_ms: -5\n")
    with pytest.raises(InputError, match=r"exp.yaml: line 3: fixation_ms: expected a whole number >= 0, got -5"):
        load_options(f)
    f.write_text("- a\n- b\n")
    with pytest.raises(InputError, match="expected a mapping"):
        load_options(f)
    f.write_text("clicks: 3\n")
    # a flag wins over the file
    assert load_options(f, {"clicks": "7"}).clicks == 7


def test_shipped_example_config_is_valid():
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "configs" / "experiment.yaml"
    o = load_options(path)
    assert o.clicks == "done" and o.practice == 2


# ------------------------------------------------------------------ building

def _build(stimset, out, *extra):
    return main(["experiment", str(stimset), "-o", str(out), *extra])


def _config(out):
    html = (out / "index.html").read_text()
    start = html.index('id="attneave-config">') + len('id="attneave-config">')
    return json.loads(html[start:html.index("</script>", start)])


def test_build_writes_a_self_contained_directory(stimset, tmp_path):
    out = tmp_path / "exp"
    assert _build(stimset, out, "--lists", "2", "--practice", "filler", "--instructions", "Click </script> here",
                  "--clicks", "4") == 0
    names = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    assert names == sorted(["index.html", "task.js", "task.css", "experiment.json"]
                           + [f"images/{s}.png" for s in ("a_peaks", "a_troughs", "b_peaks", "b_troughs",
                                                          "c_peaks", "c_troughs", "filler")])
    html = (out / "index.html").read_text()
    assert "http://" not in html and "https://" not in html  # no CDN
    assert "Click </script> here" not in html                 # cannot close the script block
    cfg = _config(out)
    assert cfg["instructions"] == "Click </script> here"
    assert cfg["background"] == "#808080"                     # the images' ground, 128
    assert cfg["clicks"] == cfg["min_clicks"] == cfg["max_clicks"] == 4
    assert [s["id"] for s in cfg["practice"]] == ["filler"]
    lists = {s["id"]: s["lists"] for s in cfg["stimuli"]}
    assert lists == {"a_peaks": [1], "a_troughs": [2], "b_peaks": [2], "b_troughs": [1], "c_peaks": [1],
                     "c_troughs": [2]}
    assert cfg["scale"] == {"max_side": W, "size_deg": 10.0, "size_px": None}
    assert (out / "images" / "a_peaks.png").read_bytes() == (stimset / "images" / "a_peaks.png").read_bytes()


def test_conditions_filter_and_first_k_practice(stimset, tmp_path):
    out = tmp_path / "exp"
    assert _build(stimset, out, "--conditions", "peaks,filler", "--practice", "1", "--px-per-deg", "30") == 0
    cfg = _config(out)
    assert [s["id"] for s in cfg["practice"]] == ["a_peaks"]
    assert [s["id"] for s in cfg["stimuli"]] == ["b_peaks", "c_peaks", "filler"]
    assert cfg["px_per_deg"] == 30.0


def test_background_colour_is_the_commonest_corner(tmp_path):
    import cv2

    from attneave.analysis.experiment.build import background_colour

    paths = []
    for i, ground in enumerate([200, 200, 30]):
        img = np.full((10, 10, 3), ground, np.uint8)
        img[0, 0] = (0, 0, 255)  # a figure touching a corner (red, in BGR)
        paths.append(tmp_path / f"{i}.png")
        cv2.imwrite(str(paths[-1]), img)
    assert background_colour(paths) == "#c8c8c8"
    img16 = np.full((4, 4), 257 * 100, np.uint16)  # 16 bit: 25700 / 257 = 100 in 8 bit
    cv2.imwrite(str(tmp_path / "g16.png"), img16)
    assert background_colour([tmp_path / "g16.png"]) == "#646464"


def test_rebuild_replaces_a_previous_experiment_but_not_user_files(stimset, tmp_path, capsys):
    out = tmp_path / "exp"
    assert _build(stimset, out) == 0
    assert _build(stimset, out, "--clicks", "2") == 0          # ours: replaced
    assert _config(out)["clicks"] == 2
    (out / "results.csv").write_text("participant data\n")     # now it holds a user's file
    capsys.readouterr()
    assert _build(stimset, out, "--clicks", "3") == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "not empty" in err and "--force" in err
    assert _config(out)["clicks"] == 2
    assert _build(stimset, out, "--clicks", "3", "--force") == 0
    assert (tmp_path / "exp.old-1" / "results.csv").read_text() == "participant data\n"  # moved aside, not deleted
    assert _config(out)["clicks"] == 3
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary left


@pytest.mark.parametrize("args, message", [
    (["--practice", "nope"], "practice[0]: stimulus 'nope' is not in"),
    (["--practice", "7"], "practice: 7 practice stimuli would leave no main trials"),
    (["--conditions", "peeks"], "conditions[0]: no stimulus of"),
    (["--lists", "1", "--clicks", "x"], "--clicks: expected a whole number"),
    (["--psychopy", "--monitor", "lab", "--size-px", "300"], "psychopy_units: 'deg' needs size_deg"),
    (["--psychopy", "--psychopy-units", "deg"], "--psychopy-units: 'deg' needs --monitor NAME"),
])
def test_cli_errors_are_one_line_and_write_nothing(stimset, tmp_path, capsys, args, message):
    out = tmp_path / "exp"
    assert _build(stimset, out, *args) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_missing_image_and_wrong_size_are_refused(stimset, tmp_path, capsys):
    import cv2

    bad = tmp_path / "set"
    shutil.copytree(stimset, bad)
    (bad / "images" / "b_peaks.png").unlink()
    assert _build(bad, tmp_path / "exp") == 2
    assert "b_peaks" in capsys.readouterr().err
    cv2.imwrite(str(bad / "images" / "b_peaks.png"), np.zeros((10, 10), np.uint8))
    assert _build(bad, tmp_path / "exp") == 2
    assert "is 10 x 10 px but the manifest says 160 x 120" in capsys.readouterr().err


def test_more_lists_needed_is_an_error(stimset, tmp_path, capsys):
    m = pd.read_csv(stimset / "manifest.csv", dtype=str, keep_default_na=False)
    bad = tmp_path / "set"
    shutil.copytree(stimset, bad)
    m["parent_id"] = "a"  # every stimulus one item: 7 stimuli, 2 lists
    m.to_csv(bad / "manifest.csv", index=False)
    assert _build(bad, tmp_path / "exp", "--lists", "2") == 2
    assert "--lists 2: item 'a' has 7 stimuli" in capsys.readouterr().err


# ------------------------------------------------------------------ PsychoPy

def _load_script(path):
    import importlib.util

    spec = importlib.util.spec_from_file_location("attneave_task_under_test", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)  # PsychoPy is imported in main() only
    return mod


def test_psychopy_export(stimset, tmp_path):
    out = tmp_path / "exp"
    assert _build(stimset, out, "--psychopy", "--lists", "2", "--size-deg", "8", "--practice", "1",
                  "--monitor", "lab") == 0
    cond = pd.read_csv(out / "psychopy" / "conditions.csv", dtype=str, keep_default_na=False)
    assert list(cond.columns) == ["image", "stimulus_id", "condition", "parent_id", "lists", "practice", "width_px",
                                  "height_px", "size_w", "size_h", "units"]
    assert all((out / "psychopy" / p).resolve().is_file() for p in cond["image"])
    # the largest side (160 px) is 8 deg: 0.05 deg per image pixel
    assert cond["size_w"].astype(float).tolist() == [8.0] * 7
    assert cond["size_h"].astype(float).tolist() == [6.0] * 7
    assert set(cond["units"]) == {"deg"}
    assert cond.loc[cond.stimulus_id == "a_peaks", "practice"].item() == "1"
    # a_peaks is practice, so a_troughs is alone in its item: every list; in the main trials
    # 'troughs' now appears first (rank 0), so b_troughs opens list 1 and c alternates
    lists = dict(zip(cond.stimulus_id, cond.lists))
    assert lists == {"a_peaks": "1;2;", "a_troughs": "1;2;", "b_peaks": "2;", "b_troughs": "1;", "c_peaks": "1;",
                     "c_troughs": "2;", "filler": "1;2;"}

    script = out / "psychopy" / "attneave_task.py"
    py_compile.compile(str(script), doraise=True)
    text = script.read_text()
    for needle in ("visual.Window(", "visual.ImageStim(", "event.Mouse(", "csv.DictWriter", "'units': 'deg'",
                   "VIEWING_DISTANCE_CM = 57.0", "MONITOR = 'lab'"):
        assert needle in text
    mod = _load_script(script)
    assert mod.COLUMNS[:7] == ["participant", "stimulus_id", "x", "y", "click", "trial", "rt_ms"]
    from importlib import resources
    js = resources.files("attneave.analysis.experiment").joinpath("static", "task.js").read_text()
    for col in mod.COLUMNS:
        assert f"'{col}'" in js  # the page writes the same columns
    # window units (centred, y up) -> image pixels (y down): the drawn image's corners and centre
    size = (8.0, 6.0)
    assert mod.to_image_px((-4.0, 3.0), size, 160, 120) == (-0.5, -0.5)
    assert mod.to_image_px((4.0, -3.0), size, 160, 120) == (159.5, 119.5)
    assert mod.to_image_px((0.0, 0.0), size, 160, 120) == (79.5, 59.5)
    ids = [f"s{i}" for i in range(9)]
    assert mod.trial_order("P3", ids, None, "random", "k") == order.trial_order("P3", ids, None, "random", "k")
    assert mod.participant_list("P3", 4, "") == order.participant_list("P3", 4, "")
    # the data file: rewritten after every trial, never over an earlier session's file
    data = tmp_path / "data"
    first = mod.data_path("P 3", str(data))
    assert first == str(data / "attneave_P_3.csv")
    mod.save([], first)
    assert not os.path.exists(first)  # no click yet (escape at once): no file for analyze to refuse
    row = dict.fromkeys(mod.COLUMNS, "1")
    mod.save([row], first)
    mod.save([row, row], first)  # the next trial: the whole file again
    assert len(pd.read_csv(first)) == 2 and not os.path.exists(first + ".tmp")
    second = mod.data_path("P 3", str(data))
    assert second == str(data / "attneave_P_3_2.csv")
    mod.save([row], second)
    assert len(pd.read_csv(first)) == 2 and len(pd.read_csv(second)) == 1


@pytest.mark.parametrize("units, size_w", [("pix", 160.0 * 300 / 160), ("height", 0.8)])
def test_psychopy_units(stimset, tmp_path, units, size_w):
    out = tmp_path / "exp"
    args = ["--psychopy", "--psychopy-units", units] + (["--size-px", "300"] if units == "pix" else [])
    assert _build(stimset, out, *args) == 0
    cond = pd.read_csv(out / "psychopy" / "conditions.csv")
    assert cond["size_w"].tolist() == pytest.approx([size_w] * 7)
    assert cond["size_h"].tolist() == pytest.approx([size_w * 120 / 160] * 7)
    py_compile.compile(str(out / "psychopy" / "attneave_task.py"), doraise=True)


def test_help_lists_the_command(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["experiment", "--help"])
    out = capsys.readouterr().out
    assert exc.value.code == 0 and "--submit-url" in out and "--psychopy" in out and "--lists" in out


def test_an_image_path_outside_the_set_is_refused(stimset, tmp_path, capsys):
    bad = tmp_path / "set"
    shutil.copytree(stimset, bad)
    shutil.copy(stimset / "images" / "filler.png", tmp_path / "outside.png")
    m = pd.read_csv(bad / "manifest.csv", dtype=str, keep_default_na=False)
    m.loc[m.stimulus_id == "filler", "image"] = "../outside.png"
    m.to_csv(bad / "manifest.csv", index=False)
    assert _build(bad, tmp_path / "exp") == 2
    # refused where the set is read, naming the manifest's line and column
    err = capsys.readouterr().err
    assert "line 8: column 'image' leads outside" in err and not (tmp_path / "exp").exists()
