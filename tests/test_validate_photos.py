"""The photo validation script reads a data set of the same kind as ../shared/data/photos but named and
stored otherwise (it judges the work on unseen photos): formats, groups, photos without a usable mask."""

import importlib.util
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "validate_photos.py"


@pytest.fixture(scope="module")
def vp():
    sys.path.insert(0, str(SCRIPT.parent))
    try:
        spec = importlib.util.spec_from_file_location("validate_photos", SCRIPT)
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        yield mod
    finally:
        sys.path.remove(str(SCRIPT.parent))


def _photo(size=80, seed=0):
    """A red disk on a noisy grey ground, and its mask."""
    rng = np.random.default_rng(seed)
    img = np.clip(rng.normal(120, 12, (size, size, 3)), 0, 255).astype(np.uint8)
    mask = np.zeros((size, size), np.uint8)
    cv2.circle(mask, (size // 2, size // 2), size // 4, 255, -1)
    img[mask > 0] = (40, 40, 220)  # BGR red
    return img, mask


def test_groups(vp):
    assert vp.group_of("weizmann_horse001.jpg") == "weizmann"
    assert vp.group_of("gsc_cat_2007_000876.jpg") == "gsc"
    assert vp.group_of("horse001.png") == "horse"
    assert vp.group_of("0042.jpg") == "0042"


def test_pairs_formats_and_lone_photos(vp, tmp_path, capsys):
    img, mask = _photo()
    for stem, ext in (("a_1", ".jpg"), ("a_2", ".PNG"), ("b_1", ".jpeg"), ("c_1", ".jpg")):
        cv2.imwrite(str(tmp_path / f"{stem}{ext}"), img)
    for stem in ("a_1", "a_2", "b_1"):
        cv2.imwrite(str(tmp_path / f"{stem}.mask.png"), mask)
    got = vp.photo_pairs(tmp_path, report=sys.stderr)
    assert [p.name for p in got] == ["a_1.jpg", "a_2.PNG", "b_1.jpeg"]
    assert "1 photo(s) without a STEM.mask.png skipped: c_1.jpg" in capsys.readouterr().err


def test_main_measures_and_names_bad_masks(vp, tmp_path, capsys):
    img, mask = _photo()
    cv2.imwrite(str(tmp_path / "disk_1.png"), img)
    cv2.imwrite(str(tmp_path / "disk_1.mask.png"), mask)
    cv2.imwrite(str(tmp_path / "disk_2.png"), img)
    cv2.imwrite(str(tmp_path / "disk_2.mask.png"), mask[:40])  # another size than its photo
    out = tmp_path / "rows.csv"
    assert vp.main([str(tmp_path), "--modes", "box,grabcut", "--csv", str(out)]) == 0
    cap = capsys.readouterr()
    assert "disk_2.mask.png: 80x40, the photo 80x80; photo skipped" in cap.err
    assert "1 of 2 photos measured" in cap.out
    import pandas as pd

    rows = pd.read_csv(out)
    assert set(rows.image) == {"disk_1.png"}
    # a plain disk from its box: both find it (IoU against the rasterised circle)
    assert (rows.iou > 0.9).all(), rows


def test_main_refuses_a_missing_directory(vp, tmp_path, capsys):
    assert vp.main([str(tmp_path / "nowhere")]) == 2
    assert "not a directory" in capsys.readouterr().err
