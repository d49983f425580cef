"""Faults of `analyze`, `simulate` and `power` found by an audit: each test fails on the code before the fix.

Outputs that would destroy an input, a mixed model that crashed on a strong effect, broken stimulus
sets read silently, degenerate designs presented as estimates, noise that puts clicks off the image
silently, and power tables that cannot mean anything.
"""

import json

import numpy as np
import pandas as pd
import pytest

from attneave.cli import main
from attneave.stimuli.stimulus_set import write_stimulus_set

SIZE = 128
FAST = ["--group-simulations", "19", "--permutations", "19", "--no-figures"]


def _polygons():
    """Four irregular polygons well inside a 128 x 128 image (corners give a few high-surprisal points)."""
    rng = np.random.default_rng(1)
    out = {}
    for i in range(4):
        a = np.sort(rng.uniform(0, 2 * np.pi, 6 + i))
        r = 45 * rng.uniform(0.6, 1.0, len(a))
        out[f"poly_{i}"] = np.c_[64 + r * np.cos(a), 64 + r * np.sin(a)]
    return out


@pytest.fixture
def stimset(tmp_path):
    d = tmp_path / "set"
    write_stimulus_set(d, _polygons(), size=(SIZE, SIZE))
    return d


def _simulate(stimset, out, *extra):
    args = ["simulate", "--stimuli", str(stimset), "-o", str(out), "--participants", "4", "--clicks", "5",
            "--seed", "1", *extra]
    return main(args + ([] if any(a in extra for a in ("--beta", "--lift", "--top-share")) else ["--beta", "0.5"]))


@pytest.fixture
def clicks(stimset, tmp_path):
    f = tmp_path / "clicks.csv"
    assert _simulate(stimset, f) == 0
    return f


def _one_line(capsys, code, status=2):
    err = capsys.readouterr().err
    assert code == status and err.count("\n") == 1 and "Traceback" not in err, err
    return err


def _snapshot(d):
    return {p.relative_to(d): p.read_bytes() for p in sorted(d.rglob("*")) if p.is_file()}


# ------------------------------------------------------------ 1. outputs that would destroy an input
def test_analyze_refuses_an_output_that_holds_its_inputs_and_deletes_nothing(stimset, clicks, tmp_path, capsys):
    mine = stimset / "myclicks.csv"
    mine.write_bytes(clicks.read_bytes())
    before = _snapshot(stimset)
    code = main(["analyze", str(mine), "--stimuli", str(stimset), "-o", str(stimset), "--force", *FAST])
    err = _one_line(capsys, code)
    assert "holds an input" in err or "is an input" in err
    assert _snapshot(stimset) == before
    # a directory holding the click file only
    own = tmp_path / "own"
    own.mkdir()
    (own / "c.csv").write_bytes(clicks.read_bytes())
    err = _one_line(capsys, main(["analyze", str(own / "c.csv"), "--stimuli", str(stimset), "-o", str(own),
                                  "--force", *FAST]))
    assert "c.csv" in err and (own / "c.csv").exists()


def test_analyze_refuses_the_working_directory_in_one_line(stimset, clicks, tmp_path, capsys, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    err = _one_line(capsys, main(["analyze", str(clicks), "--stimuli", str(stimset), "-o", ".", "--force", *FAST]))
    assert "working directory" in err and list(work.iterdir()) == []


def test_force_replaces_an_earlier_output_but_never_a_users_file(stimset, clicks, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["analyze", str(clicks), "--stimuli", str(stimset), "-o", str(out), *FAST]) == 0
    assert main(["analyze", str(clicks), "--stimuli", str(stimset), "-o", str(out), "--force", *FAST]) == 0
    capsys.readouterr()
    (out / "notes.txt").write_text("my notes")
    err = _one_line(capsys, main(["analyze", str(clicks), "--stimuli", str(stimset), "-o", str(out), "--force",
                                  *FAST]))
    assert "notes.txt" in err and "--force replaces only an earlier analysis output" in err
    assert (out / "notes.txt").read_text() == "my notes" and (out / "summary.json").exists()
    # a folder of the user's own files that merely include names analyze writes is not an analysis
    other = tmp_path / "other"
    other.mkdir()
    (other / "clicks.csv").write_text("participant,stimulus_id,x,y\n")
    err = _one_line(capsys, main(["analyze", str(clicks), "--stimuli", str(stimset), "-o", str(other), "--force",
                                  *FAST]))
    assert (other / "clicks.csv").read_text() == "participant,stimulus_id,x,y\n"


def test_analyze_help_says_what_force_replaces():
    import argparse

    from attneave.analysis.commands import analyze

    p = analyze.add_parser(argparse.ArgumentParser().add_subparsers())
    assert "earlier analysis output" in p.format_help().replace("\n", " ").replace("  ", " ")


# ------------------------------------------------ 3. simulate and power may not overwrite the set
@pytest.mark.parametrize("target", ["manifest.csv", "contours/poly_0.csv"])
def test_simulate_and_power_refuse_to_overwrite_a_file_of_the_set(stimset, capsys, target):
    before = _snapshot(stimset)
    err = _one_line(capsys, _simulate(stimset, stimset / target))
    assert "is an input" in err
    err = _one_line(capsys, main(["power", "--stimuli", str(stimset), "--beta", "0.5", "--participants", "2,4",
                                  "--simulations", "20", "--group-simulations", "19", "-o", str(stimset / target)]))
    assert "is an input" in err
    assert _snapshot(stimset) == before


# ----------------------------------------- 2. a strong effect: the mixed model degrades, no crash
@pytest.mark.parametrize("beta", ["5", "20"])
def test_a_strong_effect_warns_that_the_mixed_model_is_not_estimable_and_writes_everything(
        stimset, tmp_path, capsys, beta):
    f = tmp_path / "strong.csv"
    assert _simulate(stimset, f, "--beta", beta) == 0
    out = tmp_path / "out"
    assert main(["analyze", str(f), "--stimuli", str(stimset), "-o", str(out), *FAST]) == 0
    err = capsys.readouterr().err
    s = json.loads((out / "summary.json").read_text())
    m = s["mixed"]
    assert m["estimable"] is False and m["beta"] is None and m["ci_low"] is None and m["sd_participant"] is None
    assert "near-separation" in m["note"] and m["note"] in s["warnings"]
    assert "mixed model not estimated" in err and "near-separation" in err
    assert {"clicks.csv", "per_stimulus.csv", "per_participant.csv", "models.csv", "report.html"} <= \
        {p.name for p in out.iterdir()}
    assert s["group"]["n"] == 4 and s["effect"]["top_share"] > 0.5
    # every click on its contour's top point: each participant's mean z the same, t infinite (null in
    # JSON), and the report says why rather than a bare n/a
    g = s["group"]
    assert g["statistic"] is None and g["sd"] <= 1e-12 * max(1.0, abs(g["mean"]))
    report = (out / "report.html").read_text()
    assert "n/a (no spread: every mean z is" in report
    # a fit at its bound is flagged, its number and interval not printed
    assert "reached the upper bound of its search: &beta; is not estimable" in report
    assert f"&beta; = {s['beta_hat']:.2f}" not in report


def test_fit_mixed_never_raises_on_separated_clicks():
    from attneave.analysis.models.choice import standardize
    from attneave.analysis.models.mixed import fit_mixed

    rng = np.random.default_rng(0)
    Z = standardize(rng.gamma(1.0, size=(3, 30)))
    st = np.repeat(np.arange(3), 8)
    pa = np.tile(np.repeat(np.arange(2), 4), 3)
    top = Z.argmax(axis=1)[st]
    f = fit_mixed(Z, st, pa, top)  # every click on its stimulus's highest point
    assert f["estimable"] is False and np.isnan(f["beta"]) and "near-separation" in f["note"]
    f = fit_mixed(Z, st, pa, Z.argmin(axis=1)[st])
    assert f["estimable"] is False and "least" in f["note"]
    # an ordinary design is estimable
    j = rng.integers(0, 30, size=len(st))
    f = fit_mixed(Z, st, pa, j)
    assert f["estimable"] is True and f["note"] is None and np.isfinite(f["beta"])


# ----------------------------------------------------------------- 4. broken stimulus sets
def _broken(stimset, capsys, clicks, tmp_path):
    out = tmp_path / "out"
    err = _one_line(capsys, main(["analyze", str(clicks), "--stimuli", str(stimset), "-o", str(out), *FAST]))
    assert not out.exists() and "manifest.csv: line 2 (poly_0" in err
    return err


def test_an_image_of_another_size_than_the_manifest_is_refused(stimset, clicks, tmp_path, capsys):
    import cv2

    (stimset / "images").mkdir()
    cv2.imwrite(str(stimset / "images" / "poly_0.png"), np.zeros((SIZE, 100), np.uint8))
    err = _broken(stimset, capsys, clicks, tmp_path)
    assert "is 100 x 128 px but the manifest says 128 x 128" in err


@pytest.mark.parametrize("points, needle", [
    ([[-500, -500], [-400, -500], [-400, -400]], "wholly outside its 128 x 128 image"),
    ([[0, 0], [1e11, 0], [1e11, 1e11]], "px outside its 128 x 128 image"),
    ([[10, 10], [60, 60], [60, 10], [10, 60]], "crosses itself"),
])
def test_contours_outside_their_image_or_crossing_themselves_are_refused(stimset, clicks, tmp_path, capsys,
                                                                         points, needle):
    pd.DataFrame(points, columns=["x", "y"]).to_csv(stimset / "contours" / "poly_0.csv", index=False)
    assert needle in _broken(stimset, capsys, clicks, tmp_path)


def test_a_contour_partly_outside_its_image_is_a_warning(stimset, clicks, tmp_path, capsys):
    pd.DataFrame([[20, 20], [150, 20], [150, 100], [20, 100]], columns=["x", "y"]).to_csv(
        stimset / "contours" / "poly_0.csv", index=False)
    out = tmp_path / "out"
    assert main(["analyze", str(clicks), "--stimuli", str(stimset), "-o", str(out), *FAST]) == 0
    err = capsys.readouterr().err
    w = [x for x in json.loads((out / "summary.json").read_text())["warnings"] if "outside its 128 x 128" in x]
    assert len(w) == 1 and "poly_0" in w[0] and w[0] in err


# ------------------------------------------------------ 5. degenerate designs are said to be so
def test_one_participant_or_one_click_warns_instead_of_presenting_start_values(stimset, clicks, tmp_path, capsys):
    df = pd.read_csv(clicks)
    for name, rows in (("one_participant", df[df["participant"] == df["participant"].iloc[0]]), ("one_row", df[:1])):
        f = tmp_path / f"{name}.csv"
        rows.to_csv(f, index=False)
        out = tmp_path / name
        assert main(["analyze", str(f), "--stimuli", str(stimset), "-o", str(out), *FAST]) == 0
        err = capsys.readouterr().err
        s = json.loads((out / "summary.json").read_text())
        m = s["mixed"]
        assert m["estimable"] is False and m["sd_participant"] is None and m["beta"] is None
        assert "only 1 participant" in m["note"] and "only 1 participant" in err
        assert any("group test needs at least 2 participants" in w for w in s["warnings"])
        report = (out / "report.html").read_text()
        assert "t(None)" not in report and "from 1 participant on" in report and "participants gave t = n/a" in report
        if name == "one_row":
            assert any("only 1 used click" in w for w in s["warnings"]) and "only 1 used click" in err


# ------------------------------------------------------------------ 6. noise beyond the image
def test_simulate_warns_of_clicks_that_noise_puts_outside_the_image(stimset, tmp_path, capsys):
    assert _simulate(stimset, tmp_path / "n.csv", "--noise", "500") == 0
    err = capsys.readouterr().err
    assert "warning" in err and "outside their image" in err and "%" in err
    df = pd.read_csv(tmp_path / "n.csv")
    out = ((df.x < -0.5) | (df.x > SIZE - 0.5) | (df.y < -0.5) | (df.y > SIZE - 0.5)).sum()
    assert f"{out} of {len(df)} clicks" in err
    assert _simulate(stimset, tmp_path / "q.csv", "--noise", "0") == 0
    assert "warning" not in capsys.readouterr().err


# ------------------------------------------------------- 7. power tables that mean nothing
def test_power_refuses_an_alpha_below_the_smallest_monte_carlo_p(stimset, capsys):
    err = _one_line(capsys, main(["power", "--stimuli", str(stimset), "--lift", "3", "--participants", "4,8",
                                  "--simulations", "20", "--group-simulations", "19", "--clicks", "3",
                                  "--alpha", "0.01"]))
    assert "--group-simulations" in err and "at least 99" in err and "--alpha" in err


def test_power_needs_enough_simulations(stimset, capsys):
    from attneave.analysis.commands.power import MIN_SIMULATIONS
    from attneave.analysis.simulate.observers import MIN_SIMULATIONS as LIBRARY_MIN

    assert MIN_SIMULATIONS == LIBRARY_MIN == 20
    err = _one_line(capsys, main(["power", "--stimuli", str(stimset), "--lift", "3", "--participants", "4,8",
                                  "--simulations", "1", "--group-simulations", "19", "--clicks", "3"]))
    assert "--simulations" in err and "20" in err


# ------------------------------------------- the group figure's calibration panel on tied z (polygons)
def test_calibration_bins_spread_over_z_when_polygon_z_is_tied(stimset, clicks):
    # a polygon's z is one low value at most points and high at a few corners: quantile bins collapsed
    # into one or two (the report's middle panel showed every bin at one z); equal widths spread them
    from attneave.analysis.analyze import analyze
    from attneave.analysis.report.plots import _calibration
    from attneave.stimuli.stimulus_set import read_stimulus_set

    res = analyze(pd.read_csv(clicks), read_stimulus_set(stimset), n=100, group_simulations=19, permutations=19)
    Zs = [res.predictions[s].z["surprisal"] for s in res.profiles["ids"]]
    assert all(np.mean(np.isclose(z, np.median(z))) > 0.5 for z in Zs)  # the premise: most points share one z
    Z = np.concatenate(Zs)
    centre, obs, pred = _calibration(res)
    assert len(centre) >= 3 and np.all(np.isfinite(centre)) and np.all(np.diff(np.sort(centre)) > 0.1)
    assert np.ptp(centre) > 0.5 * np.ptp(Z)
