"""Box-assisted figure-ground: the box's inner band as probable background."""

import numpy as np

from attneave.stimuli.extraction.figure_ground.grabcut import fill_holes, grabcut, largest_part, to_bgr8
from attneave.stimuli.extraction.figure_ground.photo import box_around, mask_iou, segment_photo


def test_box_band_excludes_background_seen_only_inside_the_box():
    # a red disk with a green patch of background touching it, the patch
    # running to the left side of a box drawn with a 5 % margin: the green
    # is seen nowhere outside the box, so plain GrabCut's background model
    # cannot explain it and it joins the object; held as probable
    # background, the box's inner band teaches the model the green
    rng = np.random.default_rng(1)
    img = rng.normal(70, 10, (200, 200, 3))
    yy, xx = np.mgrid[:200, :200]
    disk = (xx - 100) ** 2 + (yy - 100) ** 2 <= 50**2
    img[disk] = rng.normal((200, 50, 40), 10, (np.count_nonzero(disk), 3))
    box = box_around(disk, 0.05)
    patch = (xx >= box[0]) & (xx < 52) & (np.abs(yy - 100) < 12) & ~disk
    img[patch] = rng.normal((40, 200, 60), 10, (np.count_nonzero(patch), 3))
    img = np.clip(img, 0, 255).astype(np.uint8)

    plain = fill_holes(largest_part(grabcut(to_bgr8(img), box=box)))
    assert np.count_nonzero(plain & patch) > 0.5 * np.count_nonzero(patch)  # the case is a real one
    res = segment_photo(img, box=box)
    assert np.count_nonzero(res.mask & patch) == 0
    assert mask_iou(res.mask, disk) > 0.99
    assert res.params["mode"] == "box"


def test_grabcut_gives_the_same_answer_twice():
    # GrabCut seeds its colour models by k-means from OpenCV's global
    # random generator: without a reset, answers depend on earlier calls
    rng = np.random.default_rng(2)
    img = rng.integers(0, 256, (60, 80, 3), dtype=np.uint8)
    img[15:45, 20:60] //= 3
    bgr = to_bgr8(img)
    first = grabcut(bgr, box=(10, 8, 60, 44))
    import cv2

    cv2.kmeans(rng.random((50, 3), dtype=np.float32), 3, None,
               (cv2.TERM_CRITERIA_MAX_ITER, 3, 0), 1, cv2.KMEANS_RANDOM_CENTERS)  # moves the generator on
    assert np.array_equal(grabcut(bgr, box=(10, 8, 60, 44)), first)
