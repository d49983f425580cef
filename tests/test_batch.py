"""Batches: byte-identical stimulus sets, resume after kill -9, refusal, bad configs."""

from __future__ import annotations

import csv
import hashlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from attneave.cli import main as cli
from attneave.stimuli.batch.config import load_config
from attneave.stimuli.batch.job import plan_jobs, run_job
from attneave.stimuli.batch.runner import run_batch
from attneave.stimuli.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
# batch configs; configs/experiment.yaml holds the experiment page settings
CONFIGS = sorted(p for p in (ROOT / "configs").glob("*.yaml") if p.stem != "experiment")
SLOW_GENERATE = Path(__file__).with_name("slow_generate.py")

# 9 recipe calls, 15 stimuli, 64 px: polygons and their curved versions (a
# parent/child pair), RF shapes on a grid, and one Barenholtz triple
TINY = """\
seed: 11
canvas: {width: 64, height: 64, margin: 4}
output: {png_bit_depth: 8, svg: true}
conditions:
  - name: poly
    recipe: attneave_polygon
    params: {version: both, grid: 40}
    grid: {n_points: [5, 8]}
    repeats: 2
  - name: rf
    recipe: radial_frequency
    params: {n: 128}
    grid: {frequency: [3, 5], amplitude: [0.05, 0.15]}
    style: {figure: 0.25, ground: 0.75}
  - name: dfm
    recipe: deformation
    params: {displacement: 4, base: {generator: attneave_polygon, params: {n_points: 6}}}
"""


def hashes(d):
    """{relative path: sha256} of every file under `d`, hidden ones included."""
    d = Path(d)
    return {p.relative_to(d).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(d.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """The tiny config and its stimulus set made by one uninterrupted run (1 worker)."""
    base = tmp_path_factory.mktemp("tiny")
    cfg = base / "tiny.yaml"
    cfg.write_text(TINY)
    out = base / "ref"
    res = run_batch(cfg, out, workers=1, progress=False)
    assert (res.n_jobs, res.n_run) == (9, 9)
    return cfg, out, hashes(out)


def test_set_has_exactly_the_design_files(tiny):
    cfg, out, ref = tiny
    ids = [r["stimulus_id"] for r in _manifest(out)]
    expected = {"manifest.csv", "config.yaml"}
    for i in ids:
        expected |= {f"images/{i}.png", f"images/{i}.svg", f"contours/{i}.csv"}
    assert set(ref) == expected  # no marker, no .rows, no temporaries left
    assert len(ids) == 4 * 2 + 4 + 3


def test_manifest_rows(tiny):
    import cv2

    cfg, out, _ = tiny
    rows = _manifest(out)
    assert list(rows[0])[:10] == ["stimulus_id", "image", "contour", "svg", "width", "height", "generator",
                                  "seed", "params", "condition"]
    ids = [r["stimulus_id"] for r in rows]
    assert ids == sorted(ids) and len(set(ids)) == len(ids)
    by_id = {r["stimulus_id"]: r for r in rows}
    for r in rows:
        img = cv2.imread(str(out / r["image"]), cv2.IMREAD_UNCHANGED)
        assert img.shape[:2] == (int(r["height"]), int(r["width"])) == (64, 64)
        pts = np.loadtxt(out / r["contour"], delimiter=",", skiprows=1)
        assert pts.shape[1] == 2 and (pts >= -0.5).all() and (pts <= 63.5).all()
        # the seed column is SeedSequence(config seed, spawn_key=(condition, cell, rep))
        c = ["poly", "rf", "dfm"].index(r["batch_condition"])
        want = np.random.SeedSequence(11, spawn_key=(c, int(r["cell"]), int(r["rep"]))).generate_state(1, np.uint64)
        assert int(r["seed"]) == int(want[0])
        if r["parent_id"]:
            assert r["parent_id"] in by_id and by_id[r["parent_id"]]["seed"] == r["seed"]
    assert by_id["dfm_000_000_concave"]["parent_id"] == "dfm_000_000_base"
    assert by_id["dfm_000_000_convex"]["condition"] == "convex"
    assert by_id["poly_001_001_curved"]["parent_id"] == "poly_001_001_polygon"
    assert by_id["rf_003_000"]["condition"] == "rf"
    # grid cell 3 of frequency x amplitude is (5, 0.15): first key slowest
    assert '"amplitude":[0.15]' in by_id["rf_003_000"]["params"]
    assert '"frequency":[5]' in by_id["rf_003_000"]["params"]
    # no absolute paths or time stamps anywhere
    for p in out.rglob("*"):
        if p.is_file() and p.suffix in (".csv", ".yaml", ".svg"):
            assert str(out.parent) not in p.read_text()


def test_same_files_with_two_workers_and_from_the_resolved_config(tiny, tmp_path):
    cfg, out, ref = tiny
    run_batch(cfg, tmp_path / "w2", workers=2, progress=False)
    assert hashes(tmp_path / "w2") == ref
    # the written config.yaml, used as a config, makes the same set again
    resolved = tmp_path / "resolved.yaml"
    resolved.write_bytes((out / "config.yaml").read_bytes())
    run_batch(resolved, tmp_path / "again", workers=1, progress=False)
    assert hashes(tmp_path / "again") == ref


def test_same_files_through_a_dask_localcluster(tiny, tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    cfg, out, ref = tiny
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        run_batch(cfg, tmp_path / "dask", scheduler=cluster.scheduler_address, progress=False)
    assert hashes(tmp_path / "dask") == ref


def _journaled(dest):
    """Jobs whose rows are in the journals (complete lines only)."""
    rows = dest / ".rows"
    if not rows.is_dir():
        return 0
    return sum(p.read_text().count("\n") for p in rows.glob("*.jsonl"))


@pytest.mark.skipif(not hasattr(os, "killpg"), reason="needs POSIX process groups")
def test_kill_9_mid_way_then_rerun_gives_the_uninterrupted_files(tiny, tmp_path, capsys):
    cfg, out, ref = tiny
    dest = tmp_path / "killed"
    # each job sleeps 0.4 s (tests/slow_generate.py), so that the kill lands mid-way even under load
    proc = subprocess.Popen(
        [sys.executable, str(SLOW_GENERATE), "0.4", "generate", str(cfg), "-o", str(dest), "--workers", "2",
         "--no-progress"],
        cwd=tmp_path, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
    )
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and proc.poll() is None:
            if _journaled(dest) >= 3:
                break
            time.sleep(0.02)
        assert proc.poll() is None, f"the batch ended before the kill: {proc.stderr.read()!r}"
        os.killpg(proc.pid, signal.SIGKILL)  # the parent and its worker processes
    finally:
        proc.wait(timeout=30)
        proc.stderr.close()
    assert proc.returncode == -signal.SIGKILL
    assert not (dest / "manifest.csv").exists() and (dest / ".attneave-batch").exists()
    made = _journaled(dest)
    assert 3 <= made < 9
    # what a kill during a write leaves: a temporary file beside its final name
    (dest / "images" / ".attneave-tmp-999999-k9x2ab_c-rf_000_000.png").write_bytes(b"partial")

    capsys.readouterr()
    assert cli(["generate", str(cfg), "-o", str(dest), "--resume", "--no-progress"]) == 0
    assert f"({made} already complete)" in capsys.readouterr().err
    assert hashes(dest) == ref


def test_rerun_remakes_a_deleted_file_and_refuses_another_config(tiny, tmp_path):
    cfg, out, ref = tiny
    dest = tmp_path / "set"
    run_batch(cfg, dest, progress=False)
    (dest / "images" / "rf_002_000.png").unlink()
    res = run_batch(cfg, dest, progress=False)
    assert res.n_run == 1 and hashes(dest) == ref
    assert run_batch(cfg, dest, resume=True, progress=False).n_run == 0

    other = tmp_path / "other.yaml"
    other.write_text(TINY.replace("seed: 11", "seed: 12"))
    with pytest.raises(InputError, match="made by another config.*--force"):
        run_batch(other, dest, progress=False)
    assert hashes(dest) == ref  # untouched
    (dest / "notes.txt").write_text("mine")
    run_batch(other, dest, force=True, progress=False)
    fresh = tmp_path / "fresh"
    run_batch(other, fresh, progress=False)
    kept = hashes(dest)
    assert kept.pop("notes.txt") and kept == hashes(fresh) != ref


def test_resume_needs_a_batch_to_resume(tiny, tmp_path, capsys):
    cfg, _, _ = tiny
    assert cli(["generate", str(cfg), "-o", str(tmp_path / "none"), "--resume"]) == 2
    err = capsys.readouterr().err.strip()
    assert "nothing to resume" in err and "\n" not in err
    assert not (tmp_path / "none").exists()


@pytest.mark.parametrize(
    "change, where",
    [
        (("canvas: {width: 64", "canvas: {widht: 64"), "canvas.widht: unknown key"),  # unknown key
        (("repeats: 2", "repeats: two"), "conditions[0].repeats: must be an integer"),  # wrong type
        (("height: 64", "height: -64"), "canvas.height: must be >= 8"),  # negative size
        (("amplitude: [0.05, 0.15]", "amplitude: [0.05, -0.15]"), "conditions[1].grid.amplitude[1]: must be >= 0"),
        (("    recipe: radial_frequency\n", "    recipe: radial_frequency\n   oops\n"), "invalid YAML"),  # YAML
    ],
)
def test_bad_config_exits_2_with_one_line_and_writes_nothing(tmp_path, capsys, change, where):
    cfg = tmp_path / "bad.yaml"
    text = TINY.replace(*change)
    assert text != TINY
    cfg.write_text(text)
    out = tmp_path / "out"
    assert cli(["generate", str(cfg), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"attneave generate: error: {cfg}:"), err
    assert where in err
    assert not out.exists()


def test_bad_input_met_inside_a_recipe_leaves_no_directory(tmp_path, capsys):
    (tmp_path / "two.csv").write_text("x,y\n0,0\n1,1\n")  # passes the config check, not the recipe
    cfg = tmp_path / "c.yaml"
    cfg.write_text("seed: 1\ncanvas: {width: 64, height: 64, margin: 4}\n"
                   "conditions:\n  - name: c\n    recipe: from_csv\n    params: {path: two.csv}\n")
    assert cli(["generate", str(cfg), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "two.csv" in err and "condition 'c', call c_000_000" in err
    assert not (tmp_path / "out").exists()


def test_file_parameters_are_recorded_as_written(tmp_path):
    (tmp_path / "shapes").mkdir()
    (tmp_path / "shapes" / "sq.csv").write_text("x,y\n0,0\n0,10\n10,10\n10,0\n")
    cfg = tmp_path / "c.yaml"
    cfg.write_text("seed: 1\ncanvas: {width: 64, height: 64, margin: 4}\nconditions:\n  - name: c\n"
                   "    recipe: deformation\n    params:\n      base: {generator: from_csv, params: {path: shapes/sq.csv}}\n")
    out = tmp_path / "out"
    run_batch(cfg, out, progress=False)
    rows = _manifest(out)
    assert [r["condition"] for r in rows] == ["base", "concave", "convex"]
    assert all('"path":"shapes/sq.csv"' in r["params"] for r in rows)
    for p in out.rglob("*"):
        if p.is_file() and p.suffix in (".csv", ".yaml"):
            assert str(tmp_path) not in p.read_text()
    # a 10 px square fitted into 56 px, so 5.6x; the base keeps the square's area
    base = np.loadtxt(out / rows[0]["contour"], delimiter=",", skiprows=1)
    x, y = base.T
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    assert area == pytest.approx(56.0 ** 2, rel=1e-6)


def test_scheduler_without_dask_says_how_to_install(tiny, tmp_path, monkeypatch):
    cfg, _, _ = tiny
    monkeypatch.setitem(sys.modules, "dask.distributed", None)  # import fails
    with pytest.raises(InputError, match=r"attneave\[dask\]"):
        run_batch(cfg, tmp_path / "d", scheduler="tcp://127.0.0.1:1", progress=False)
    assert not (tmp_path / "d").exists()


def test_shipped_configs_generate(tmp_path):
    # the first recipe call of every condition of every shipped config ...
    for p in CONFIGS:
        batch = load_config(p)
        jobs = plan_jobs(batch)
        out = tmp_path / p.stem
        for sub in ("images", "contours", ".rows"):
            (out / sub).mkdir(parents=True)
        for cond in batch.conditions:
            job = next(j for j in jobs if j["condition"] == cond.name)
            rows = run_job(job, out)
            assert rows and all((out / r["image"]).is_file() and (out / r["contour"]).is_file() for r in rows)
    # ... and one whole set (16-bit PNG and SVG)
    res = run_batch(ROOT / "configs" / "radial_frequency.yaml", tmp_path / "rf", progress=False)
    assert res.n_stimuli == len(_manifest(tmp_path / "rf")) == 22


def _manifest(d):
    with open(Path(d) / "manifest.csv", newline="") as fh:
        return list(csv.DictReader(fh))
