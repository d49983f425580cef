"""`attneave simulate`, `attneave analyze` and `attneave power` end to end."""

import json
import math
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from attneave.cli import main
from attneave.stimuli.stimulus_set import write_stimulus_set

W, H = 480, 400


def _shapes():
    th = np.linspace(0, 2 * np.pi, 300, endpoint=False)
    c = np.array([240.0, 200.0])
    out = {}
    for i in range(3):
        out[f"ellipse_{i}"] = np.c_[c[0] + 150 * np.cos(th), c[1] + (50 + 30 * i) * np.sin(th)]
    for i in range(3):
        r = 110 * (1 + (0.12 + 0.04 * i) * np.cos((3 + i) * th))
        out[f"rf_{i}"] = np.c_[c[0] + r * np.cos(th), c[1] + r * np.sin(th)]
    rng = np.random.default_rng(0)
    for i in range(2):
        a = np.sort(rng.uniform(0, 2 * np.pi, 10 + 2 * i))
        r = 150 * rng.uniform(0.5, 1.0, len(a))
        out[f"polygon_{i}"] = np.c_[c[0] + r * np.cos(a), c[1] + r * np.sin(a)]
    return out


@pytest.fixture(scope="module")
def stimset(tmp_path_factory):
    d = tmp_path_factory.mktemp("stimuli")
    write_stimulus_set(d, _shapes(), size=(W, H))
    # one stimulus has its image file; the others have none (allowed)
    import cv2

    (d / "images").mkdir(exist_ok=True)
    img = np.full((H, W), 255, np.uint8)
    cv2.ellipse(img, (240, 200), (150, 50), 0, 0, 360, 0, -1)
    cv2.imwrite(str(d / "images" / "ellipse_0.png"), img)
    return d


@pytest.fixture(scope="module")
def clicks(stimset, tmp_path_factory):
    f = tmp_path_factory.mktemp("clicks") / "clicks.csv"
    rc = main(["simulate", "--stimuli", str(stimset), "-o", str(f), "--participants", "8", "--clicks", "5",
               "--beta", "1.0", "--seed", "3", "--noise", "1.0"])
    assert rc == 0
    return f


def _analyze(clicks, stimset, out, *extra):
    return main(["analyze", str(clicks), "--stimuli", str(stimset), "-o", str(out), "--permutations", "200", *extra])


def test_analyze_writes_every_output(stimset, clicks, tmp_path, capsys):
    out = tmp_path / "out"
    assert _analyze(clicks, stimset, out) == 0
    assert "used" in capsys.readouterr().out
    names = {p.name for p in out.iterdir()}
    assert {"clicks.csv", "per_stimulus.csv", "per_participant.csv", "models.csv", "summary.json",
            "report.html", "figures"} <= names
    s = json.loads((out / "summary.json").read_text())
    for key in ("n_clicks", "n_used", "n_excluded", "exclusions", "beta_hat", "beta_ci", "group"):
        assert key in s
    assert {"test", "statistic", "p_value", "effect_size", "p_value_parametric"} <= set(s["group"])
    assert "Monte Carlo" in s["group"]["test"] and s["group"]["simulations"] == 1999
    assert s["group"]["alternative"] == "greater" and "wilcoxon" not in s["group"]
    # the t-test of per-participant betas is not calibrated: descriptive, without a p_value
    assert "p_value" not in s["participant_beta"] and "p_value_parametric" in s["participant_beta"]
    assert s["group"]["p_value"] >= 1 / 2000 and s["by_stimulus"]["p_value"] >= 1 / 2000
    # the statistic is the one-sample t of the per-participant mean z in per_participant.csv
    mz = pd.read_csv(out / "per_participant.csv")["mean_z"].dropna()
    import scipy.stats

    assert s["group"]["statistic"] == pytest.approx(scipy.stats.ttest_1samp(mz, 0.0).statistic, rel=1e-9)
    assert s["n_clicks"] == 8 * 8 * 5 and s["n_used"] + s["n_excluded"] == s["n_clicks"]
    assert s["group"]["p_value"] < 0.05 and s["beta_hat"] > 0
    from attneave.analysis.models.predictors import RIVALS

    assert set(s["models"]) == {"surprisal", "uniform", *RIVALS} - set(s["models_left_out"])
    assert s["models"]["surprisal"]["tested"] and "vonmises" not in s["models"]
    # the output contract: unit of length, portable effect, joint predictors, mixed model
    assert s["length_unit"] == s["params"]["length_unit"] and isinstance(s["length_unit"], str)
    e = s["effect"]
    assert e["chance_share"] == 0.1 and e["lift"] == pytest.approx(e["top_share"] / 0.1)
    assert set(s["predictors"]) == {"surprisal"}
    j = s["predictors"]["surprisal"]
    # one predictor fitted jointly is the pooled fit
    assert j["coef"] == pytest.approx(s["beta_hat"], abs=1e-6) and j["ci_low"] < j["coef"] < j["ci_high"]
    assert 0 <= j["lr_p"] <= 1
    m = s["mixed"]
    assert m["ci_low"] < m["beta"] < m["ci_high"] and m["sd_participant"] >= 0 and m["sd_stimulus"] >= 0
    assert {"points.csv", "choices.csv", "analysis.R"} <= {p.name for p in out.iterdir()}
    ch = pd.read_csv(out / "choices.csv")
    assert len(ch) == s["n_used"] * 100 and ch.groupby("choice_set")["chosen"].sum().eq(1).all()
    figs = sorted(p.name for p in (out / "figures").iterdir())
    # 8 stimuli, 6 per page; each figure as PNG and SVG
    assert figs == sorted(f"{k}.{e}" for k in ("group", "stimuli_001", "stimuli_002") for e in ("png", "svg"))
    html = (out / "report.html").read_text()
    assert html.count('src="data:image/png;base64,') == 3 and "http" not in html.split("<body>")[1]
    per_s = pd.read_csv(out / "per_stimulus.csv")
    assert len(per_s) == 8 and per_s["n_used"].sum() == s["n_used"]
    assert len(pd.read_csv(out / "per_participant.csv")) == 8
    # nothing else is left beside the output directory
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_same_inputs_give_identical_files(stimset, clicks, tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    assert _analyze(clicks, stimset, a, "--no-figures") == 0
    assert _analyze(clicks, stimset, b, "--no-figures") == 0
    for name in ("clicks.csv", "per_stimulus.csv", "per_participant.csv", "models.csv"):
        assert (a / name).read_bytes() == (b / name).read_bytes()
    sa, sb = (json.loads((d / "summary.json").read_text()) for d in (a, b))
    sa.pop("inputs"), sb.pop("inputs")
    assert sa == sb


def _num_equal(a, b, cols):
    for c in cols:
        x, y = a[c], b[c]
        if pd.api.types.is_numeric_dtype(x) and pd.api.types.is_numeric_dtype(y):
            np.testing.assert_allclose(x.to_numpy(float), y.to_numpy(float), rtol=1e-9, atol=1e-9, err_msg=c)
        else:
            assert x.fillna("").astype(str).tolist() == y.fillna("").astype(str).tolist(), c


def _same_summary(a, b, path=""):
    if isinstance(a, dict):
        assert set(a) == set(b), path
        for k in a:
            if k not in ("inputs", "coords", "scale"):
                _same_summary(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _same_summary(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and isinstance(b, float):
        assert math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-9), (path, a, b)
    else:
        assert a == b, path


def test_image_and_centered_coordinates_give_identical_results(stimset, clicks, tmp_path):
    df = pd.read_csv(clicks)
    # PsychoPy 'pix', image drawn 1.5x at the window centre: origin at the image
    # centre ((W-1)/2, (H-1)/2 in pixel-centre coordinates), y up, 1.5 screen px per image px
    cen = df.assign(x=(df["x"] - (W - 1) / 2) * 1.5, y=((H - 1) / 2 - df["y"]) * 1.5)
    cen.to_csv(tmp_path / "centered.csv", index=False, float_format="%.17g")
    # the same image shown at 2x in image coordinates: shown pixel-centre = (x + 0.5) * 2 - 0.5
    big = df.assign(x=(df["x"] + 0.5) * 2 - 0.5, y=(df["y"] + 0.5) * 2 - 0.5)
    big.to_csv(tmp_path / "big.csv", index=False, float_format="%.17g")
    runs = {
        "image": [],
        "centered": ["--coords", "centered", "--scale", "1.5"],
        "big": ["--scale", "2"],
    }
    res = {}
    for name, extra in runs.items():
        src = clicks if name == "image" else tmp_path / f"{name}.csv"
        assert _analyze(src, stimset, tmp_path / name, "--no-figures", *extra) == 0
        res[name] = {f: pd.read_csv(tmp_path / name / f) for f in ("clicks.csv", "per_stimulus.csv",
                                                                  "per_participant.csv", "models.csv")}
        res[name]["summary"] = json.loads((tmp_path / name / "summary.json").read_text())
    mapped = ["x_image", "y_image", "nearest_x", "nearest_y", "distance", "t", "point", "curvature", "surprisal",
              "z", "surprisal_percentile", "concave", "peak_hit", "excluded", "reason"]
    for name in ("centered", "big"):
        _num_equal(res["image"]["clicks.csv"], res[name]["clicks.csv"], mapped)
        for f in ("per_stimulus.csv", "per_participant.csv", "models.csv"):
            _num_equal(res["image"][f], res[name][f], res["image"][f].columns)
        _same_summary(res["image"]["summary"], res[name]["summary"])
        assert res[name]["summary"]["params"]["coords"] == ("centered" if name == "centered" else "image")


def test_bad_rows_are_kept_with_reasons_and_counted(stimset, clicks, tmp_path):
    good = pd.read_csv(clicks, dtype=str, keep_default_na=False)
    bad = pd.DataFrame(
        [
            dict(participant="P001", stimulus_id="rf_0", x="", y="10"),          # NaN (empty)
            dict(participant="P001", stimulus_id="rf_0", x="NaN", y="10"),       # NaN (written)
            dict(participant="P001", stimulus_id="rf_0", x="left", y="10"),      # text in x
            dict(participant="P002", stimulus_id="no_such", x="240", y="200"),   # unknown stimulus
            dict(participant="P002", stimulus_id="rf_0", x="5", y="5"),          # far from the contour
            dict(participant="P002", stimulus_id="rf_0", x="240", y="200"),      # the centre: far
            dict(participant="P003", stimulus_id="rf_1", x="900", y="10"),       # outside the image
            dict(participant="", stimulus_id="rf_1", x="240", y="90"),           # no participant
        ]
    ).reindex(columns=good.columns, fill_value="")
    rows = pd.concat([good.iloc[:7], bad, good.iloc[7:]], ignore_index=True)
    f = tmp_path / "dirty.csv"
    rows.to_csv(f, index=False)
    out = tmp_path / "out"
    assert _analyze(f, stimset, out, "--no-figures") == 0
    c = pd.read_csv(out / "clicks.csv", dtype=str, keep_default_na=False)
    assert len(c) == len(rows) and c["line"].tolist() == [str(i + 2) for i in range(len(rows))]
    assert c["x"].tolist() == rows["x"].tolist()  # passed through as written
    assert c["reason"].iloc[7:15].tolist() == [
        "missing_coordinate", "missing_coordinate", "non_numeric_coordinate", "unknown_stimulus",
        "far_from_contour", "far_from_contour", "outside_image", "missing_participant",
    ]
    s = json.loads((out / "summary.json").read_text())
    counted = c.loc[c["excluded"] == "True", "reason"].value_counts().to_dict()
    assert {k: v for k, v in s["exclusions"].items() if v} == counted
    assert s["n_clicks"] == len(rows) and s["n_excluded"] == sum(counted.values()) == (c["excluded"] == "True").sum()
    assert s["n_used"] == (c["reason"] == "").sum()
    # the simulated clicks had noise 1 px: none of them was excluded
    assert s["n_used"] == len(good)


def test_column_mapping(stimset, clicks, tmp_path):
    df = pd.read_csv(clicks, dtype=str, keep_default_na=False)
    df.rename(columns={"participant": "subj", "stimulus_id": "stim", "x": "mouse_x", "y": "mouse_y"}).to_csv(
        tmp_path / "renamed.csv", index=False)
    assert _analyze(tmp_path / "renamed.csv", stimset, tmp_path / "m", "--no-figures",
                    "--columns", "participant=subj,stimulus_id=stim,x=mouse_x,y=mouse_y") == 0
    assert _analyze(clicks, stimset, tmp_path / "plain", "--no-figures") == 0
    a = json.loads((tmp_path / "m" / "summary.json").read_text())
    b = json.loads((tmp_path / "plain" / "summary.json").read_text())
    assert a["beta_hat"] == b["beta_hat"] and a["group"] == b["group"]


def test_group_simulations_option(stimset, clicks, tmp_path, capsys):
    assert _analyze(clicks, stimset, tmp_path / "r99", "--no-figures", "--group-simulations", "99") == 0
    g = json.loads((tmp_path / "r99" / "summary.json").read_text())["group"]
    assert g["simulations"] == 99 and "R = 99" in g["test"] and 0.01 <= g["p_value"] <= 1
    assert "Monte Carlo p" in capsys.readouterr().out
    assert _analyze(clicks, stimset, tmp_path / "bad", "--no-figures", "--group-simulations", "-1") == 2
    assert "--group-simulations" in capsys.readouterr().err and not (tmp_path / "bad").exists()


def test_unusable_click_file_exits_2_with_one_line_and_writes_nothing(stimset, tmp_path):
    f = tmp_path / "clicks.csv"
    f.write_text("participant,stimulus_id,x\nP1,rf_0,3\n")
    out = tmp_path / "out"
    p = subprocess.run([sys.executable, "-m", "attneave.cli", "analyze", str(f), "--stimuli", str(stimset),
                        "-o", str(out)], capture_output=True, text=True, timeout=60)
    assert p.returncode == 2
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("attneave analyze: error:") and "missing column(s) y" in lines[0]
    assert "Traceback" not in p.stderr and p.stdout == ""
    assert sorted(x.name for x in tmp_path.iterdir()) == ["clicks.csv"]


def test_broken_stimulus_set_exits_2(stimset, clicks, tmp_path, capsys):
    assert main(["analyze", str(clicks), "--stimuli", str(tmp_path / "none"), "-o", str(tmp_path / "o")]) == 2
    assert "not a directory" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_existing_output_is_kept_unless_forced(stimset, clicks, tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    assert _analyze(clicks, stimset, out, "--no-figures") == 2
    assert "not empty" in capsys.readouterr().err and (out / "keep.txt").exists()
    # --force never deletes a user's file: it replaces only an earlier analysis output
    assert _analyze(clicks, stimset, out, "--no-figures", "--force") == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "keep.txt" in err and "earlier analysis output" in err
    assert (out / "keep.txt").read_text() == "mine" and not (out / "summary.json").exists()
    (out / "keep.txt").unlink()
    assert _analyze(clicks, stimset, out, "--no-figures", "--group-simulations", "19") == 0
    first = (out / "summary.json").read_text()
    assert _analyze(clicks, stimset, out, "--no-figures", "--force", "--group-simulations", "19") == 0
    assert (out / "summary.json").read_text() == first
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_failure_while_writing_leaves_no_output(stimset, clicks, tmp_path, monkeypatch):
    from attneave.analysis.report import plots

    def boom(analysis):
        raise RuntimeError("disk full")

    monkeypatch.setattr(plots, "all_figures", boom)
    with pytest.raises(RuntimeError):
        _analyze(clicks, stimset, tmp_path / "out")
    assert list(tmp_path.iterdir()) == []


def test_power_command(stimset, capsys):
    assert main(["power", "--stimuli", str(stimset), "--beta", "0.4", "--participants", "3,6",
                 "--clicks", "2", "--simulations", "40"]) == 0
    out = capsys.readouterr().out
    assert "participants for power >= 0.8" in out and "power" in out


def test_simulate_rejects_bad_values(stimset, tmp_path, capsys):
    assert main(["simulate", "--stimuli", str(stimset), "-o", str(tmp_path / "c.csv"), "--participants", "0",
                 "--clicks", "2", "--beta", "1", "--seed", "1"]) == 2
    assert "--participants" in capsys.readouterr().err and not (tmp_path / "c.csv").exists()


def test_bad_predictor_names_are_one_line_exit_2(stimset, clicks, tmp_path, capsys):
    rc = _analyze(clicks, stimset, tmp_path / "o", "--no-figures", "--predictors", "surprisal,wiggliness")
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "--predictors" in err and "concavity" in err
    assert not (tmp_path / "o").exists()
