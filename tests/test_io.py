"""File helpers and CLI file errors: one line, exit 2, nothing written."""

import numpy as np
import pytest

from attneave.cli import main
from attneave.stimuli import Contour, InputError
from attneave.stimuli.io import atomic_write
from attneave.stimuli.tables import read_points, read_table


def _ellipse_csv(path):
    th = 2 * np.pi * np.arange(200) / 200
    p = np.c_[256 + 150 * np.cos(th), 256 + 60 * np.sin(th)]
    path.write_text("x,y\n" + "".join(f"{x},{y}\n" for x, y in p))
    return path


def test_atomic_write_into_missing_directory_is_input_error(tmp_path):
    with pytest.raises(InputError, match="cannot write"):
        with atomic_write(tmp_path / "nope" / "out.csv") as fh:
            fh.write("x")


def test_atomic_write_onto_a_directory_is_input_error(tmp_path):
    (tmp_path / "d").mkdir()
    with pytest.raises(InputError, match="is a directory"):
        with atomic_write(tmp_path / "d") as fh:
            fh.write("x")
    assert list((tmp_path).iterdir()) == [tmp_path / "d"]  # no temporary left behind


def test_read_table_of_a_directory_is_input_error(tmp_path):
    with pytest.raises(InputError, match="is a directory, expected a CSV file"):
        read_table(tmp_path)


@pytest.mark.parametrize("which", ["missing-dir", "dir-as-output", "dir-as-input"])
def test_surprisal_cli_file_errors_one_line_exit_2(tmp_path, capsys, which):
    src = _ellipse_csv(tmp_path / "c.csv")
    args = {
        "missing-dir": [str(src), "-o", str(tmp_path / "no" / "o.csv")],
        "dir-as-output": [str(src), "-o", str(tmp_path)],
        "dir-as-input": [str(tmp_path), "-o", str(tmp_path / "o.csv")],
    }[which]
    assert main(["surprisal", *args]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.csv"]


def test_resample_refuses_absurd_point_counts(tmp_path, capsys):
    th = 2 * np.pi * np.arange(50) / 50
    c = Contour(np.c_[np.cos(th), np.sin(th)] * 100)
    with pytest.raises(InputError, match="n <="):
        c.resample(spacing=1e-9)
    src = _ellipse_csv(tmp_path / "c.csv")
    assert main(["surprisal", str(src), "-o", str(tmp_path / "o.csv"), "--spacing", "1e-9"]) == 2
    assert "n <=" in capsys.readouterr().err
    assert not (tmp_path / "o.csv").exists()


def test_trailing_delimiters_never_shift_columns(tmp_path):
    # pandas alone takes the first field as an index when rows are longer than the header
    f = tmp_path / "trailing.csv"
    f.write_text("x,y\n10,10,\n10,50,\n50,50,\n50,10,\n")
    assert read_points(f).tolist() == [[10, 10], [10, 50], [50, 50], [50, 10]]
    g = tmp_path / "extra.csv"
    g.write_text("x,y\n10,10,1\n10,50,1\n50,50,1\n")
    with pytest.raises(InputError, match=r"extra.csv: line 2: 3 fields but the header has 2"):
        read_points(g)


def test_line_numbers_count_blank_lines(tmp_path):
    f = tmp_path / "blank.csv"
    f.write_text("x,y\n10,10\n\n10,50\n50,zz\n")
    with pytest.raises(InputError, match=r"line 5: column 'y' must be a finite number, got 'zz'"):
        read_points(f)


def test_an_output_may_not_destroy_an_input(tmp_path, monkeypatch):
    from attneave.stimuli.io import check_output_spares_inputs

    (tmp_path / "set").mkdir()
    (tmp_path / "set" / "manifest.csv").write_text("id\n")
    (tmp_path / "clicks.csv").write_text("x\n")
    monkeypatch.chdir(tmp_path)
    for out, inputs in (("clicks.csv", ["clicks.csv"]),                   # the same file
                        ("./clicks.csv", ["clicks.csv"]),                 # the same file, spelt otherwise
                        ("set", ["set/manifest.csv"]),                   # a directory holding an input
                        ("set", ["set"]),                                # the input directory itself
                        (".", []), ("..", []),                           # the working directory or its parent
                        ("", [])):
        with pytest.raises(InputError):
            check_output_spares_inputs(out, inputs)
    # a link to an input is that input
    (tmp_path / "link.csv").symlink_to(tmp_path / "clicks.csv")
    with pytest.raises(InputError, match="is an input"):
        check_output_spares_inputs("link.csv", ["clicks.csv"])
    check_output_spares_inputs("out", ["set", "clicks.csv"])        # a fresh sibling is fine
    check_output_spares_inputs("set/out.csv", ["set/manifest.csv"])  # beside an input, not on it


def test_make_output_dir_says_why_not_in_one_line(tmp_path):
    from attneave.stimuli.io import make_output_dir

    (tmp_path / "file").write_text("")
    for out, why in ((tmp_path / "file", "not a directory"), (tmp_path / "file" / "sub", "cannot be created"),
                     ("", "empty output path")):
        with pytest.raises(InputError, match=why):
            make_output_dir(out)
    assert make_output_dir(tmp_path / "a" / "b").is_dir()


def test_temporary_directory_refuses_the_working_directory(tmp_path, monkeypatch):
    from attneave.stimuli.io import temporary_directory

    monkeypatch.chdir(tmp_path)
    with pytest.raises(InputError, match="working directory"):
        temporary_directory(".")
    assert list(tmp_path.iterdir()) == []
