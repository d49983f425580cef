"""Reading (and writing by hand) a stimulus-set directory.

A stimulus set is a directory in the format of DESIGN.md ("Files"), whether
``attneave generate`` wrote it or a person built it by hand:

``manifest.csv``
    One row per stimulus. Required by analysis: ``stimulus_id``
    (``[A-Za-z0-9_.-]+``, unique), ``contour`` (path relative to the
    directory), ``width`` and ``height`` (image size in pixels, > 0).
    Optional: ``image`` (path relative to the directory), ``generator``,
    ``seed``, ``params``, ``condition``, ``parent_id`` and anything else; they
    are kept in :attr:`StimulusSet.manifest`.
``contours/<stimulus_id>.csv``
    Columns ``x, y`` in image pixels (x = column, y = row, y down, pixel
    centres at integer coordinates), in order, closed, first point not
    repeated.
``images/<stimulus_id>.png``
    Optional for analysis. The image file need not exist: analysis works on
    the contour and on the ``width``/``height`` of the manifest alone, and a
    figure draws the image behind the contour only when the file is there.
    This lets people analyse clicks on stimuli whose images they keep
    elsewhere.

Every contour is read as closed (stimuli are silhouettes); it is stored
counter-clockwise on the screen by :class:`stimuli.contour.Contour`, so the
arc position ``t`` of analysis runs counter-clockwise from the first point of
the file.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from stimuli.geometry.contour import Contour
from stimuli.errors import InputError

from stimuli.io import describe_columns, read_text_csv

__all__ = ["StimulusSet", "read_stimulus_set", "write_stimulus_set", "ID_PATTERN", "REQUIRED_COLUMNS"]

ID_PATTERN = re.compile(r"^[A-Za-z0-9_.-]+$")
REQUIRED_COLUMNS = ("stimulus_id", "contour", "width", "height")


@dataclass
class StimulusSet:
    """Stimuli of one set: contours, image sizes and the manifest.

    Attributes
    ----------
    directory : Path
        The set's directory.
    manifest : pandas.DataFrame
        The manifest as read (strings), one row per stimulus, in file order.
    ids : list of str
        Stimulus ids in manifest order.
    contours : dict of str -> Contour
        Closed contours in image pixels (y down), counter-clockwise on screen.
    sizes : dict of str -> (int, int)
        ``(width, height)`` of each image in pixels.
    images : dict of str -> Path or None
        The image file when the manifest names one that exists, else None.
    """

    directory: Path
    manifest: object
    ids: list
    contours: dict
    sizes: dict
    images: dict = field(default_factory=dict)

    def __len__(self):
        return len(self.ids)

    def __contains__(self, stimulus_id):
        return stimulus_id in self.contours


def _positive_size(value, where, name):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{where}: column {name!r} must be a positive number of pixels, got {value!r}") from None
    if not (np.isfinite(v) and v > 0 and v == int(v)):
        raise InputError(f"{where}: column {name!r} must be a positive whole number of pixels, got {value!r}")
    return int(v)


def read_stimulus_set(directory):
    """Read a stimulus-set directory (see the module docstring for the format).

    Parameters
    ----------
    directory : str or Path
        Directory holding ``manifest.csv``.

    Returns
    -------
    StimulusSet

    Raises
    ------
    InputError
        One line naming the file and line: no manifest, a missing column, a
        bad or duplicated id, a non-positive size, a missing or unreadable
        contour file, or a contour with fewer than 3 distinct points.

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> th = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    >>> d = tempfile.mkdtemp()
    >>> _ = write_stimulus_set(d, {"disc": np.c_[50 + 20 * np.cos(th), 50 + 20 * np.sin(th)]}, size=(100, 100))
    >>> s = read_stimulus_set(d)
    >>> s.ids, s.sizes["disc"]
    (['disc'], (100, 100))
    """

    directory = Path(directory)
    mpath = directory / "manifest.csv"
    if not directory.is_dir():
        raise InputError(f"{directory}: not a directory (a stimulus set needs manifest.csv and contours/)")
    if not mpath.is_file():
        raise InputError(f"{mpath}: no such file (a stimulus set needs a manifest.csv)")
    manifest, lines = read_text_csv(mpath, what="a manifest", empty=f"expected a header with {', '.join(REQUIRED_COLUMNS)}")
    missing = [c for c in REQUIRED_COLUMNS if c not in manifest.columns]
    if missing:
        raise InputError(f"{mpath}: missing column(s) {', '.join(missing)}; {describe_columns(manifest.columns)}")
    if len(manifest) == 0:
        raise InputError(f"{mpath}: no stimuli (the manifest has no rows)")
    ids, contours, sizes, images = [], {}, {}, {}
    for i, row in enumerate(manifest.itertuples(index=False)):
        where = f"{mpath}: line {lines[i]}"
        sid = str(row.stimulus_id).strip()
        if not ID_PATTERN.match(sid):
            raise InputError(f"{where}: stimulus_id must match [A-Za-z0-9_.-]+, got {sid!r}")
        if sid in contours:
            raise InputError(f"{where}: stimulus_id {sid!r} appears twice")
        w = _positive_size(row.width, where, "width")
        h = _positive_size(row.height, where, "height")
        rel = str(row.contour).strip()
        if not rel:
            raise InputError(f"{where}: column 'contour' is empty (expected a path like contours/{sid}.csv)")
        cpath = directory / rel
        if not cpath.is_file():
            raise InputError(f"{where}: contour file {rel!r} not found in {directory}")
        contours[sid] = Contour.from_csv(cpath, closed=True)
        sizes[sid] = (w, h)
        image = None
        if "image" in manifest.columns and str(getattr(row, "image")).strip():
            ipath = directory / str(getattr(row, "image")).strip()
            image = ipath if ipath.is_file() else None
        images[sid] = image
        ids.append(sid)
    manifest = manifest.assign(stimulus_id=ids)
    return StimulusSet(directory, manifest, ids, contours, sizes, images)


def write_stimulus_set(directory, contours, size=(512, 512), generator="by_hand", condition="", params=None):
    """Write a minimal stimulus set (manifest and contour files, no images).

    For people who build a set by hand and for tests. Every file is written
    atomically; existing files of the same names are replaced.

    Parameters
    ----------
    directory : str or Path
        Created if needed.
    contours : dict of str -> (N, 2) array_like or Contour
        Closed contours in image pixels (x = column, y = row, y down).
    size : (int, int) or dict of str -> (int, int)
        ``(width, height)`` for all stimuli or per stimulus.
    generator, condition : str or dict of str -> str
        Recorded in the manifest.
    params : dict of str -> dict, optional
        JSON-serialisable parameters per stimulus.

    Returns
    -------
    Path
        The manifest file.
    """
    from stimuli.io import write_table

    directory = Path(directory)
    (directory / "contours").mkdir(parents=True, exist_ok=True)
    rows = []
    for sid, pts in contours.items():
        if not ID_PATTERN.match(sid):
            raise InputError(f"stimulus_id must match [A-Za-z0-9_.-]+, got {sid!r}")
        c = pts if isinstance(pts, Contour) else Contour(pts)
        rel = f"contours/{sid}.csv"
        c.to_csv(directory / rel)
        w, h = size[sid] if isinstance(size, dict) else size
        rows.append(
            dict(
                stimulus_id=sid,
                image=f"images/{sid}.png",
                contour=rel,
                width=int(w),
                height=int(h),
                generator=generator[sid] if isinstance(generator, dict) else generator,
                seed="",
                params=json.dumps((params or {}).get(sid, {}), sort_keys=True),
                condition=condition[sid] if isinstance(condition, dict) else condition,
                parent_id="",
            )
        )
    path = directory / "manifest.csv"
    write_table(rows and {k: [r[k] for r in rows] for k in rows[0]}, path, float_format="%.17g")
    return path
