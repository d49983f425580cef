"""Cross-validate the automatic photo search's rules on the development photos.

The automatic mode (``extract(photo, method='auto')`` on a photograph;
:func:`attneave.stimuli.extraction.figure_ground.photo.segment_photo`
without a box) runs GrabCut from several starts on the photo inset by 5 %
and keeps one of the hypotheses by a rule that needs no ground truth. Which
starts and which rule are themselves choices made on the development
photos, so their figures there are optimistic; this script measures how
they hold on photos they were not chosen on.

Per photo, every candidate start's GrabCut mask is computed once, as the
automatic search computes it (the same working copy and inset frame, the
largest part, holes filled, brought back to the photo's size), and its IoU
against the true mask, colour error and fill of the frame are cached under
``--cache`` (default ``/tmp/cv_auto_cache``, one ``.npz`` per photo; a
start not yet cached is computed and added), so that every rule is then
evaluated in seconds. A *rule* is a set of starts, the one of the lowest
colour error kept (:func:`~attneave.stimuli.extraction.figure_ground.boxcut.choose_hypothesis`
without the gap penalty). The rules tried (:func:`candidate_rules`, the
simplest first): GrabCut in CIE Lab from the central ellipse of the frame
alone, at each size of :data:`CORES` and box mode's 0.7; the five starts the
automatic search had before (:data:`FIVE`); and those five with one Lab
ellipse added (the automatic search now: ``five+lab_core40``). Each rule
is scored on one half of the photos (``A``/``B`` as ``validate_photos.py``
makes them: alternate photos of each group in name order) by the smaller
of the two groups' median IoU less its target (0.72 horses, 0.60 objects),
so that neither group is given up for the other; the best rule on one half
(the simplest among equals) is reported with its median IoU per group on
the other half, and vice versa; the rule chosen on all photos is the
automatic search's default. The table before it gives every rule's medians
on both halves.

IoU here is the mask's (GrabCut's pixels), not the traced outline's as in
``validate_photos.py``; for the default the medians differ by at most 0.004.

With ``--subsets`` the rules are every subset of the five starts, with or
without one Lab ellipse (191 rules; the per-rule table is then left out).

Usage: python benchmarks/cv_auto.py [DATA_DIR] [--cache DIR] [--limit K] [--progress] [--subsets]
"""

from __future__ import annotations

import argparse
import itertools
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from validate_photos import DEFAULT_DIR, group_of, halves, photos_to_measure  # noqa: E402

from _machine import header  # noqa: E402

#: The targets per group (median IoU on each held-out half).
TARGETS = {"weizmann": 0.72, "gsc": 0.60}


#: The automatic search's five starts before the small central one (box mode's four and CIE Lab on
#: the smoothed photo), the fallback (taken when no start found a boundary) first.
FIVE = ("lab_smooth", "lab_band", "rgb_box", "lab_core", "rgb_core")
#: Sizes of the central ellipse tried for a start in CIE Lab (its axes as a fraction of the inset
#: frame's): 'lab_coreNN'; 'lab_core' is box mode's (0.7).
CORES = (20, 30, 40, 50, 60)
STARTS = FIVE + tuple(f"lab_core{c}" for c in CORES)


def start_labels(name, small, inset):
    """One start on the working copy (8-bit BGR) from the inset frame: (3-channel image, GrabCut labels)."""
    import cv2

    from attneave.stimuli.extraction.figure_ground.boxcut import BOX_BAND, CORE
    from attneave.stimuli.extraction.figure_ground.grabcut import box_labels, core_labels

    space, start = name.split("_")
    if space == "lab" and start == "smooth":
        return cv2.cvtColor(cv2.bilateralFilter(small, 7, 40, 5), cv2.COLOR_BGR2LAB), box_labels(small.shape, inset)
    img = small if space == "rgb" else cv2.cvtColor(small, cv2.COLOR_BGR2LAB)
    if start == "box":
        return img, box_labels(small.shape, inset)
    if start == "band":
        return img, box_labels(small.shape, inset, BOX_BAND)
    core = CORE if start == "core" else int(start[4:]) / 100
    return img, core_labels(small.shape, inset, core)


def photo_cache(path, cache_dir, starts=STARTS):
    """Measures of each start's mask on one photo, name -> (iou, colour_error, fill); the starts not yet in
    the photo's cache file are computed and added."""
    import cv2

    from attneave.stimuli.extraction import read_image
    from attneave.stimuli.extraction.figure_ground.grabcut import fill_holes, grabcut, inset_box, largest_part, to_bgr8
    from attneave.stimuli.extraction.figure_ground.photo import WORK_PIXELS
    from attneave.stimuli.extraction.quality import colour_error

    p = Path(path)
    out = Path(cache_dir) / f"{p.stem}.npz"
    have = {}
    if out.is_file():
        with np.load(out) as z:
            have = {k: z[k] for k in z.files}
    todo = [k for k in starts if k not in have]
    if todo:
        rgb = read_image(p)
        truth = cv2.imread(str(p.with_name(f"{p.stem}.mask.png")), cv2.IMREAD_GRAYSCALE) > 127
        bgr = to_bgr8(rgb)
        h, w = bgr.shape[:2]
        # the working copy and frame of segment_photo's automatic search
        scale = min(1.0, float(np.sqrt(WORK_PIXELS / (h * w))))
        small = bgr if scale == 1.0 else cv2.resize(bgr, (max(2, round(w * scale)), max(2, round(h * scale))),
                                                    interpolation=cv2.INTER_AREA)
        inset = inset_box(small.shape)
        _, _, bw, bh = inset

        def run(name):
            img, labels = start_labels(name, small, inset)
            m = fill_holes(largest_part(grabcut(img, labels=labels)))
            big = m if scale == 1.0 else cv2.resize(m.astype(np.float32), (w, h), interpolation=cv2.INTER_LINEAR) > 0.5
            union = np.count_nonzero(big | truth)
            fill = m.sum() / (bw * bh)
            # hypothesis_score(gap=False): no boundary found outside these fills
            err = colour_error(small[:, :, ::-1], m) if 0.03 <= fill <= 0.97 else np.nan
            return np.array([np.count_nonzero(big & truth) / union if union else 1.0, err, fill])

        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(2) as pool:  # OpenCV releases the GIL
            have.update(zip(todo, pool.map(run, todo)))
        Path(cache_dir).mkdir(parents=True, exist_ok=True)
        tmp = out.with_suffix(".part.npz")
        np.savez_compressed(tmp, **have)
        os.replace(tmp, out)
    return {k: have[k] for k in starts}


def table(photos, cache_dir, progress=False):
    """One row per photo and start: image, group, half, start, iou, colour_error, fill."""
    import pandas as pd

    half = halves([p.name for p in photos])
    rows = []
    for p in photos:
        t0 = time.perf_counter()
        for k, (iou, err, fill) in photo_cache(p, cache_dir).items():
            rows.append(dict(image=p.name, group=group_of(p.name), half=half[p.name], start=k, iou=iou,
                             colour_error=err, fill=fill))
        if progress:
            print(f"{p.name}: {time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)
    return pd.DataFrame(rows)


def choose(photo, starts):
    """The row of the start a rule keeps on one photo (rows of :func:`table`): the lowest colour error among
    `starts` (those that found a boundary), as the automatic search chooses; the first when none did."""
    g = photo.set_index("start").loc[list(starts)]
    fits = g[np.isfinite(g.colour_error)]
    return g.iloc[0] if fits.empty else fits.loc[fits.colour_error.idxmin()]


def candidate_rules(subsets=False):
    """Name -> starts of the rules tried, the simplest first (a tie goes to the earlier): each Lab core
    alone, the five starts of before, and those with each Lab core added; with `subsets`, every subset
    of the five with or without one Lab core instead (fewer starts first)."""
    cores = tuple(f"lab_core{c}" for c in CORES)
    if subsets:
        sets = (sub + core for r in range(len(FIVE) + 1) for core in [()] + [(k,) for k in cores]
                for sub in itertools.combinations(FIVE, r))
        return {"+".join(s): s for s in sets if s}
    rules = {k: (k,) for k in ("lab_core",) + cores}
    rules["five"] = FIVE
    rules.update({f"five+{k}": FIVE + (k,) for k in cores})
    return rules


def evaluate(df, rules):
    """IoU of each rule's choice per photo (photo rows, rule columns), and each photo's group and half."""
    import pandas as pd

    out = {image: {name: choose(photo, starts).iou for name, starts in rules.items()}
           for image, photo in df.groupby("image", sort=True)}
    res = pd.DataFrame.from_dict(out, orient="index")[list(rules)]
    first = df.drop_duplicates("image").set_index("image")
    return res, first.group.loc[res.index], first.half.loc[res.index]


def margin(res, group, rows):
    """Per rule, the smaller over the groups of (median IoU - target) on `rows`."""
    import pandas as pd

    return pd.concat([res[rows & (group == g)].median() - t for g, t in TARGETS.items()], axis=1).min(axis=1)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data", nargs="?", default=str(DEFAULT_DIR))
    ap.add_argument("--cache", default="/tmp/cv_auto_cache")
    ap.add_argument("--limit", type=int, default=None)
    ap.add_argument("--progress", action="store_true", help="one line per photo on stderr")
    ap.add_argument("--subsets", action="store_true",
                    help="rules: every subset of the five starts, with or without one Lab core (191 rules)")
    args = ap.parse_args(argv)
    header("cv_auto: the automatic search's rules chosen on one half, measured on the other")
    photos = photos_to_measure("cv_auto", args.data, args.limit)
    if photos is None:
        return 2
    df = table(photos, args.cache, args.progress)
    rules = candidate_rules(args.subsets)
    res, group, half = evaluate(df, rules)
    best = df.groupby("image").iou.max()
    print(f"{len(res)} photos, {len(rules)} rules; best start per photo (chosen with the truth), median IoU: "
          + ", ".join(f"{g} {best[group == g].median():.3f}" for g in TARGETS))

    def medians(rule, h):
        return "  ".join(f"{g} {res.loc[(half == h) & (group == g), rule].median():.3f}" for g in TARGETS)

    if not args.subsets:
        print(f"\nmedian IoU per rule and half\n{'rule':24s} {'half A':>24s}   {'half B':>24s}")
        for rule in rules:
            print(f"{rule:24s} {medians(rule, 'A')}   {medians(rule, 'B')}")
    print("\ncross-validated (the rule of the largest margin over the targets on one half, measured on the other):")
    for tune, check in (("A", "B"), ("B", "A")):
        m = margin(res, group, half == tune)
        chosen = m.index[int(np.argmax(m.to_numpy()))]  # the first of the largest: the simplest
        print(f"chosen on {tune}: {chosen} (margin {m[chosen]:+.3f}); held-out half {check}: {medians(chosen, check)}")
    m = margin(res, group, half.notna())
    chosen = m.index[int(np.argmax(m.to_numpy()))]
    print(f"chosen on both halves: {chosen} (margin {m[chosen]:+.3f}); all photos, median / mean / share < 0.5: "
          + "  ".join(f"{g} {res.loc[group == g, chosen].median():.3f} / {res.loc[group == g, chosen].mean():.3f} / "
                      f"{(res.loc[group == g, chosen] < 0.5).mean():.2f}" for g in TARGETS))
    return 0


if __name__ == "__main__":
    sys.exit(main())
