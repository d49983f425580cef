"""The extraction overlay hides nothing of the image: the verdict's band is added below it, and the
colour bar goes to the corner where it covers the least of the outline."""

import cv2
import numpy as np

from attneave.stimuli.extraction.outlines import extract
from attneave.stimuli.extraction.overlays import overlay
from attneave.stimuli.extraction.scalespace import describe
from attneave.stimuli.extraction.verdict import Verdict


def _disk_image(cx, cy, r=40, size=(240, 320)):
    img = np.full(size, 255, np.uint8)
    cv2.circle(img, (cx, cy), r, 0, -1)
    return img


def _overlay(img, verdict=None):
    ex = extract(img, method="otsu")
    infos = [describe(c, n=64) for c in ex.contours]
    return overlay(img, ex.contours, infos, verdict=verdict)


def test_a_suspect_verdict_adds_its_band_below_the_image():
    img = _disk_image(160, 200)  # the object reaches near the bottom, where the band used to be drawn
    plain = _overlay(img)
    reason = "; ".join(["colours inside and outside the outline overlap"] * 6)  # several lines' worth
    flagged = _overlay(img, Verdict("suspect", [reason], {}))
    h, w = img.shape
    assert plain.shape == (h, w, 3) and flagged.shape[0] > h + 20 and flagged.shape[1] == w
    # the image and its outline are all there, bar the thin frame
    t = 4
    assert np.array_equal(flagged[t:h - t, t:w - t], plain[t:h - t, t:w - t])
    band = flagged[h:]
    assert (band == (255, 140, 0)).all(axis=2).mean() > 0.5  # an orange band with dark text
    assert (band.sum(axis=2) < 200).any()


def test_the_colour_bar_avoids_the_outline():
    # the object in the top-left corner, where the bar used to go
    img = _disk_image(45, 45, r=40)
    out = _overlay(img)
    white = (out[:30, :150] == 255).all(axis=2).mean()
    assert white < 0.9  # the outline (coloured) is drawn there, not covered by the bar ...
    corners = [out[4:24, -160:-4], out[-24:-4, 4:160], out[-24:-4, -160:-4]]
    # ... and the bar (its turbo colours) sits in one of the other corners
    assert any((np.abs(c.astype(int) - (48, 18, 59)).sum(axis=2) < 60).any() for c in corners)
