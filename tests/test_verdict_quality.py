"""The measures of a photographed outline's quality (attneave.stimuli.extraction.quality)
and the reasons they give in the verdict, on constructed photos whose
answers are known: exact pixel counts of colour regions, outlines on and
off a rendered edge, a square sharing sides with its box.
"""

from __future__ import annotations

import numpy as np
import pytest

from attneave.stimuli.extraction.quality import box_contact, box_gap, colour_error, edge_support
from attneave.stimuli.extraction.verdict import frame_contact, judge
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.render import coverage


def _square(x0, y0, x1, y1):
    """The outline of the pixels of columns x0..x1-1, rows y0..y1-1 (pixel edges at half-integers)."""
    return Contour(np.array([[x0 - 0.5, y0 - 0.5], [x1 - 0.5, y0 - 0.5], [x1 - 0.5, y1 - 0.5], [x0 - 0.5, y1 - 0.5]]))


def _circle(cx, cy, r, n=720):
    th = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return Contour(np.c_[cx + r * np.cos(th), cy + r * np.sin(th)])


def test_box_contact_counts_the_sides_shared_with_the_box():
    corners = _square(10, 10, 30, 30)  # a 20 px square
    assert box_contact(corners, (10, 10, 20, 20)) == 1.0  # the box is the square
    assert box_contact(corners, (10, 10, 40, 40)) == 0.5  # top and left sides
    assert box_contact(corners, (10, 5, 40, 40)) == 0.25  # the left side only
    assert box_contact(corners, (5, 5, 40, 40)) == 0.0
    # sampled every 0.5 px, the sides meeting a shared side also count over the
    # first `within` = 1 px from it
    sq = corners.resample(spacing=0.5)
    assert box_contact(sq, (10, 10, 40, 40)) == pytest.approx((40 + 2) / 80)
    assert box_contact(sq, (10, 5, 40, 40)) == pytest.approx((20 + 2) / 80)
    # the frame is the box of the whole image
    assert frame_contact(sq, (60, 30)) == box_contact(sq, (0, 0, 30, 60)) == pytest.approx((20 + 2) / 80)


def test_box_gap_of_a_box_drawn_with_a_margin_and_of_a_missing_part():
    disk = _circle(49.5, 49.5, 20)  # extent 29.5 .. 69.5 on both axes (samples at 0, 90, 180, 270 degrees)
    box = (26, 26, 48, 48)  # sides at 25.5 and 73.5: a margin of 4 px on every side
    assert box_gap(disk, box) == pytest.approx(4 / 48)
    # a 5 % margin of the object's size on every side gives m / (1 + 2 m)
    assert box_gap(disk, (28, 28, 44, 44)) == pytest.approx(0.05 / 1.1)
    # the disk without its bottom below y = 60 (a missing part): the bottom gap is 13.5 px of 48
    p = disk.points
    cut = Contour(np.c_[p[:, 0], np.minimum(p[:, 1], 60.0)])
    assert box_gap(cut, box) == pytest.approx(13.5 / 48)
    assert box_gap(disk, (32, 32, 36, 36)) < 0  # the outline leaves the box


def _two_colour(shape=(80, 100)):
    img = np.empty((*shape, 3), np.uint8)
    img[...] = (40, 120, 40)
    img[20:60, 20:60] = (220, 30, 30)
    return img


def test_colour_error_is_zero_for_the_true_outline_and_half_for_one_colour():
    img = _two_colour()
    truth = np.zeros(img.shape[:2], bool)
    truth[20:60, 20:60] = True
    assert colour_error(img, truth) == 0.0
    # an outline through a region of one colour: the two sides cannot be told apart
    assert colour_error(np.full(img.shape[:2], 128, np.uint8), truth) == 0.5


def test_colour_error_of_a_leaked_outline_is_the_share_of_background_inside():
    # the outline takes 20 columns of background beside the object: 3 px inside
    # it (the core) are 37 columns of object and 17 of background, the ring
    # outside it is all background, so the background's colour is classed
    # background and 17 of the core's 54 columns are misclassified: error 17/108.
    # The 1 px blur mixes the two columns on either side of the colour boundary.
    img = _two_colour()
    leaked = np.zeros(img.shape[:2], bool)
    leaked[20:60, 20:80] = True
    assert colour_error(img, leaked) == pytest.approx(17 / 108, abs=2 / 108)


def test_several_outlines_of_one_photo_measure_its_fields_once(monkeypatch):
    import attneave.stimuli.extraction.quality as quality
    import attneave.stimuli.extraction.verdict as verdict
    from attneave.stimuli.extraction.outlines import Extraction

    calls = {"edge": 0, "contrast": 0}
    edge, contrast = quality.edge_distance, verdict.contrast_field

    def count(name, f):
        def wrapped(*a, **k):
            calls[name] += 1
            return f(*a, **k)
        return wrapped

    monkeypatch.setattr(quality, "edge_distance", count("edge", edge))
    monkeypatch.setattr(verdict, "contrast_field", count("contrast", contrast))
    img = _two_colour()
    mask = np.zeros(img.shape[:2], bool)
    mask[20:60, 20:60] = True
    contours = [_square(20, 20, 60, 60).resample(spacing=0.5), _square(22, 22, 40, 40).resample(spacing=0.5),
                _square(42, 42, 58, 58).resample(spacing=0.5)]
    params = dict(method="auto", resolved="photo", objects="all", boxes=[None] * 3, mode="auto")
    v = judge(img, Extraction(contours, [[], [], []], mask, params))
    assert calls == {"edge": 1, "contrast": 1}
    # the lowest support and contrast of the three outlines, as each alone gives them
    alone = [judge(img, Extraction([c], [[]], mask, {**params, "boxes": [None]})) for c in contours]
    assert v.measures["edge_support"] == min(a.measures["edge_support"] for a in alone)
    assert v.measures["contrast"] == min(a.measures["contrast"] for a in alone)


def test_edge_support_on_and_off_a_rendered_edge():
    rng = np.random.default_rng(1)
    cov = coverage(_circle(60.3, 50.2, 30).points, (100, 120))
    img = np.clip(60 + 140 * cov + rng.normal(0, 4, cov.shape), 0, 255).astype(np.uint8)
    assert edge_support(img, _circle(60.3, 50.2, 30)) > 0.97
    assert edge_support(img, _circle(60.3, 50.2, 22)) < 0.03
    # half on the edge: a half-disk of the circle's radius closed by its diameter
    th = np.linspace(-np.pi / 2, np.pi / 2, 300)
    d = Contour(np.c_[60.3 + 30 * np.cos(th), 50.2 + 30 * np.sin(th)]).resample(spacing=0.5)
    assert edge_support(img, d) == pytest.approx(np.pi / (np.pi + 2), abs=0.04)


def _photo_extraction(mask, box=None, mode="auto"):
    from attneave.stimuli.extraction.outlines import Extraction

    ys, xs = np.nonzero(mask)
    c = _square(xs.min(), ys.min(), xs.max() + 1, ys.max() + 1).resample(spacing=0.5)
    params = dict(method="auto", resolved="photo", objects="largest", box=box, mode=mode)
    return Extraction([c], [[]], mask, params)


def test_verdict_names_a_leaked_outline_and_a_box_that_cuts():
    img = _two_colour()
    truth = np.zeros(img.shape[:2], bool)
    truth[20:60, 20:60] = True
    v = judge(img, _photo_extraction(truth, box=(16, 16, 48, 48)))
    m = v.measures
    assert m["colour_error"] == 0.0 and m["box_contact"] == 0.0 and m["edge_support"] > 0.95
    assert v.status == "suspect" and len(v.reasons) == 1 and "cannot be verified" in v.reason
    leaked = np.zeros(img.shape[:2], bool)
    leaked[20:70, 20:80] = True
    v = judge(img, _photo_extraction(leaked, box=(20, 20, 60, 50)))
    assert "colours inside and outside the outline overlap" in v.reason
    assert "runs along its box over 100%" in v.reason
    assert "of the outline lies on an image edge" in v.reason  # two of its four sides are on no edge
    # a box reaching far below the object: 36 of its 80 rows are below the outline
    v = judge(img, _photo_extraction(truth, box=(16, 16, 48, 80)))
    assert v.measures["box_gap"] == pytest.approx(36 / 80)
    assert "falls short of its box by 45%" in v.reason

def test_box_outline_is_ok_only_when_its_colours_part_and_it_reaches_the_box():
    img = _two_colour()
    truth = np.zeros(img.shape[:2], bool)
    truth[20:60, 20:60] = True
    # the true outline in a box drawn 2 px around it (gap 2 / 44): the calibrated rule holds
    v = judge(img, _photo_extraction(truth, box=(18, 18, 44, 44), mode="box"))
    assert v.status == "ok" and v.reasons == []
    # the same outline, found without a box, is not certified
    v = judge(img, _photo_extraction(truth, box=None, mode="auto"))
    assert v.status == "suspect" and "cannot be verified" in v.reason
    # a box reaching 6 px further down (gap 8 / 50: above the rule's 0.114, below the 0.2 that
    # names a missing part): not certified, and no other reason
    v = judge(img, _photo_extraction(truth, box=(18, 18, 44, 50), mode="box"))
    assert v.measures["box_gap"] == pytest.approx(8 / 50)
    assert v.status == "suspect" and v.reasons == [
        "figure-ground of a photograph (photo) cannot be verified: check the overlay"]
    # an outline through one colour (the object's top half cut off, the box on what is left):
    # colour error 0.5 of the half left inside and outside
    half = truth.copy()
    half[20:40] = False
    v = judge(img, _photo_extraction(half, box=(18, 38, 44, 24), mode="box"))
    assert v.measures["colour_error"] > 0.031 and v.status == "suspect"


def test_silhouettes_get_no_photo_measures():
    from attneave.stimuli.extraction import extract

    img = (255 * coverage(_circle(50.2, 40.1, 25).points, (80, 100))).round().astype(np.uint8)
    v = judge(img, extract(img, method="auto"))
    assert v.status == "ok"
    assert v.measures["colour_error"] is None and v.measures["box_contact"] is None


@pytest.mark.parametrize("width", [40, 70, 120])
def test_suspect_banner_on_a_narrow_image(width):
    # the reason is cut to the image's width; cutting once looped for ever on
    # narrow images (a silhouette of 70 px touching the frame)
    import faulthandler

    from attneave.stimuli.extraction import describe
    from attneave.stimuli.extraction.overlays import overlay
    from attneave.stimuli.extraction.verdict import Verdict

    img = (255 * coverage(_circle(width / 2, 30.2, 12).points, (60, width))).round().astype(np.uint8)
    c = _circle(width / 2, 30.2, 12)
    v = Verdict("suspect", ["touches the image frame over 5% of its outline", "a long second reason " * 5])
    faulthandler.dump_traceback_later(60, exit=True)  # a hang fails the run instead of stalling it
    try:
        out = overlay(img, [c], [describe(c, n=40)], verdict=v)
    finally:
        faulthandler.cancel_dump_traceback_later()
    assert out.shape[0] > 60 and out.shape[1:] == (width, 3)  # the band is added below the image
    assert np.all(out[-1, 1:-1] == (255, 140, 0))  # the orange band across the bottom
