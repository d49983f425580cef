"""``attneave extract`` at corpus scale: Dask, resuming after a signal, memory independent of the image count.

Every run that could hang (a child process, a forked pool) runs under a
subprocess timeout, so that a hang fails the test instead of blocking the suite.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

ATTNEAVE = str(Path(sys.executable).with_name("attneave"))
TESTS = str(Path(__file__).resolve().parent)


def _silhouettes(folder, n, size=48):
    """`n` black polygons/discs on white, each different (radius, lobes, phase), as PNG files."""
    import cv2

    folder.mkdir(parents=True, exist_ok=True)
    th = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    for k in range(n):
        r = size * (0.25 + 0.1 * (k % 5) / 5) * (1 + 0.15 * np.cos((2 + k % 4) * th + 0.3 * k))
        pts = np.stack([size / 2 + r * np.cos(th), size / 2 + r * np.sin(th)], 1)
        img = np.full((size, size), 255, np.uint8)
        cv2.fillPoly(img, [np.round(pts * 16).astype(np.int32)], 0, lineType=cv2.LINE_AA, shift=4)
        cv2.imwrite(str(folder / f"s{k:05d}.png"), img)
    return folder


def _files(d):
    return {p.name: p.read_bytes() for p in sorted(Path(d).iterdir())}


def _same(a, b):
    fa, fb = _files(a), _files(b)
    assert sorted(fa) == sorted(fb)
    assert [n for n in fa if fa[n] != fb[n]] == []


def test_local_cluster_byte_identical_to_one_worker(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    from attneave.stimuli.extraction.pipeline import extract_images

    imgs = sorted(str(p) for p in _silhouettes(tmp_path / "in", 40).iterdir())
    one = extract_images(imgs, tmp_path / "one", workers=1, progress=False, method="otsu")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as c, \
            distributed.Client(c) as client:
        dask = extract_images(imgs, tmp_path / "dask", scheduler=client, progress=False, method="otsu")
    _same(tmp_path / "one", tmp_path / "dask")
    # 40 images x 4 files + the summary, and no record directory left behind
    assert len(_files(tmp_path / "one")) == 40 * 4 + 1
    assert list(one["image"]) == imgs and (dask["status"] != "failed").all()


# OpenCV's pool runs (its threads then sleep on condition variables), then a pool of two workers is
# forked: a worker that called cv2.setNumThreads waited forever in pthread_cond_destroy for threads
# that do not exist in it (the suite hung so when an earlier test had used OpenCV in the same process)
_AFTER_OPENCV = """
import sys, time
import cv2, numpy as np
sys.path.insert(0, sys.argv[2])
from pathlib import Path
from test_batch import TINY
from test_extract_scale import _silhouettes
from attneave.stimuli.batch.runner import run_batch
from attneave.stimuli.extraction.pipeline import extract_images
d = Path(sys.argv[1])
imgs = sorted(str(p) for p in _silhouettes(d / "in", 6, size=32).iterdir())
cv2.GaussianBlur(np.zeros((1500, 1500), np.float32), (31, 31), 5)
time.sleep(0.3)
n = cv2.getNumThreads()
print("extract", len(extract_images(imgs, d / "x", workers=2, progress=False, method="otsu")), flush=True)
(d / "tiny.yaml").write_text(TINY)
time.sleep(0.3)
print("generate", run_batch(d / "tiny.yaml", d / "g", workers=2, progress=False).n_run, flush=True)
print("threads", n, cv2.getNumThreads())
"""


def test_workers_forked_after_opencv_ran_do_not_hang(tmp_path):
    try:
        r = subprocess.run([sys.executable, "-c", _AFTER_OPENCV, str(tmp_path), TESTS], capture_output=True,
                           text=True, timeout=60)
    except subprocess.TimeoutExpired as exc:
        pytest.fail(f"workers hung (60 s); stdout so far: {exc.stdout!r}")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.split("\n")
    assert lines[:2] == ["extract 6", "generate 9"]
    # the parent's OpenCV threads are as they were before the pool
    n, after = lines[2].split()[1:]
    assert n == after


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    """60 silhouettes and the directory of an uninterrupted run."""
    base = tmp_path_factory.mktemp("corpus")
    src = _silhouettes(base / "in", 60)
    subprocess.run([ATTNEAVE, "extract", str(src), "--method", "otsu", "--quiet", "-o", str(base / "ref")],
                   check=True, capture_output=True, timeout=120)
    return src, base / "ref"


@pytest.mark.parametrize("sig, workers", [(signal.SIGKILL, "1"), (signal.SIGTERM, "2")])
def test_signal_mid_run_then_rerun_completes_byte_identical(corpus, tmp_path, sig, workers):
    src, ref = corpus
    cmd = [ATTNEAVE, "extract", str(src), "--method", "otsu", "--quiet", "--workers", workers, "-o"]
    out = tmp_path / "out"
    proc = subprocess.Popen([*cmd, str(out)], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    records = out / ".extract-progress"
    t0 = time.monotonic()
    while time.monotonic() - t0 < 60 and proc.poll() is None:
        if records.is_dir() and len(list(records.glob("*.done.json"))) >= 10:
            break
        time.sleep(0.02)
    assert proc.poll() is None, "the run ended before it could be interrupted"
    os.kill(proc.pid, sig)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode in (-sig, 128 + sig)
    assert "Traceback" not in err
    # unfinished, visibly: no summary, some records
    assert not (out / "summary.csv").exists()
    done_before = len(list(records.glob("*.done.json")))
    assert 10 <= done_before < 60
    rerun = subprocess.run([*cmd, str(out)], capture_output=True, text=True, timeout=120)
    assert rerun.returncode == 0, rerun.stderr
    # the images finished before the signal were not processed again
    assert f"; {done_before} done by an earlier, interrupted run" in rerun.stderr
    _same(ref, out)


# the command in this process with tracemalloc on, every summary row made ~100 kB by a long
# reason: a run that keeps the rows (a list, a DataFrame) holds n x 100 kB at its end
_PEAK = """
import sys, tracemalloc
from pathlib import Path
import attneave.stimuli.extraction.pipeline as pipeline
from attneave.cli import main

real = pipeline.process_one

def ballast(image, stem, outdir, opts):
    row = real(image, stem, outdir, opts)
    row["reason"] = "x" * 100_000
    return row

pipeline.process_one = ballast
src, out = sys.argv[1], Path(sys.argv[2])
args = ["extract", src, "--method", "otsu", "--quiet", "-n", "8"]
assert main([*args, "-o", str(out / "warm")]) == 0  # imports, caches
tracemalloc.start()
base = tracemalloc.get_traced_memory()[0]
assert main([*args, "-o", str(out / "run")]) == 0
print(tracemalloc.get_traced_memory()[1] - base)
"""


def test_summary_rows_are_streamed_not_held(tmp_path):
    src = _silhouettes(tmp_path / "in", 100, size=24)
    r = subprocess.run([sys.executable, "-c", _PEAK, str(src), str(tmp_path)], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    peak = int(r.stdout.split()[-1])
    rows = (tmp_path / "run" / "summary.csv").read_text().splitlines()
    assert len(rows) == 101 and len(rows[-1]) > 100_000
    # 100 rows of 100 kB are 10 MB (the rows held, as before the records: peak 11.5 MB);
    # streamed, 1.4-1.5 MB at 60, 100 or 150 images
    assert peak < 4_000_000, peak
