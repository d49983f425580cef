"""Reading (and writing by hand) a stimulus-set directory.

A stimulus set is a directory in the format of docs/design.md ("Files"), whether
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
counter-clockwise on the screen by :class:`attneave.stimuli.geometry.contour.Contour`, so the
arc position ``t`` of analysis runs counter-clockwise from the first point of
the file.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.tables import describe_columns, read_text_csv

__all__ = [
    "StimulusSet", "read_stimulus_set", "write_stimulus_set", "ID_PATTERN", "REQUIRED_COLUMNS",
    "MANIFEST_COLUMNS", "FILE_COLUMNS", "to_jsonable", "encode_json", "write_manifest", "read_manifest_rows",
    "image_size", "check_image_size", "check_contour_in_image",
]

ID_PATTERN = re.compile(r"^[A-Za-z0-9_.-]+$")
REQUIRED_COLUMNS = ("stimulus_id", "contour", "width", "height")
# every column a manifest written by this package may have, in their order
MANIFEST_COLUMNS = (
    "stimulus_id", "image", "contour", "svg", "width", "height", "generator", "seed", "params",
    "condition", "parent_id", "batch_condition", "cell", "rep", "style", "warning",
)
# the columns that name files, relative to the set's directory
FILE_COLUMNS = ("image", "contour", "svg")


def to_jsonable(obj):
    """Plain JSON types, the same whatever produced the values.

    numpy scalars and arrays become Python numbers and lists, tuples lists,
    paths and other objects strings; NaN and infinities become ``None``
    (JSON ``null``): strict JSON has no NaN, and a missing value is what they
    mean in a record.

    Examples
    --------
    >>> import numpy as np
    >>> to_jsonable({"a": np.float32(0.5), "b": (1, np.nan), "c": np.arange(2)})
    {'a': 0.5, 'b': [1, None], 'c': [0, 1]}
    """
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if obj is None or isinstance(obj, str):
        return obj
    return str(obj)


def encode_json(obj):
    """Deterministic compact JSON of a manifest cell (``params``, ``style``).

    Examples
    --------
    >>> encode_json({"b": [1, 2.5], "a": float("nan")})
    '{"a":null,"b":[1,2.5]}'
    """
    return json.dumps(to_jsonable(obj), sort_keys=True, separators=(",", ":"), allow_nan=False)


def write_manifest(path, rows):
    """Write ``manifest.csv`` atomically (fsync'd: it marks a set complete).

    Parameters
    ----------
    path : str or Path
    rows : list of dict
        One per stimulus, values already strings or numbers. The columns are
        those of `MANIFEST_COLUMNS` that some row has, in that order, then any
        other keys in order of appearance.
    """
    from attneave.stimuli.io import atomic_write

    keys = dict.fromkeys(k for r in rows for k in r)
    cols = [c for c in MANIFEST_COLUMNS if c in keys] + [k for k in keys if k not in MANIFEST_COLUMNS]
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n", restval="")
    w.writeheader()
    w.writerows(rows)
    with atomic_write(path, "w", fsync=True, encoding="utf-8", newline="") as fh:
        fh.write(buf.getvalue())


def read_manifest_rows(path):
    """The rows of a manifest as dicts of strings, or ``[]`` if it cannot be read.

    For resuming a batch (a damaged manifest is remade, not an error); analysis
    reads a set with :func:`read_stimulus_set`, which checks everything.
    """
    try:
        with open(path, encoding="utf-8", newline="") as fh:
            rows = [{k: v for k, v in row.items() if k in MANIFEST_COLUMNS} for row in csv.DictReader(fh)]
    except (OSError, csv.Error, UnicodeDecodeError):
        return []
    for row in rows:  # write_manifest leaves a cell empty where a row has no value: no empty warning
        if not row.get("warning"):
            row.pop("warning", None)
    return rows


def inside(directory, rel, where, column, root=None):
    """`directory / rel`, refused when it leads outside `directory`.

    Absolute paths, ``..`` steps that climb out and symbolic links that
    resolve outside are refused: a hand-built manifest must not make
    analysis read (or echo) files elsewhere. `root`, the resolved
    `directory`, may be given by a caller that checks many paths (resolving
    it is most of the cost of a check).

    Raises
    ------
    InputError
        Naming `where` (file and line) and the `column`.
    """
    if os.path.isabs(rel) or re.match(r"^[A-Za-z]:", rel):
        raise InputError(f"{where}: column {column!r} must be a path relative to the set's directory, got {rel!r}")
    root = os.path.realpath(directory) if root is None else root
    full = os.path.realpath(os.path.join(root, rel))
    if full != root and not full.startswith(root.rstrip(os.sep) + os.sep):
        raise InputError(f"{where}: column {column!r} leads outside the set's directory: {rel!r}")
    return Path(directory) / rel


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
    warnings : list of str
        What reading found doubtful but not broken (a contour partly outside
        its image), one sentence each, for the outputs of the commands.
    """

    directory: Path
    manifest: object
    ids: list
    contours: dict
    sizes: dict
    images: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)

    def __len__(self):
        return len(self.ids)

    def __contains__(self, stimulus_id):
        return stimulus_id in self.contours

    def files(self):
        """Every file of the set that exists: manifest, ``config.yaml`` and the files the manifest names.

        For commands that write a file: none of these may be an output
        (:func:`attneave.stimuli.io.check_output_spares_inputs`).

        Returns
        -------
        list of Path
        """
        d = Path(self.directory)
        out = [d / "manifest.csv", d / "config.yaml"]
        for col in FILE_COLUMNS:
            if col in self.manifest.columns:
                out += [d / str(v).strip() for v in self.manifest[col] if str(v).strip()]
        return [p for p in dict.fromkeys(out) if p.is_file()]


def _positive_size(value, where, name):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{where}: column {name!r} must be a positive number of pixels, got {value!r}") from None
    if not (np.isfinite(v) and v > 0 and v == int(v)):
        raise InputError(f"{where}: column {name!r} must be a positive whole number of pixels, got {value!r}")
    return int(v)


def image_size(path):
    """``(width, height)`` in pixels of an image file from its header, or None if it cannot be read.

    Only the header is read (Pillow opens images lazily), so checking a
    large set costs little; a file Pillow does not know (e.g. SVG) or a
    damaged one gives None: analysis does not need the image itself.
    """
    import warnings

    try:
        from PIL import Image

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with Image.open(path) as im:
                return tuple(int(v) for v in im.size)
    except Exception:  # not an image Pillow reads (SVG, text, truncated header): nothing to compare
        return None


def check_image_size(path, width, height, where):
    """Raise `InputError` when the image at `path` is not `width` x `height` pixels.

    Clicks are converted with the manifest's width and height, and a page or
    a PsychoPy script shows the image at its own size: the two must agree.
    An image whose header cannot be read is not checked (see :func:`image_size`).

    Parameters
    ----------
    path : str or Path
        The image file.
    width, height : int
        The size in pixels the manifest gives.
    where : str
        Names the manifest row in the message (e.g. ``manifest.csv line 3``).

    Raises
    ------
    InputError
        The image's header gives another size.
    """
    size = image_size(path)
    if size is not None and size != (width, height):
        raise InputError(f"{where}: image {Path(path).name} is {size[0]} x {size[1]} px but the manifest says "
                         f"{width} x {height}")


def check_contour_in_image(contour, width, height, where):
    """Check that a closed contour is simple and lies in its ``width`` x ``height`` image.

    The image covers ``[-0.5, width - 0.5] x [-0.5, height - 0.5]`` (pixel
    centres at integer coordinates).

    Parameters
    ----------
    contour : Contour
        Closed, ``(x, y)`` image pixels (x = column, y = row, y down).
    width, height : int
        The image's size in pixels.
    where : str
        Names the contour in messages (e.g. its file and manifest line).

    Returns
    -------
    str or None
        A warning when part of the contour lies outside the image (clicks
        cannot reach it), else None.

    Raises
    ------
    InputError
        The contour crosses or touches itself (its inside, and so concavity,
        is undefined), lies wholly outside the image, or reaches farther
        outside it than the image's larger side (wrong units, or width and
        height of another image).
    """
    import shapely

    if not contour.is_simple():
        x, y = contour.self_intersections()[0]
        raise InputError(f"{where}: the contour crosses itself near (x={x:.3f}, y={y:.3f}); a simple closed "
                         "curve is needed")
    p = contour.points
    lo, hi = np.array([-0.5, -0.5]), np.array([width - 0.5, height - 0.5])
    ring = shapely.LineString(np.vstack([p, p[:1]]))
    if not ring.intersects(shapely.box(*lo, *hi)):
        x0, y0 = p.min(axis=0)
        x1, y1 = p.max(axis=0)
        raise InputError(f"{where}: the contour (x {x0:.4g} to {x1:.4g}, y {y0:.4g} to {y1:.4g}) lies wholly "
                         f"outside its {width} x {height} image")
    beyond = np.maximum(lo - p, p - hi).max(axis=1)  # how far each point lies outside the image (px)
    far = int(np.argmax(beyond))
    if beyond[far] > max(width, height):
        raise InputError(f"{where}: the contour reaches ({p[far, 0]:.4g}, {p[far, 1]:.4g}), "
                         f"{beyond[far]:.4g} px outside its {width} x {height} image; the contour must lie in "
                         "the image (check its units and the manifest's width and height)")
    if beyond[far] > 0:
        share = float(np.mean(beyond > 0))
        return (f"{where}: {100 * share:.3g}% of the contour's points lie outside its {width} x {height} image "
                f"(up to {beyond[far]:.3g} px); no click can land there")
    return None


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
        contour file, a contour with fewer than 3 distinct points, a contour
        that crosses itself, lies wholly outside its image or reaches farther
        outside it than the image's size (:func:`check_contour_in_image`),
        or an image file whose size differs from the manifest's
        (:func:`check_image_size`). A contour partly outside its image is
        kept, with a sentence in :attr:`StimulusSet.warnings`.

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
    ids, contours, sizes, images, warnings = [], {}, {}, {}, []
    root = os.path.realpath(directory)
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
        cpath = inside(directory, rel, where, "contour", root)
        if not cpath.is_file():
            raise InputError(f"{where}: contour file {rel!r} not found in {directory}")
        contours[sid] = Contour.from_csv(cpath, closed=True)
        warning = check_contour_in_image(contours[sid], w, h, f"{where} ({sid}, {rel})")
        if warning:
            warnings.append(warning)
        sizes[sid] = (w, h)
        image = None
        if "image" in manifest.columns and str(getattr(row, "image")).strip():
            ipath = inside(directory, str(getattr(row, "image")).strip(), where, "image", root)
            image = ipath if ipath.is_file() else None
            if image is not None:
                check_image_size(image, w, h, f"{where} ({sid})")
        images[sid] = image
        ids.append(sid)
    manifest = manifest.assign(stimulus_id=ids)
    return StimulusSet(directory, manifest, ids, contours, sizes, images, warnings)


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
                params=encode_json((params or {}).get(sid, {})),
                condition=condition[sid] if isinstance(condition, dict) else condition,
                parent_id="",
            )
        )
    path = directory / "manifest.csv"
    write_manifest(path, rows)
    return path
