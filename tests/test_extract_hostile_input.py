"""Hostile and careless input to ``attneave extract`` (issue 11): memory
bombs refused from the header, special files refused instead of read, and
worker processes that do not outlive a killed parent."""

from __future__ import annotations

import os
import struct
import sys
import threading
import time
import zlib

import numpy as np
import pytest


def _png_header_only(w, h):
    """A small PNG whose header claims w x h pixels (its data would decode to w*h bytes)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    rows = zlib.compress(b"\x00" * (w + 1) * 4)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
            + chunk(b"IDAT", rows) + chunk(b"IEND", b""))


def test_pixel_count_checked_from_the_header_before_decoding(tmp_path, capsys):
    import pandas as pd

    from attneave.cli import main

    (tmp_path / "huge.png").write_bytes(_png_header_only(65535, 65535))
    (tmp_path / "big.png").write_bytes(_png_header_only(3000, 2000))
    out = tmp_path / "out"
    t0 = time.perf_counter()
    assert main(["extract", str(tmp_path / "huge.png"), str(tmp_path / "big.png"), "-o", str(out),
                 "--max-pixels", "5e6"]) == 1
    assert time.perf_counter() - t0 < 20  # nothing was decoded (4.3 GB for the first)
    text = (out / "summary.csv").read_text()
    assert len(text.strip().splitlines()) == 3  # header + one line per image: no newline in a reason
    s = pd.read_csv(out / "summary.csv")
    assert s["status"].tolist() == ["failed", "failed"]
    assert "65535x65535" in s["reason"][0] and "limit of 5000000 pixels" in s["reason"][0]
    assert "3000x2000" in s["reason"][1]
    assert "2 failed" in capsys.readouterr().err


def test_fifo_input_is_refused_not_read(tmp_path):
    from attneave.cli import main

    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    result = {}
    t = threading.Thread(target=lambda: result.update(rc=main(["extract", str(fifo), "-o", str(tmp_path / "o")])),
                         daemon=True)
    t.start()
    t.join(20)
    if t.is_alive():  # unblock the reader so that the thread can end, then fail
        with open(fifo, "wb"):
            pass
        pytest.fail("extract blocked on a FIFO")
    assert result["rc"] == 1
    assert "FIFO" in (tmp_path / "o" / "summary.csv").read_text()


def _children(pid):
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return [int(p) for p in f.read().split()]
    except OSError:
        return []


def _alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            state = f.read().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state not in ("Z", "X")  # a zombie has exited


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_workers_exit_when_the_parent_is_killed(tmp_path):
    import signal
    import subprocess

    import cv2

    rng = np.random.default_rng(0)
    files = []
    for i in range(40):  # photos: each takes GrabCut a while
        img = rng.integers(0, 255, (300, 300, 3), dtype=np.uint8)
        cv2.rectangle(img, (80, 80), (220, 220), (20, 20, 220), -1)
        files.append(str(tmp_path / f"p{i}.png"))
        cv2.imwrite(files[-1], img)
    proc = subprocess.Popen([sys.executable, "-m", "attneave.cli", "extract", *files, "-o", str(tmp_path / "o"),
                             "--workers", "2"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        workers = []
        while time.monotonic() < deadline and len(workers) < 2 and proc.poll() is None:
            time.sleep(0.2)
            workers = [c for c in _children(proc.pid) if _alive(c)]
        if len(workers) < 2:
            pytest.skip("the batch ended before two workers were seen")
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and any(_alive(w) for w in workers):
            time.sleep(0.2)
        left = [w for w in workers if _alive(w)]
        for w in left:  # do not leave them behind after a failure
            os.kill(w, signal.SIGKILL)
        assert not left, f"workers {left} outlived their parent by 10 s"
    finally:
        if proc.poll() is None:
            proc.kill()
