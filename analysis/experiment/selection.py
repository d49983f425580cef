"""Which stimuli the experiment shows, and checks that participants can see them.

The practice and main stimuli of a set with their counterbalanced lists
(:func:`select_stimuli`), every image decoded in full and its size checked
against the manifest (:func:`check_image_sizes`), and the page's background,
the images' ground (:func:`background_colour`). Used by the page
(:mod:`attneave.analysis.experiment.build`) and the PsychoPy export alike.
"""

from __future__ import annotations

import contextlib
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from attneave.analysis.experiment.options import DEFAULT_SIZE_DEG
from attneave.analysis.experiment.order import latin_square_lists
from attneave.stimuli.errors import InputError

__all__ = ["Stimulus", "select_stimuli", "check_image_sizes", "background_colour", "set_px_per_deg"]


@dataclass(frozen=True)
class Stimulus:
    """One stimulus as the experiment uses it.

    Attributes
    ----------
    id : str
    source : Path
        The set's image file.
    src : str
        Its copy, relative to the experiment directory (``images/<id>.png``).
    width, height : int
        Image size in pixels (the click coordinates' frame).
    condition, parent_id : str
        From the manifest ('' when absent).
    lists : tuple of int
        The participant lists (1-based) that see it.
    """

    id: str
    source: Path
    src: str
    width: int
    height: int
    condition: str = ""
    parent_id: str = ""
    lists: tuple = field(default=(1,))


def _column(manifest, name, i):
    if name not in manifest.columns:
        return ""
    v = manifest[name].iloc[i]
    return "" if v is None else str(v).strip()


def select_stimuli(stimset, options):
    """The practice and main stimuli of the experiment, with their lists.

    Parameters
    ----------
    stimset : attneave.stimuli.stimulus_set.StimulusSet
    options : ExperimentOptions

    Returns
    -------
    practice, main : list of Stimulus
        Manifest order. Practice stimuli are seen by every list.

    Raises
    ------
    InputError
        A stimulus without an image file, an image whose size differs from the
        manifest's, an unknown condition or practice id, no main trials left,
        or a set that cannot be split into `options.lists` lists.
    """
    manifest = stimset.manifest
    mpath = Path(stimset.directory) / "manifest.csv"
    rows = []
    for i, sid in enumerate(stimset.ids):
        rows.append(dict(id=sid, condition=_column(manifest, "condition", i),
                         parent_id=_column(manifest, "parent_id", i), index=i))
    if options.conditions is not None:
        known = list(dict.fromkeys(r["condition"] for r in rows))
        for j, c in enumerate(options.conditions):
            if c not in known:
                raise InputError(f"{options.origin('conditions')}[{j}]: no stimulus of {mpath} has condition {c!r}; "
                                 f"conditions there: {', '.join(map(repr, known))}")
        rows = [r for r in rows if r["condition"] in options.conditions]
    if isinstance(options.practice, int):
        if options.practice >= len(rows):
            raise InputError(f"{options.origin('practice')}: {options.practice} practice stimuli would leave no main trials "
                             f"({len(rows)} stimuli selected)")
        practice_ids = [r["id"] for r in rows[: options.practice]]
    else:
        practice_ids = list(options.practice)
        for j, sid in enumerate(practice_ids):
            if sid not in stimset:
                raise InputError(f"{options.origin('practice')}[{j}]: stimulus {sid!r} is not in {mpath}")
    by_id = {sid: dict(id=sid, condition=_column(manifest, "condition", i), parent_id=_column(manifest, "parent_id", i),
                       index=i) for i, sid in enumerate(stimset.ids)}
    main_rows = [r for r in rows if r["id"] not in set(practice_ids)]
    if not main_rows:
        raise InputError(f"{options.origin('practice')}: every selected stimulus is a practice stimulus; no main trials are left")
    # an item is a base shape and what derives from it: the rows sharing parent_id (or the base itself)
    lists = latin_square_lists([r["id"] for r in main_rows],
                               [r["parent_id"] or r["id"] for r in main_rows],
                               [r["condition"] for r in main_rows], options.lists)

    def make(r, ls):
        return _stimulus(stimset, mpath, r, ls)

    practice = [make(by_id[sid], tuple(range(1, options.lists + 1))) for sid in practice_ids]
    main = [make(r, tuple(lists[r["id"]])) for r in main_rows]
    return practice, main


def _stimulus(stimset, mpath, row, lists):
    sid = row["id"]
    where = f"{mpath}: line {row['index'] + 2} ({sid})"
    source = stimset.images.get(sid)
    if source is None:
        raise InputError(f"{where}: no image file (column 'image' must name an existing file; the experiment "
                         f"shows the images)")
    root = Path(stimset.directory).resolve()
    if root not in Path(source).resolve().parents:
        # a manifest path must not lead outside the set (docs/design.md, Files)
        raise InputError(f"{where}: image path leads outside the stimulus set {stimset.directory}")
    suffix = Path(source).suffix.lower()
    if suffix not in (".png", ".jpg", ".jpeg", ".gif", ".webp", ".svg"):
        raise InputError(f"{where}: image {Path(source).name!r} is not a format browsers show (png, jpg, gif, webp, svg)")
    w, h = stimset.sizes[sid]
    return Stimulus(sid, Path(source), f"images/{sid}{suffix}", w, h, row["condition"], row["parent_id"], lists)


def _read_rgba(path):
    """An image as 8-bit RGBA (H, W, 4), or None when cv2 cannot decode it (e.g. SVG)."""
    import cv2
    import numpy as np

    img = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if img is None:
        return None
    if img.dtype == np.uint16:
        img = np.round(img / 257.0).astype(np.uint8)
    elif img.dtype != np.uint8:
        return None
    if img.ndim == 2:
        img = np.dstack([img, img, img, np.full_like(img, 255)])
    elif img.shape[2] == 3:
        img = np.dstack([img[..., ::-1], np.full(img.shape[:2], 255, np.uint8)])
    else:
        img = img[..., [2, 1, 0, 3]]
    return img


def check_image_sizes(stimuli, mpath):
    """Raise InputError when an image cannot be shown or its pixel size differs from its manifest size.

    Every raster image is decoded in full (with Pillow, which reads every
    format browsers show but SVG): a file that is not an image, or whose
    data are truncated or corrupt, would show participants a broken image.
    Clicks are converted with the manifest's width and height (what
    ``analyze`` uses) and the page with the image's natural size; the two must
    agree.
    """
    for s in stimuli:
        if s.source.suffix.lower() == ".svg":
            continue
        w, h = _decoded_size(s, mpath)
        if (w, h) != (s.width, s.height):
            raise InputError(f"{mpath}: {s.id}: image {s.source.name} is {w} x {h} px but the manifest says "
                             f"{s.width} x {s.height}")


def _decoded_size(s, mpath):
    """(width, height) of a stimulus's image, decoded in full; InputError naming the file if it cannot be."""
    import warnings

    from PIL import Image, UnidentifiedImageError

    where = f"{mpath}: {s.id}: image {s.source}"
    try:
        with warnings.catch_warnings():
            # Pillow's DecompressionBombWarning is an error here: no stimulus image is that large
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            with Image.open(s.source) as im:
                im.load()  # the whole file: a truncated one raises here, not when the browser shows it
                return im.size
    except UnidentifiedImageError:
        with contextlib.suppress(OSError):
            if s.source.stat().st_size == 0:
                raise InputError(f"{where}: empty file; participants would see a broken image") from None
        raise InputError(f"{where}: not an image file (or a format Pillow cannot read); participants would "
                         "see a broken image") from None
    except (OSError, SyntaxError, ValueError, Image.DecompressionBombError, Image.DecompressionBombWarning) as exc:
        reason = " ".join(str(exc).split())[:200] or type(exc).__name__
        raise InputError(f"{where}: cannot be decoded ({reason}); participants would see a broken image") from None


def background_colour(paths):
    """The background colour of a set of images: the commonest opaque corner pixel.

    Stimuli are figures on a uniform ground, so the four corner pixels of
    every image show the ground; their mode is robust to a figure that
    touches a corner.

    Parameters
    ----------
    paths : sequence of Path
        Image files (those that cannot be decoded, e.g. SVG, are skipped).

    Returns
    -------
    str
        ``'#rrggbb'`` (sRGB, 8 bit; 16-bit images are rounded), or
        ``'#808080'`` when no opaque corner pixel was found (transparent
        images show the page's colour, so any grey matches them).
    """
    votes = Counter()
    for p in paths:
        img = _read_rgba(p)
        if img is None:
            continue
        for y, x in ((0, 0), (0, -1), (-1, 0), (-1, -1)):
            r, g, b, a = (int(v) for v in img[y, x])
            if a == 255:
                votes[(r, g, b)] += 1
    if not votes:
        return "#808080"
    r, g, b = votes.most_common(1)[0][0]
    return f"#{r:02x}{g:02x}{b:02x}"


def set_px_per_deg(stimset, stimuli):
    """The image pixels per degree the set was made at (its canvas in degrees), or None.

    A batch config may give the canvas in degrees of visual angle
    (:func:`attneave.stimuli.batch.placement.canvas_in_pixels`); the set's
    resolved ``config.yaml`` then holds ``px_per_deg`` for the top-level
    canvas and each condition's. The stimuli's conditions are those of the
    manifest's column ``batch_condition``.

    Returns
    -------
    float or None
        The scale shared by every stimulus of `stimuli`; None when the set
        has no degrees, or its stimuli were made at different scales (they
        cannot be shown at one scale, each at its degrees; a line on stderr
        says so).
    """
    import sys

    from attneave.stimuli.batch.config_file import parse_yaml, read_text

    path = Path(stimset.directory) / "config.yaml"
    if not path.is_file() or "batch_condition" not in stimset.manifest.columns:
        return None
    try:
        _, doc = parse_yaml(read_text(path), path)
    except InputError:
        return None  # not a resolved batch config: the set says nothing about degrees
    if not isinstance(doc, dict):
        return None
    top = (doc.get("canvas") or {}).get("px_per_deg")
    by_condition = {}
    for c in doc.get("conditions") or []:
        if isinstance(c, dict):
            by_condition[str(c.get("name"))] = (c.get("canvas") or {}).get("px_per_deg", top)
    index = {sid: i for i, sid in enumerate(stimset.ids)}
    scales = {by_condition.get(_column(stimset.manifest, "batch_condition", index[s.id]), top) for s in stimuli}
    if scales == {None}:
        return None
    if len(scales) > 1:
        print(f"attneave experiment: {path}: the stimuli were made at different scales "
              f"({', '.join(str(v) for v in sorted(scales, key=str))} px/deg) and are shown at one; "
              f"the size is size_deg's (default {DEFAULT_SIZE_DEG:g} deg), not the canvas's degrees", file=sys.stderr)
        return None
    return float(next(iter(scales)))
