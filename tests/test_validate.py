"""One rule set for arguments (attneave.stimuli.validate): the Python API, the
configs and the command flags refuse the same value in the same words;
strings and booleans are not numbers; spline and surprisal share the bounds
of a contour and name the file and the CSV line."""

import math

import numpy as np
import pytest

from attneave.cli import main
from attneave.stimuli.errors import InputError

SQUARE = np.array([[0.0, 0.0], [100.0, 0.0], [100.0, 100.0], [0.0, 100.0]])


def _cli(argv, capsys):
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:
        code = exc.code
    return code, capsys.readouterr().err


def _write(path, points):
    path.write_text("x,y\n" + "".join(f"{float(x)!r},{float(y)!r}\n" for x, y in points))
    return path


# ------------------------------------------------------------------ the rule for numbers
@pytest.mark.parametrize("call, message", [
    (lambda: __import__("attneave").stimuli.shapes.generators.radial_frequency(0, r0="50"),
     "r0: must be a number, got '50'"),
    (lambda: __import__("attneave").stimuli.shapes.generators.radial_frequency(0, r0=True),
     "r0: must be a number, got True"),
    (lambda: __import__("attneave").stimuli.shapes.generators.radial_frequency(0, n="64"),
     "n: must be an integer, got '64'"),
    (lambda: __import__("attneave").stimuli.geometry.information.surprisal(SQUARE, b="1"),
     "b: must be a number, got '1'"),
    (lambda: __import__("attneave").stimuli.geometry.information.surprisal(SQUARE, A=True),
     "A: must be a number, got True"),
])
def test_the_api_refuses_text_and_booleans_where_a_number_belongs(call, message):
    import attneave.stimuli.geometry.information  # noqa: F401  (the lambdas reach it as an attribute)
    import attneave.stimuli.shapes.generators  # noqa: F401

    with pytest.raises(InputError) as e:
        call()
    assert str(e.value) == message


def test_numpy_scalars_and_integral_floats_are_numbers():
    from attneave.stimuli.shapes.generators import radial_frequency
    from attneave.stimuli.validate import as_int, as_number

    a, _ = radial_frequency(0, r0=np.float32(50), n=np.int64(64))
    b, _ = radial_frequency(0, r0=50, n=64.0)
    np.testing.assert_array_equal(a.points, b.points)
    assert len(a.points) == 64
    assert as_number(np.float16(0.5), "x") == 0.5 and as_int(np.uint8(7), "x") == 7
    for bad, kind in ((3.5, "an integer"), (np.bool_(True), "an integer"), (b"3", "an integer")):
        with pytest.raises(InputError, match=f"^x: must be {kind}, got"):
            as_int(bad, "x")
    for bad in ("1", b"1", None, [1.0], 1j, np.array([1.0, 2.0])):
        with pytest.raises(InputError, match="^x: must be a number, got"):
            as_number(bad, "x")


def test_text_is_a_number_only_where_it_is_read():
    from attneave.stimuli.validate import parse_number

    assert parse_number(" 1e3", "--width", gt=0) == 1000.0
    with pytest.raises(InputError, match=r"^--width: must be a number, got 'wide'$"):
        parse_number("wide", "--width")
    with pytest.raises(InputError, match=r"^--width: must be > 0, got -1.0$"):
        parse_number("-1", "--width", gt=0)


# ------------------------------------------------------------------ a config, in the API's words
_CONFIG = """seed: 1
conditions:
  - name: rf
    recipe: radial_frequency
    params:
      r0: {r0}
      n: {n}
"""


def _config_error(tmp_path, **values):
    from attneave.stimuli.batch.config import load_config

    path = tmp_path / "cfg.yaml"
    path.write_text(_CONFIG.format(**{"r0": 50, "n": 64, **values}))
    with pytest.raises(InputError) as e:
        load_config(path)
    return path, str(e.value)


@pytest.mark.parametrize("written, key, line, api", [
    ('"50"', "r0", 6, dict(r0="50")),
    ("true", "r0", 6, dict(r0=True)),
    ("'64'", "n", 7, dict(n="64")),
])
def test_a_quoted_number_in_a_config_is_refused_in_the_api_words(tmp_path, written, key, line, api):
    from attneave.stimuli.shapes.generators import radial_frequency

    with pytest.raises(InputError) as e:
        radial_frequency(0, **api)
    words = str(e.value).removeprefix(f"{key}: ")
    path, msg = _config_error(tmp_path, **{key: written})
    assert msg == f"{path}:{line}: conditions[0].params.{key}: {words}"


def test_unquoted_numbers_in_a_config_are_numbers(tmp_path):
    from attneave.stimuli.batch.config import load_config

    path = tmp_path / "cfg.yaml"
    path.write_text(_CONFIG.format(r0=50, n=64.0))
    cells = load_config(path).conditions[0].cells
    assert cells[0]["r0"] == 50.0 and cells[0]["n"] == 64


def test_the_same_value_is_refused_in_the_same_words_by_api_config_and_flag(tmp_path, capsys, stimset):
    # NaN where a finite number belongs: the library, a batch config, the experiment's YAML
    # and its flag, and the surprisal command's flag all say it the same way
    from attneave.analysis.experiment.options import load_options
    from attneave.stimuli.geometry.surprisal_file import surprisal_of_file
    from attneave.stimuli.shapes.generators import radial_frequency

    words = "must be a finite number, got nan"
    sq = _write(tmp_path / "sq.csv", SQUARE)
    found = []
    for call in (lambda: radial_frequency(0, r0=math.nan), lambda: surprisal_of_file(sq, spacing=math.nan)):
        with pytest.raises(InputError) as e:
            call()
        found.append(str(e.value))
    path, msg = _config_error(tmp_path, r0=".nan")
    found.append(msg)
    exp = tmp_path / "exp.yaml"
    exp.write_text("size_deg: .nan\n")
    with pytest.raises(InputError) as e:
        load_options(exp)
    found.append(str(e.value))
    code, err = _cli(["surprisal", sq, "-o", tmp_path / "o.csv", "--spacing", "nan"], capsys)
    assert code == 2
    found.append(err.strip())
    code, err = _cli(["experiment", stimset, "-o", tmp_path / "e", "--size-deg", "nan"], capsys)
    assert code == 2
    found.append(err.strip())
    assert found == [
        f"r0: {words}",
        f"spacing: {words}",
        f"{path}:6: conditions[0].params.r0: {words}",
        f"{exp}: line 1: size_deg: {words}",
        f"attneave surprisal: error: --spacing: {words}",
        f"attneave experiment: error: --size-deg: {words}",
    ]
    assert not (tmp_path / "o.csv").exists() and not (tmp_path / "e").exists()


# ------------------------------------------------------------------ spline and surprisal: one bound
@pytest.mark.parametrize("side, offset, needle", [
    (1e4, 1e12 - 5e3, "line 3: coordinates must lie within +-1e+12 px"),  # far out: beyond the bound
    (1e-12, 0.0, "the contour spans only 1e-12 px"),  # only rounding noise
    (1.0, 1e11, "the contour spans only 1 px"),  # resolved only by rounding, far from the origin
])
def test_spline_and_surprisal_refuse_the_same_contours_in_the_same_words(tmp_path, capsys, side, offset, needle):
    src = _write(tmp_path / "pts.csv", SQUARE / 100 * side + offset)
    errors = []
    for command in ("spline", "surprisal"):
        out = tmp_path / f"{command}.csv"
        code, err = _cli([command, src, "-o", out], capsys)
        assert code == 2 and err.count("\n") == 1, err
        assert not out.exists()
        errors.append(err.split(": error: ", 1)[1])
    assert errors[0] == errors[1]
    assert errors[0].startswith(f"{src}: ") and needle in errors[0] and "rescale" in errors[0]


def test_spline_names_the_file_and_the_csv_line_not_a_sample(tmp_path, capsys):
    # a blank line and a comment-free header: point 1 of the file is on CSV line 4
    src = tmp_path / "far.csv"
    src.write_text("x,y\n0,0\n\n3e12,0\n3e12,3e12\n0,3e12\n")
    code, err = _cli(["spline", src, "-o", tmp_path / "o.csv"], capsys)
    assert code == 2
    assert err.strip() == (f"attneave spline: error: {src}: line 4: coordinates must lie within +-1e+12 px, "
                           "got [3000000000000.0, 0.0]; rescale the contour")


# ------------------------------------------------------------------ the commands read their file once
@pytest.mark.parametrize("command", ["spline", "surprisal"])
def test_a_command_reads_its_points_once(tmp_path, capsys, monkeypatch, command):
    import attneave.stimuli.tables as tables

    calls = []
    real = tables.read_points

    def counting(*args, **kwargs):
        calls.append(args[0])
        return real(*args, **kwargs)

    monkeypatch.setattr(tables, "read_points", counting)
    # a closing repeat of the first point: its note names the CSV lines
    src = _write(tmp_path / "sq.csv", [*SQUARE, SQUARE[0]])
    code, err = _cli([command, src, "-o", tmp_path / "o.csv"], capsys)
    assert code == 0, err
    assert "line 6" in err and len(calls) == 1
