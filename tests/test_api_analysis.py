"""The Python API of analysis and extraction: bad arguments are refused with an InputError naming
the parameter (never a numpy/OpenCV exception, never silently ignored or a silently wrong result)."""

from __future__ import annotations

import numpy as np
import pytest

from attneave.stimuli.errors import InputError

KW = dict(permutations=19, group_simulations=19, mixed=False, progress=False, grid=128)


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    from attneave.analysis.clicks.mapping import predict
    from attneave.analysis.simulate.observers import simulate
    from attneave.stimuli.stimulus_set import read_stimulus_set, write_stimulus_set

    th = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    d = tmp_path_factory.mktemp("set") / "set"
    write_stimulus_set(d, {"e": np.c_[100 + 60 * np.cos(th), 100 + 30 * np.sin(th)],
                           "f": np.c_[100 + 30 * np.cos(th), 100 + 60 * np.sin(th) + 5 * np.cos(5 * th)]},
                       size=(200, 200))
    s = read_stimulus_set(d)
    pr = predict(s, n=50)
    df, _ = simulate(pr, 4, 5, 1.0, 1)
    return d, s, pr, df


def _square_image(dtype=np.uint8, value=200):
    img = np.zeros((40, 50), dtype)
    img[10:30, 5:25] = value
    return img


# ------------------------------------------------------------- 1. analyze: n and model of predictions
def test_analyze_refuses_n_or_model_other_than_the_predictions(small):
    from attneave.analysis.analyze import analyze

    _, s, pr, df = small
    with pytest.raises(InputError, match=r"^n is 60 but the predictions were made with n = 50"):
        analyze(df, s, n=60, predictions=pr, **KW)
    with pytest.raises(InputError, match=r"^model is 'vonmises' but the predictions were made with model = 'paper'"):
        analyze(df, s, model="vonmises", predictions=pr, **KW)
    with pytest.raises(InputError, match=r"^b is 2"):
        analyze(df, s, b=2.0, predictions=pr, **KW)
    # left out: the predictions' own; the same values given: accepted
    for extra in ({}, dict(n=50, model="paper")):
        r = analyze(df, s, predictions=pr, **extra, **KW)
        assert r.predictions["e"].n == 50 and r.predictions["e"].result.params["model"] == "paper"


def test_analyze_refuses_predictions_of_another_set(small):
    from attneave.analysis.analyze import analyze

    _, s, pr, df = small
    with pytest.raises(InputError, match="predictions: they are not those of this stimulus set"):
        analyze(df, s, predictions={"e": pr["e"]}, **KW)
    with pytest.raises(InputError, match="predictions: expected the dict of attneave.analysis.clicks.mapping.predict"):
        analyze(df, s, predictions={"e": 1}, **KW)


# ------------------------------------------------------------- 6. analyze: clicks, stimset, numbers
def test_analyze_checks_clicks_and_takes_a_stimulus_set_directory(small):
    from attneave.analysis.analyze import analyze

    d, s, _, df = small
    with pytest.raises(InputError, match=r"clicks: missing column\(s\) x;"):
        analyze(df.drop(columns=["x"]), s, **KW)
    with pytest.raises(InputError, match="clicks: expected a pandas.DataFrame .* got ndarray"):
        analyze(df.to_numpy(), s, **KW)
    with pytest.raises(InputError, match="stimset: expected a StimulusSet"):
        analyze(df, {"e": 1}, **KW)
    with pytest.raises(InputError, match="^b must be a finite number, got 'x'"):
        analyze(df, s, b="x", **KW)
    with pytest.raises(InputError, match="^level"):
        analyze(df, s, level="x", **KW)
    r = analyze(df, str(d), **KW)
    assert r.summary["n_used"] == len(df) and list(r.stimset.ids) == ["e", "f"]


def test_power_takes_one_number_of_participants_and_checks_target(small):
    from attneave.analysis.simulate.observers import power

    _, _, pr, _ = small
    table, info = power(pr, 1.0, participants=5, simulations=20, group_simulations=19, alpha=0.05)
    assert table["participants"].tolist() == [5]
    for bad in (True, [3, True], "5", [1]):
        with pytest.raises(InputError, match="^participants needs whole numbers >= 2"):
            power(pr, 1.0, participants=bad, simulations=20, group_simulations=19)
    for target in (2, np.nan, 0, "x"):
        with pytest.raises(InputError, match="^target must be a power in"):
            power(pr, 1.0, participants=[4], simulations=20, group_simulations=19, target=target)


# ------------------------------------------------------------- 5. simulate: seeds and counts
def test_simulate_seeds_int_generator_none_and_refuses_others(small):
    from attneave.analysis.simulate.observers import simulate

    _, _, pr, _ = small
    df, p = simulate(pr, 2, 3, 1.0, None)  # fresh entropy, recorded so that it reproduces
    again, _ = simulate(pr, 2, 3, 1.0, p["seed"])
    assert isinstance(p["seed"], int) and df.equals(again)
    g = np.random.default_rng(0)
    a, pa = simulate(pr, 2, 3, 1.0, g)
    b, _ = simulate(pr, 2, 3, 1.0, g)
    assert not a.equals(b)  # the generator advanced
    assert simulate(pr, 2, 3, 1.0, pa["seed"])[0].equals(a)
    assert simulate(pr, 2, 3, 1.0, np.random.default_rng(0))[0].equals(a)
    for seed in (-1, 1.5, "abc", True, np.random.RandomState(0)):
        with pytest.raises(InputError, match="^seed must be a whole number >= 0, a numpy.random.Generator or None"):
            simulate(pr, 2, 3, 1.0, seed)


@pytest.mark.parametrize("kwargs, needle", [
    (dict(participants=True), "participants must be a whole number >= 1, got True"),
    (dict(participants=2.5), "participants must be a whole number >= 1"),
    (dict(clicks=False), "clicks must be a whole number >= 1"),
    (dict(beta="x"), "beta must be a finite number, got 'x'"),
    (dict(beta=1e308), "beta must be from -50 to 50"),
    (dict(noise="x"), "noise must be a number of pixels >= 0"),
    (dict(beta_sd="x"), "beta_sd must be a finite number >= 0"),
])
def test_simulate_names_the_python_parameter(small, kwargs, needle):
    from attneave.analysis.simulate.observers import simulate

    _, _, pr, _ = small
    args = {**dict(participants=2, clicks=3, beta=1.0, seed=1), **kwargs}
    with pytest.raises(InputError) as e:
        simulate(pr, **args)
    assert str(e.value).startswith(needle) and "--" not in str(e.value)


# ------------------------------------------------------------- 7. messages: parameters in Python, flags on the CLI
def test_library_messages_name_parameters_and_the_cli_flags(small):
    from attneave.analysis.analyze import analyze
    from attneave.analysis.argnames import cli_names
    from attneave.analysis.clicks.mapping import predict

    _, s, _, df = small
    with pytest.raises(InputError, match="^n must be a whole number >= 3"):
        predict(s, n=2)
    with pytest.raises(InputError, match="^seed must be a whole number >= 0"):
        analyze(df, s, seed=-5, **KW)
    with pytest.raises(InputError, match="^group_simulations must be"):
        analyze(df, s, **{**KW, "group_simulations": -1})
    with cli_names():
        with pytest.raises(InputError, match="^-n must be a whole number >= 3"):
            predict(s, n=2)
        with pytest.raises(InputError, match="^--seed must be a whole number >= 0"):
            analyze(df, s, seed=-5, **KW)


def test_power_cli_still_names_its_flags(small, capsys):
    from attneave.cli import main

    d, _, _, _ = small
    assert main(["power", "--stimuli", str(d), "--beta", "1", "--participants", "4", "--simulations", "20",
                 "--group-simulations", "19", "--alpha", "0.01", "-n", "20"]) == 2
    err = capsys.readouterr().err
    assert "--alpha 0.01 is below" in err and "raise --group-simulations" in err


# ------------------------------------------------------------- 2. GrabCut iterations
@pytest.mark.parametrize("iterations", [0, -1, 2.5, True, "3"])
def test_grabcut_iterations_must_be_a_positive_whole_number(iterations):
    from attneave.stimuli.extraction import extract_contours

    with pytest.raises(InputError, match="^grabcut_iterations"):
        extract_contours(np.dstack([_square_image()] * 3), method="grabcut", rect=(2, 2, 30, 35),
                         grabcut_iterations=iterations)


# ------------------------------------------------------------- 3. options of another method
@pytest.mark.parametrize("kwargs, needle", [
    (dict(rect=(2, 2, 30, 35)), "rect needs method 'grabcut', not 'otsu'"),
    (dict(grabcut_iterations=3), "grabcut_iterations need method 'auto', 'photo' or 'grabcut', not 'otsu'"),
    (dict(model={"model_file": "net.onnx"}), "model needs method 'model' or 'rembg', not 'otsu'"),
    (dict(threshold=100), "threshold needs method 'threshold' or 'alpha', not 'otsu'"),
    (dict(method="mask", threshold=100), "threshold needs method 'threshold' or 'alpha', not 'mask'"),
])
def test_extract_contours_refuses_options_of_another_method(kwargs, needle):
    from attneave.stimuli.extraction import extract_contours

    with pytest.raises(InputError, match="^" + needle):
        extract_contours(_square_image(), **kwargs)


# ------------------------------------------------------------- 4. images and numbers
def test_integer_image_of_huge_range_is_traced_not_a_memory_error():
    from attneave.stimuli.extraction import extract, extract_contours

    [c] = extract_contours(_square_image(np.int64, 10**12))
    assert [round(float(v), 1) for v in c.bbox] == [4.5, 9.5, 24.5, 29.5]
    ex = extract(_square_image(np.int64, 10**12), method="threshold", threshold=5e11)
    assert ex.params["level"] == 5e11
    with pytest.raises(InputError, match="alpha channel and values from 0 to 1000000000000"):
        extract_contours(np.dstack([_square_image(np.int64, 10**12)] * 4))


@pytest.mark.parametrize("kwargs, needle", [
    (dict(method="threshold", threshold="x"), "threshold: must be a number"),
    (dict(method="threshold", threshold=np.nan), "threshold: must be a finite number"),
    (dict(min_area="x"), "min_area: must be a number"),
    (dict(mask_sigma="x"), "mask_sigma: must be a number"),
    (dict(min_hole_area=-1), "min_hole_area: must be >= 0"),
])
def test_extract_numbers_are_checked(kwargs, needle):
    from attneave.stimuli.extraction import extract_contours

    with pytest.raises(InputError, match="^" + needle):
        extract_contours(_square_image(), **kwargs)


def test_read_image_checks_its_arguments(tmp_path):
    from attneave.stimuli.extraction import read_image
    from attneave.stimuli.render import write_png

    for bad in (None, 5, np.zeros((3, 3))):
        with pytest.raises(InputError, match=r"^path: expected an image file name \(str or Path\)"):
            read_image(bad)
    f = tmp_path / "a.png"
    write_png(f, _square_image())
    for bad in (np.nan, "x", 0, True, 2.5):
        with pytest.raises(InputError, match="^max_pixels: must be a whole number of pixels >= 1"):
            read_image(f, max_pixels=bad)
    assert read_image(f, max_pixels=1e8).shape == (40, 50)
    with pytest.raises(InputError, match="exceeds the limit of 10 pixels"):
        read_image(f, max_pixels=10)


def test_smooth_and_default_sigma_check_their_numbers():
    from attneave.stimuli.extraction import default_sigma, smooth

    sq = [[0, 0], [100, 0], [100, 100], [0, 100]]
    for spacing in (0, -1, np.nan, "x"):
        with pytest.raises(InputError, match="^spacing"):
            smooth(sq, spacing=spacing)
    with pytest.raises(InputError, match="at most 10,000,000"):
        smooth(sq, spacing=1e-9)
    assert smooth(sq, spacing=2).n == 200
    for fraction in (-1, 0, np.nan, 0.6, "x"):
        with pytest.raises(InputError, match="^fraction"):
            default_sigma(sq, fraction=fraction)
    with pytest.raises(InputError, match="^minimum"):
        default_sigma(sq, minimum=-1)
    assert default_sigma(sq, fraction=0.02) == 8.0


# ------------------------------------------------------------- 8. docstrings
def test_public_functions_document_their_parameters():
    from attneave.stimuli.extraction import contour_curvature, default_sigma, extract_contours
    from attneave.stimuli.stimulus_set import check_contour_in_image, check_image_size

    for f in (extract_contours, contour_curvature, default_sigma, check_contour_in_image, check_image_size):
        assert "Parameters\n    ----------" in f.__doc__, f.__name__


def test_curvature_peaks_refuses_a_string_flag():
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.extraction.scalespace import curvature_peaks

    th = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    ellipse = np.c_[60 * np.cos(th), 30 * np.sin(th)]
    with pytest.raises(InputError, match="minima: must be True or False"):
        curvature_peaks(ellipse, minima="no")
    assert len(curvature_peaks(ellipse, minima=np.bool_(False))["t"]) == 2  # the two ends of the major axis
