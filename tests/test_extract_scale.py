"""``attneave extract`` at corpus scale: Dask, resuming after kill -9, memory independent of the image count."""

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

    imgs = sorted(str(p) for p in _silhouettes(tmp_path / "in", 50).iterdir())
    one = extract_images(imgs, tmp_path / "one", workers=1, progress=False, method="otsu")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as c, \
            distributed.Client(c) as client:
        dask = extract_images(imgs, tmp_path / "dask", scheduler=client, progress=False, method="otsu")
    _same(tmp_path / "one", tmp_path / "dask")
    # 50 images x 4 files + the summary, and no record directory left behind
    assert len(_files(tmp_path / "one")) == 50 * 4 + 1
    assert list(one["image"]) == imgs and (dask["status"] != "failed").all()


def test_kill_9_then_rerun_completes_byte_identical(tmp_path):
    src = _silhouettes(tmp_path / "in", 60)
    cmd = [ATTNEAVE, "extract", str(src), "--method", "otsu", "--quiet", "-o"]
    subprocess.run([*cmd, str(tmp_path / "ref")], check=True, capture_output=True, timeout=120)
    out = tmp_path / "out"
    proc = subprocess.Popen([*cmd, str(out)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    records = out / ".extract-progress"
    t0 = time.monotonic()
    while time.monotonic() - t0 < 60 and proc.poll() is None:
        if records.is_dir() and len(list(records.glob("*.done.json"))) >= 10:
            break
        time.sleep(0.02)
    assert proc.poll() is None, "the run ended before it could be interrupted"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    assert not (out / "summary.csv").exists()
    done_before = len(list(records.glob("*.done.json")))
    assert 10 <= done_before < 60
    rerun = subprocess.run([*cmd, str(out)], capture_output=True, text=True, timeout=120)
    assert rerun.returncode == 0, rerun.stderr
    # the images finished before the kill were not processed again
    assert f"; {done_before} done by an earlier, interrupted run" in rerun.stderr
    _same(tmp_path / "ref", out)


_PEAK = """
import resource, subprocess, sys
subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
"""


def _peak_kb(images, out):
    cmd = [ATTNEAVE, "extract", str(images), "-o", str(out), "--method", "otsu", "--quiet", "-n", "8", "--workers", "2"]
    r = subprocess.run([sys.executable, "-c", _PEAK, *cmd], capture_output=True, text=True, timeout=300, check=True)
    return int(r.stdout.split()[-1])


def test_memory_does_not_grow_with_the_number_of_images(tmp_path):
    small = _peak_kb(_silhouettes(tmp_path / "a", 100, size=24), tmp_path / "oa")
    large = _peak_kb(_silhouettes(tmp_path / "b", 1500, size=24), tmp_path / "ob")
    assert sum(1 for _ in open(tmp_path / "ob" / "summary.csv")) == 1501
    # 15x the images: the peak may differ by a little noise, not by rows held in memory
    assert large - small < 4000, (small, large)
    print(f"peak RSS {small} kB (100 images), {large} kB (1500)")
