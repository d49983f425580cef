"""`attneave experiment` on bad input: one line naming the file, key or flag, exit 2, nothing written.

Each test failed on the code before the fix (audit of generate and experiment).
"""

from __future__ import annotations

import shutil

import pytest

from attneave.cli import main


def _refused(capsys, tmp_path, out, *words):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith("attneave experiment: error: "), err
    for w in words:
        assert w in err, err
    assert not out.exists()
    assert not [p for p in out.parent.iterdir() if p.name.startswith(".attneave-tmp")]


@pytest.mark.parametrize("damage, words", [
    (lambda p: p.write_text("nope\n"), ["a_peaks.png", "not an image file"]),
    (lambda p: p.write_bytes(p.read_bytes()[:300]), ["a_peaks.png", "cannot be decoded", "truncated"]),
    (lambda p: p.write_bytes(b""), ["a_peaks.png", "empty file"]),
])
def test_a_broken_image_is_refused_naming_the_file(stimset, tmp_path, capsys, damage, words):
    bad = tmp_path / "set"
    shutil.copytree(stimset, bad)
    damage(bad / "images" / "a_peaks.png")
    out = tmp_path / "exp"
    assert main(["experiment", str(bad), "-o", str(out)]) == 2
    _refused(capsys, tmp_path, out, *words)


@pytest.mark.parametrize("args, words", [
    (["--practice", "a_peaks,a_peaks"], ["--practice: stimulus id 'a_peaks' is given twice"]),
    (["--conditions", "peaks,peaks"], ["--conditions: condition 'peaks' is given twice"]),
    (["--psychopy-units", "pix"], ["--psychopy-units: applies only to the PsychoPy export; add --psychopy"]),
    (["--size-deg", "nan"], ["--size-deg: must be a finite number, got nan"]),
])
def test_bad_flags_are_refused(stimset, tmp_path, capsys, args, words):
    out = tmp_path / "exp"
    assert main(["experiment", str(stimset), "-o", str(out), *args]) == 2
    _refused(capsys, tmp_path, out, *words)


@pytest.mark.parametrize("text, words", [
    ("title: a\ntitle: b\n", ["exp.yaml:2: duplicate key 'title' (first given on line 1)"]),
    ("size_deg: .nan\n", ["exp.yaml: line 1: size_deg: must be a finite number"]),
    ("practice: [a_peaks, a_peaks]\n", ["practice: stimulus id 'a_peaks' is given twice"]),
])
def test_bad_config_files_are_refused(stimset, tmp_path, capsys, text, words):
    cfg = tmp_path / "exp.yaml"
    cfg.write_text(text)
    out = tmp_path / "exp"
    assert main(["experiment", str(stimset), "-o", str(out), "--config", str(cfg)]) == 2
    _refused(capsys, tmp_path, out, *words)


def test_psychopy_units_with_psychopy_still_work(stimset, tmp_path):
    out = tmp_path / "exp"
    assert main(["experiment", str(stimset), "-o", str(out), "--psychopy", "--psychopy-units", "pix"]) == 0
    assert (out / "psychopy").is_dir()


def test_an_output_under_a_file_says_the_parent_is_a_file(stimset, tmp_path, capsys):
    f = tmp_path / "ok.csv"
    f.write_text("x\n")
    assert main(["experiment", str(stimset), "-o", str(f / "e")]) == 2
    err = capsys.readouterr().err
    assert f"{f} is a file, not a directory" in err and err.count("\n") == 1, err


def test_the_output_may_not_be_the_set_nor_empty(stimset, tmp_path, capsys):
    assert main(["experiment", str(stimset), "-o", str(stimset), "--force"]) == 2
    assert "is an input of this command" in capsys.readouterr().err
    assert (stimset / "manifest.csv").is_file()
    assert main(["experiment", str(stimset), "-o", ""]) == 2
    assert "empty output path" in capsys.readouterr().err


def test_the_shipped_config_serves_runs_without_the_psychopy_export(stimset, tmp_path):
    # the README's step 2 (configs/experiment.yaml keeps psychopy_units for when the export is made)
    from pathlib import Path

    cfg = Path(__file__).resolve().parents[1] / "configs" / "experiment.yaml"
    assert "psychopy_units" in cfg.read_text()
    for extra in ([], ["--psychopy"]):
        out = tmp_path / f"exp{len(extra)}"
        assert main(["experiment", str(stimset), "-o", str(out), "--config", str(cfg), *extra]) == 0
        assert (out / "index.html").is_file() and (out / "psychopy").is_dir() == bool(extra)
