"""Faults, carelessness and hostile input on the batch path (issue 11, items 1, 2, 3, 5, 6, 10, 14, 15).

Each test names the item it checks; each failed on the code before the fix.
"""

from __future__ import annotations

import errno
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
from attneave.stimuli.errors import InputError
from attneave.stimuli.stimulus_set import read_stimulus_set, write_stimulus_set

SLOW_GENERATE = Path(__file__).with_name("slow_generate.py")

# 5 recipe calls, 6 stimuli, 48 px
SMALL = """\
seed: 3
canvas: {width: 48, height: 48, margin: 4}
conditions:
  - name: rf
    recipe: radial_frequency
    params: {n: 64}
    grid: {frequency: [3, 5]}
    repeats: 2
  - name: poly
    recipe: attneave_polygon
    params: {version: both, grid: 30, n_points: 6}
"""


def hashes(d, skip=()):
    d = Path(d)
    return {p.relative_to(d).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(d.rglob("*")) if p.is_file() and p.relative_to(d).as_posix() not in skip}


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    """The config and its set made by one clean run."""
    base = tmp_path_factory.mktemp("small")
    cfg = base / "small.yaml"
    cfg.write_text(SMALL)
    assert cli(["generate", str(cfg), "-o", str(base / "ref"), "--no-progress"]) == 0
    return cfg, hashes(base / "ref")


def _one_line(capsys):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


def test_1_force_removes_only_the_earlier_batchs_files(small, tmp_path, capsys):
    cfg, ref = small
    dest = tmp_path / "set"
    assert cli(["generate", str(cfg), "-o", str(dest), "--no-progress"]) == 0
    mine = {"images/holiday.png": b"my photo", "contours/traced.csv": b"x,y\n1,2\n", "notes.txt": b"mine"}
    for rel, data in mine.items():
        (dest / rel).write_bytes(data)
    other = tmp_path / "other.yaml"
    other.write_text(SMALL.replace("seed: 3", "seed: 4").replace("repeats: 2", "repeats: 1"))
    assert cli(["generate", str(other), "-o", str(dest), "--force", "--no-progress"]) == 0
    for rel, data in mine.items():
        assert (dest / rel).read_bytes() == data
    # and of the earlier batch nothing is left: the set is what a fresh run writes
    assert cli(["generate", str(other), "-o", str(tmp_path / "fresh"), "--no-progress"]) == 0
    assert hashes(dest, skip=mine) == hashes(tmp_path / "fresh")


def test_2_user_files_named_like_temporaries_survive(small, tmp_path):
    cfg, ref = small
    dest = tmp_path / "set"
    dest.mkdir()
    mine = [".draft.tmp", ".x.tmp.bak", ".attneave-tmp-notes"]
    for rel in mine:
        (dest / rel).write_text("mine")
    assert cli(["generate", str(cfg), "-o", str(dest), "--no-progress"]) == 0
    assert all((dest / rel).read_text() == "mine" for rel in mine)
    assert hashes(dest, skip=mine) == ref
    # and in images/, through a --force rerun
    mine += ["images/.a.png.tmp", "contours/.b.csv.tmp.bak"]
    for rel in mine[-2:]:
        (dest / rel).write_text("mine")
    assert cli(["generate", str(cfg), "-o", str(dest), "--force", "--no-progress"]) == 0
    assert all((dest / rel).read_text() == "mine" for rel in mine)
    assert hashes(dest, skip=mine) == ref
    # the temporaries of atomic_write carry the package name and this pid
    from attneave.stimuli.io import atomic_write, is_temporary

    with atomic_write(tmp_path / "f.txt") as fh:
        fh.write("x")
        [tmp] = [p.name for p in tmp_path.iterdir() if p.name != "set"]
    assert tmp.startswith(f".attneave-tmp-{os.getpid()}-") and is_temporary(tmp)
    assert not any(is_temporary(Path(rel).name) for rel in mine)


def _children(pid):
    """Pids of the live (not zombie) processes whose parent is `pid`, from /proc."""
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as fh:
                fields = fh.read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if fields[0] != "Z" and int(fields[1]) == pid:
            found.append(int(entry))
    return found


def _alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="finds the workers through /proc")
def test_3_workers_exit_when_their_parent_is_killed(small, tmp_path):
    cfg, _ = small
    proc = subprocess.Popen(
        [sys.executable, str(SLOW_GENERATE), "2", "generate", str(cfg), "-o", str(tmp_path / "set"),
         "--workers", "2", "--no-progress"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )
    workers = []
    try:
        deadline = time.monotonic() + 60
        while len(workers) < 2 and time.monotonic() < deadline and proc.poll() is None:
            workers = _children(proc.pid)
            time.sleep(0.05)
        assert len(workers) == 2, "the two workers did not start"
        os.kill(proc.pid, signal.SIGKILL)  # the parent alone
        proc.wait(timeout=10)
        deadline = time.monotonic() + 10
        while any(_alive(w) for w in workers) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not any(_alive(w) for w in workers), "workers outlived their parent by 10 s"
    finally:
        for w in workers:  # the processes this test started, if the test failed
            if _alive(w):
                os.kill(w, signal.SIGKILL)
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_5_a_second_run_on_a_locked_directory_is_refused(small, tmp_path, capsys):
    import fcntl

    cfg, _ = small
    dest = tmp_path / "set"
    dest.mkdir()
    # another process's lock, as the documented protocol takes it: flock on .attneave.lock holding its pid
    with open(dest / ".attneave.lock", "w") as held:
        fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
        held.write("424242\n")
        held.flush()
        assert cli(["generate", str(cfg), "-o", str(dest), "--no-progress"]) == 2
        err = _one_line(capsys)
        assert str(dest) in err and "424242" in err
        assert sorted(p.name for p in dest.iterdir()) == [".attneave.lock"]  # nothing written
    assert cli(["generate", str(cfg), "-o", str(dest), "--no-progress"]) == 0  # free again


def test_6_disk_full_is_one_line_exit_1_and_the_rerun_completes(small, tmp_path, capsys, monkeypatch):
    import attneave.stimuli.render.files as core

    cfg, ref = small
    dest = tmp_path / "set"
    real, calls = core.write_png, []

    def fills_up(path, *args, **kwargs):
        calls.append(path)
        if len(calls) >= 4:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        return real(path, *args, **kwargs)

    monkeypatch.setattr(core, "write_png", fills_up)
    assert cli(["generate", str(cfg), "-o", str(dest), "--no-progress"]) == 1
    err = _one_line(capsys)
    assert "No space left on device" in err and str(dest) in err
    # nothing corrupt: every stimulus file there is the one a clean run writes, and no manifest yet
    got = hashes(dest)
    assert not (dest / "manifest.csv").exists()
    assert all(got[rel] == ref[rel] for rel in got if rel.startswith(("images/", "contours/")))
    monkeypatch.setattr(core, "write_png", real)
    assert cli(["generate", str(cfg), "-o", str(dest), "--no-progress"]) == 0
    assert hashes(dest) == ref


def test_10_huge_grids_deep_nesting_and_huge_files_are_refused_at_once(tmp_path, capsys):
    cfg = tmp_path / "grid.yaml"
    cfg.write_text("seed: 1\nconditions:\n  - name: big\n    recipe: blob\n    grid:\n"
                   f"      n: {list(range(8, 408))}\n      r0: {list(range(1, 501))}\n")  # 200,000 cells
    t0 = time.perf_counter()
    assert cli(["generate", str(cfg), "-o", str(tmp_path / "out"), "--dry-run"]) == 2
    assert time.perf_counter() - t0 < 5
    err = _one_line(capsys)
    assert "'big'" in err and "200000" in err and "100000" in err

    deep = tmp_path / "deep.yaml"
    deep.write_text("seed: 1\nconditions: " + "[" * 500 + "]" * 500 + "\n")
    assert cli(["generate", str(deep), "-o", str(tmp_path / "out"), "--dry-run"]) == 2
    assert "nested deeper than 50" in _one_line(capsys)

    laughs = tmp_path / "laughs.yaml"
    text = "seed: 1\na0: &a0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n"
    for i in range(1, 9):
        text += f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]\n"
    laughs.write_text(text + "conditions: [{name: a, recipe: blob}]\n")
    assert cli(["generate", str(laughs), "-o", str(tmp_path / "out"), "--dry-run"]) == 2
    assert "aliases are expanded" in _one_line(capsys)

    big = tmp_path / "big.yaml"
    big.write_text("# padding\n" * 200_000 + "seed: 1\nconditions: [{name: a, recipe: blob}]\n")
    assert cli(["generate", str(big), "-o", str(tmp_path / "out"), "--dry-run"]) == 2
    assert "larger than 1000000 bytes" in _one_line(capsys)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("column", ["contour", "image"])
@pytest.mark.parametrize("how", ["dotdot", "absolute", "symlink", "sibling"])
def test_14_manifest_paths_that_leave_the_set_are_refused(tmp_path, column, how):
    th = np.linspace(0, 2 * np.pi, 32, endpoint=False)
    d = tmp_path / "set"
    write_stimulus_set(d, {"disc": np.c_[50 + 20 * np.cos(th), 50 + 20 * np.sin(th)]}, size=(100, 100))
    secret = tmp_path / "secret.csv"  # outside the set, a valid contour file
    secret.write_bytes((d / "contours" / "disc.csv").read_bytes())
    if how == "dotdot":
        rel = "../secret.csv"
    elif how == "absolute":
        rel = str(secret)
    elif how == "sibling":  # a directory whose name begins with the set's: not inside it
        (tmp_path / "set2").mkdir()
        secret.replace(tmp_path / "set2" / "secret.csv")
        rel = "../set2/secret.csv"
    else:
        (d / "contours" / "link.csv").symlink_to(secret)
        rel = "contours/link.csv"
    manifest = d / "manifest.csv"
    text = manifest.read_text()
    old = "contours/disc.csv" if column == "contour" else "images/disc.png"
    manifest.write_text(text.replace(old, rel))
    with pytest.raises(InputError) as exc:
        read_stimulus_set(d)
    msg = str(exc.value)
    assert "\n" not in msg and "line 2" in msg and f"column {column!r}" in msg


def test_15_workers_are_capped_at_the_jobs_with_a_warning(small, tmp_path, capsys, monkeypatch):
    import concurrent.futures

    cfg, ref = small
    started = []

    class Counting(concurrent.futures.ProcessPoolExecutor):
        def __init__(self, max_workers=None, *args, **kwargs):
            started.append(max_workers)
            super().__init__(max_workers, *args, **kwargs)

    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", Counting)
    assert cli(["generate", str(cfg), "-o", str(tmp_path / "set"), "--workers", "500", "--no-progress"]) == 0
    assert started and max(started) <= 5  # the config has 5 recipe calls
    err = capsys.readouterr().err
    assert "warning: --workers 500 is more than the" in err
    assert hashes(tmp_path / "set") == ref


def test_5_the_lock_dies_with_its_holder_not_with_its_forked_workers(tmp_path):
    from attneave.stimuli.batch.outdir import locked

    # a holder that forks a long-lived child (as the worker pool does) and then dies without
    # cleaning up (as under kill -9): the directory must be free although the child lives on
    script = (
        "import os, sys, time\n"
        "from attneave.stimuli.batch.outdir import locked\n"
        "with locked(sys.argv[1]):\n"
        "    child = os.fork()\n"
        "    if child == 0:\n"
        "        os.closerange(0, 3)\n"
        "        time.sleep(30)\n"
        "        os._exit(0)\n"
        "    print(child, flush=True)\n"
        "    os._exit(0)\n"
    )
    proc = subprocess.run([sys.executable, "-c", script, str(tmp_path)], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stderr
    child = int(proc.stdout)
    try:
        assert _alive(child)
        with locked(tmp_path):  # refused (InputError) while the child held the lock
            pass
    finally:
        os.kill(child, signal.SIGKILL)


def test_review_an_images_link_leading_outside_is_refused_before_writing(small, tmp_path, capsys):
    # the set's PNGs were written through the link into another directory, and the set then
    # written was refused by 'analyze' (its paths lead outside the set)
    cfg, _ = small
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "holiday.png").write_bytes(b"my photo")
    dest = tmp_path / "set"
    dest.mkdir()
    (dest / "images").symlink_to(elsewhere)
    assert cli(["generate", str(cfg), "-o", str(dest), "--force", "--no-progress"]) == 2
    err = _one_line(capsys)
    assert "images: leads outside the output directory" in err
    assert sorted(p.name for p in elsewhere.iterdir()) == ["holiday.png"]
