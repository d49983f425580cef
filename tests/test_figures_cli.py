"""``attneave curve`` and ``attneave figures`` through the command-line entry point."""

import numpy as np
import pandas as pd
import pytest
from scipy.special import fresnel

from attneave.cli import main

COLUMNS = ["s", "x", "y", "theta", "curvature"]


def test_curve_clothoid_matches_fresnel(tmp_path):
    out = tmp_path / "c.csv"
    # kappa = pi*s from 0: (x, y) = (C(s), S(s))
    assert main(["curve", "clothoid", "--c", str(np.pi), "--s-end", "2", "--points", "41", "-o", str(out)]) == 0
    df = pd.read_csv(out)
    assert list(df.columns) == COLUMNS and len(df) == 41
    S, C = fresnel(df["s"].to_numpy())
    assert np.max(np.abs(df["x"] - C)) < 1e-9 and np.max(np.abs(df["y"] - S)) < 1e-9
    assert np.allclose(df["theta"], np.pi * df["s"] ** 2 / 2, atol=1e-12)
    assert not list(tmp_path.glob(".*tmp"))  # the atomic write left no temporary file


@pytest.mark.parametrize(
    "argv",
    [
        ["clothoid", "--k0", "0.5", "--c", "-1", "--s-start", "-1", "--s-end", "3"],
        ["pseudospiral", "--a", "0.3", "--m", "1", "--s-start", "0.5", "--s-end", "4"],
        ["lac", "--alpha", "0", "--lam", "-0.5", "--s-end", "3"],
        ["superspiral", "--a", "1", "--b", "1", "--c", "2", "--theta-end", "6"],
        ["constant-info", "--C", "-0.02", "--s-end", "5"],
    ],
)
def test_curve_every_family(tmp_path, argv):
    out = tmp_path / "c.csv"
    assert main(["curve", *argv, "--points", "51", "-o", str(out)]) == 0
    df = pd.read_csv(out)
    assert list(df.columns) == COLUMNS and len(df) == 51
    assert np.all(np.isfinite(df.to_numpy()))
    assert (df["x"][0], df["y"][0], df["theta"][0]) == (0.0, 0.0, 0.0)
    assert np.all(np.diff(df["s"]) > 0)


def test_curve_constant_info_domain_start(tmp_path):
    out = tmp_path / "c.csv"
    assert main(["curve", "constant-info", "--C", "0.03", "--n", "10", "--s-end", "5", "-o", str(out)]) == 0
    df = pd.read_csv(out)
    assert np.isclose(df["s"][0], np.sqrt(0.03) * 10)
    assert np.isclose(df["curvature"][0], 2 * np.pi / (np.sqrt(0.03) * 10))  # arccos(1) = 0


@pytest.mark.parametrize(
    "argv, words",
    [
        (["constant-info", "--C", "0.03", "--s-start", "1", "--s-end", "5"], "outside the domain of eq. 7"),
        (["lac", "--alpha", "1", "--lam", "-1", "--s-end", "2"], "domain of eq. 9"),
        (["pseudospiral", "--a", "1", "--m", "1", "--s-start", "0", "--s-end", "1"], "s > 0"),
        (["superspiral", "--a", "1", "--b", "2", "--c", "1", "--theta-end", "1"], "c > b > 0"),
        (["clothoid", "--c", "nan", "--s-end", "1"], "finite"),
        (["clothoid", "--c", "1", "--s-start", "2", "--s-end", "1"], "s_end must be greater"),
    ],
)
def test_curve_bad_input_exit_2(tmp_path, capsys, argv, words):
    out = tmp_path / "c.csv"
    assert main(["curve", *argv, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("attneave curve: error:") and words in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists() and not list(tmp_path.iterdir())


def test_curve_usage_errors_exit_2(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["curve", "clothoid", "--s-end", "1", "-o", str(tmp_path / "c.csv")])  # --c missing
    assert exc.value.code == 2
    with pytest.raises(SystemExit) as exc:
        main(["curve", "spiral", "-o", str(tmp_path / "c.csv")])  # unknown family
    assert exc.value.code == 2
    assert "Traceback" not in capsys.readouterr().err


def test_curve_missing_output_directory(tmp_path, capsys):
    assert main(["curve", "clothoid", "--c", "1", "--s-end", "1", "-o", str(tmp_path / "no" / "c.csv")]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_curve_help_documents_every_family(capsys):
    with pytest.raises(SystemExit):
        main(["curve", "--help"])
    text = capsys.readouterr().out
    for words in ("clothoid", "--k0", "pseudospiral", "--m", "lac", "--alpha", "--lam", "superspiral",
                  "--theta-end", "constant-info", "--C", "y-UP"):
        assert words in text


PAPER_FIGURES = [
    "fig1_u_vs_curvature.png",
    "fig2_u_exp_curvature.png",
    "fig3_u_cusp.png",
    "fig4_u_clothoid.png",
    "fig5_eq7_curvature_pos.png",
    "fig6_eq7_curvature_neg.png",
]


def test_figures_writes_paper_figures(tmp_path, capsys):
    import matplotlib.image as mpimg

    out = tmp_path / "figs"
    assert main(["figures", "-o", str(out)]) == 0
    for name in PAPER_FIGURES:
        path = out / name
        assert path.exists(), name
        img = mpimg.imread(path)
        assert img.ndim == 3 and img.shape[0] >= 300 and img.shape[1] >= 500
        rgb = img[..., :3].reshape(-1, 3)
        # not blank: many colours, and some of the plot's ink (dark pixels)
        assert len(np.unique(np.round(rgb * 255).astype(np.uint8), axis=0)) > 50
        assert (rgb.sum(axis=1) < 1.0).mean() > 0.002
    note = (out / "figures.md").read_text()
    for name in PAPER_FIGURES:
        assert name in note
    for words in ("Fig. 1.", "Fig. 3.", "cusp", "Fig. 5.", "Fig. 6.", "A' = 1/4"):
        assert words in note
    printed = capsys.readouterr().out.split()
    assert str(out / "figures.md") in printed


def test_make_figures_writes_the_named_figures(tmp_path):
    from attneave.papers.draw import make_figures

    files = make_figures(tmp_path / "f", ["fig5", "fig1"])
    assert [p.name for p in files] == ["fig5_eq7_curvature_pos.png", "fig1_u_vs_curvature.png", "figures.md"]
    note = (tmp_path / "f" / "figures.md").read_text()
    assert note.index("Fig. 5.") < note.index("Fig. 1.") and "Fig. 2." not in note
    assert "The paper's caption: Curvature function (7)" in note


def test_make_figures_unknown_name(tmp_path):
    from attneave.papers.draw import make_figures
    from attneave.stimuli.errors import InputError

    with pytest.raises(InputError, match="no figure named fig7"):
        make_figures(tmp_path / "f", ["fig1", "fig7"])
    assert not (tmp_path / "f").exists()


def test_figures_bad_output(tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    assert main(["figures", "-o", str(f)]) == 2
    assert "not a directory" in capsys.readouterr().err


@pytest.mark.parametrize("b", [0.5, 1.0, 2.0])
def test_fig2_amplitude_grows_with_arc_length(b):
    # the paper: "the amplitudes of (5) increase with an arc length (Fig. 2)", which holds
    # with ds = s/n: u = -ln A' - b (s/n)^2 cos(exp(s) s/n - 2 pi/n), A' = 1/4, n = 10
    from attneave.papers.ziatdinov import fig2

    line = next(line for line in fig2().panels[0].lines if line.label == f"b = {b:g}")
    s, u = line.x, line.y
    n, level = 10, -np.log(0.25)
    expected = level - b * (s / n) ** 2 * np.cos(np.exp(s) * s / n - 2 * np.pi / n)
    np.testing.assert_allclose(u, expected, rtol=0, atol=1e-12)
    dev = np.abs(u - level)
    assert np.all(dev <= b * (s / n) ** 2 + 1e-12)
    # the largest deviation on each unit of arc length grows, up to the envelope b (s/n)^2 at s = 3,
    # where the turn passes 2 pi/n + pi (cos = -1 near exp(s) s/n = 3.77, s = 2.6)
    amp = [dev[(s >= lo) & (s <= lo + 1)].max() for lo in (0.0, 1.0, 2.0)]
    assert amp[0] < amp[1] < amp[2]
    assert amp[0] <= b * 0.01 and amp[2] > 0.6 * b * 0.09


def test_fig2_note_says_ds_is_s_over_n(tmp_path):
    from attneave.papers.draw import make_figures

    make_figures(tmp_path, ["fig2"])
    note = (tmp_path / "figures.md").read_text()
    assert "ds = s/n" in note and "We follow the text" in note and "ds = L/n = 10" in note
