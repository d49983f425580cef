"""Writing the experiment directory.

``DIR/index.html`` (the trial list and settings embedded as a JSON block, so
the page needs no request and runs from ``file://``), ``DIR/task.js``,
``DIR/task.css`` (the project's own, no CDN), ``DIR/images/<id>.<ext>`` (copies
of the set's images), ``DIR/experiment.json`` (what was built, from what; it
also marks the directory as one this module wrote) and, on request,
``DIR/psychopy/``.

The directory is built in a temporary directory beside it and renamed into
place, so it appears complete or not at all. An existing ``DIR`` is replaced
only when it is empty or holds exactly a previous experiment's files; any
other content is the user's, and is moved aside (never deleted) with
``force=True``.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
from collections import Counter
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

from attneave.analysis.experiment.options import ExperimentOptions
from attneave.analysis.experiment.order import latin_square_lists
from attneave.stimuli.errors import InputError
from attneave.stimuli.io import replace_directory, temporary_directory

__all__ = ["Stimulus", "select_stimuli", "background_colour", "page_config", "build_experiment", "MARKER", "embedded_json", "fill_template"]

#: File that marks a directory written by :func:`build_experiment`.
MARKER = "experiment.json"
_STATIC = ("task.js", "task.css")


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


def page_config(options, practice, main, background, version):
    """The settings and trial list the page reads (embedded in index.html as JSON).

    Parameters
    ----------
    options : ExperimentOptions
    practice, main : list of Stimulus
    background : str
        ``'#rrggbb'``.
    version : str

    Returns
    -------
    dict
        JSON-serialisable. ``scale.max_side`` is the larger side of the
        largest image: it is shown at ``size_deg`` degrees (or ``size_px`` CSS
        px) and every image at the same scale.
    """
    def entry(s):
        return dict(id=s.id, src=s.src, width=s.width, height=s.height, condition=s.condition,
                    parent_id=s.parent_id, lists=list(s.lists))

    every = practice + main
    o = options
    return dict(
        attneave_experiment=version,
        title=o.title,
        instructions=o.instructions,
        end_text=o.end_text,
        clicks=o.clicks,
        min_clicks=o.clicks if o.clicks != "done" else o.min_clicks,
        max_clicks=o.clicks if o.clicks != "done" else o.max_clicks,
        undo=o.undo,
        order=o.order,
        seed=o.seed,
        lists=o.lists,
        fixation_ms=o.fixation_ms,
        iti_ms=o.iti_ms,
        break_every=o.break_every,
        scale=dict(max_side=max(max(s.width, s.height) for s in every), size_deg=o.size_deg, size_px=o.size_px),
        px_per_deg=o.px_per_deg,
        viewing_distance_cm=o.viewing_distance_cm,
        background=background,
        submit_url=o.submit_url,
        practice=[entry(s) for s in practice],
        stimuli=[entry(s) for s in main],
    )


def _static(name):
    return resources.files("attneave.analysis.experiment").joinpath("static", name)


def render_index(config):
    """index.html with `config` embedded as a JSON script block.

    Every ``<``, ``>`` and ``&`` inside the JSON is written as a ``\\u`` escape
    (still the same JSON, as Django's ``json_script`` does): inside a script
    element the HTML tokenizer looks for ``</script`` and, after ``<!--``,
    for ``<script`` too, so a title or an instruction holding them could
    close or swallow the element and leave a blank page. The placeholders
    of the template are substituted in one pass, so a placeholder's name in
    the participant-facing text (``{{CONFIG}}`` in a title) stays text.

    Examples
    --------
    >>> "<" in embedded_json({"title": "<!--<script>"})
    False
    """
    import html

    template = _static("index.html").read_text(encoding="utf-8")
    return fill_template(template, {"{{TITLE}}": html.escape(config["title"]),
                                    "{{BACKGROUND}}": config["background"],
                                    "{{CONFIG}}": embedded_json(config)})


_HTML_UNSAFE = {"<": "\\u003c", ">": "\\u003e", "&": "\\u0026", "\u2028": "\\u2028", "\u2029": "\\u2029"}


def embedded_json(value):
    """`value` as JSON that is safe inside an HTML ``<script>`` element.

    Examples
    --------
    >>> embedded_json({"t": "a</script>&"})
    '{\\n "t": "a\\\\u003c/script\\\\u003e\\\\u0026"\\n}'
    """
    blob = json.dumps(value, indent=1, ensure_ascii=False, allow_nan=False)
    return re.sub("[<>&\u2028\u2029]", lambda m: _HTML_UNSAFE[m.group()], blob)


def fill_template(template, values):
    """`template` with each key of `values` replaced by its value, in one pass.

    A value is never searched for placeholders again, so user text holding
    a placeholder's name is kept as it is.

    Examples
    --------
    >>> fill_template("<b>{{A}}</b>{{B}}", {"{{A}}": "{{B}}", "{{B}}": "x"})
    '<b>{{B}}</b>x'
    """
    pattern = re.compile("|".join(re.escape(k) for k in sorted(values, key=len, reverse=True)))
    return pattern.sub(lambda m: values[m.group()], template)


def _listing(directory):
    return sorted(p.relative_to(directory).as_posix() for p in Path(directory).rglob("*") if p.is_file())


def _is_previous_experiment(out):
    """True when `out` holds exactly the files of an experiment this module wrote."""
    try:
        marker = json.loads((out / MARKER).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    if not isinstance(marker, dict) or "attneave_experiment" not in marker:
        return False
    return set(_listing(out)) <= set(marker.get("files", [])) | {MARKER}


def check_output(out, force=False):
    """What to do with an existing output directory: None (absent/empty/previous) or 'move-aside'.

    Raises
    ------
    InputError
        `out` is a file, or a non-empty directory that is not a previous
        experiment and `force` is not set.
    """
    out = Path(out)
    if not out.exists():
        return None
    if not out.is_dir():
        raise InputError(f"{out}: exists and is not a directory")
    if not any(out.iterdir()) or _is_previous_experiment(out):
        return None
    if not force:
        raise InputError(f"{out}: directory exists, is not empty and is not an experiment attneave wrote "
                         f"(or holds other files too); choose another -o or pass --force (which moves it aside)")
    return "move-aside"


def _check_parents(out):
    """InputError when a parent of `out` exists but is a file (the directory could never be made there)."""
    for parent in out.parents:
        if parent.exists() or parent.is_symlink():
            if not parent.is_dir():
                raise InputError(f"{out}: cannot be created: {parent} is a file, not a directory")
            return


def _aside_name(out):
    i = 1
    while True:
        cand = out.with_name(f"{out.name}.old-{i}")
        if not cand.exists():
            return cand
        i += 1


def build_experiment(stimset, out, options=None, psychopy=False, force=False):
    """Write the browser experiment for a stimulus set.

    Parameters
    ----------
    stimset : attneave.stimuli.stimulus_set.StimulusSet
    out : str or Path
        The experiment directory. Created; replaced when it is empty or a
        previous experiment; otherwise refused unless `force`, which renames
        it to ``<out>.old-N`` first (nothing is deleted).
    options : ExperimentOptions, optional
    psychopy : bool
        Also write ``out/psychopy/`` (see :mod:`attneave.analysis.experiment.psychopy`).
    force : bool

    Returns
    -------
    dict
        ``out`` (Path), ``moved_aside`` (Path or None), ``practice`` and
        ``stimuli`` (counts), ``lists``, ``background``, ``files``.

    Raises
    ------
    InputError
        Bad options for this set, missing images, an output that cannot be
        written; nothing is written then.

    References
    ----------
    .. [1] Attneave, F. (1954). Some informational aspects of visual
           perception. Psychological Review, 61(3), 183-193.
    .. [2] Norman, J. F., Phillips, F. & Ross, H. E. (2001). Information
           concentration along the boundary contours of naturally shaped
           solid objects. Perception, 30(11), 1285-1294.
    .. [3] De Winter, J. & Wagemans, J. (2008). Perceptual saliency of points
           along the contour of everyday objects: A large-scale study.
           Perception & Psychophysics, 70(1), 50-64.
    """
    from attneave.stimuli import __version__

    options = options or ExperimentOptions()
    out = Path(out)
    _check_parents(out)
    mpath = Path(stimset.directory) / "manifest.csv"
    # every check on the inputs happens before anything is written
    practice, main = select_stimuli(stimset, options)
    every = practice + main
    check_image_sizes(every, mpath)
    background = options.grey or background_colour([s.source for s in every])
    config = page_config(options, practice, main, background, __version__)
    if psychopy:
        from attneave.analysis.experiment.psychopy import conditions_rows

        conditions_rows(options, practice, main)  # its units' checks, before anything is written
    action = check_output(out, force)

    tmp = temporary_directory(out)
    try:
        (tmp / "images").mkdir()
        for s in every:
            shutil.copyfile(s.source, tmp / s.src)
        for name in _STATIC:
            (tmp / name).write_bytes(_static(name).read_bytes())
        (tmp / "index.html").write_text(render_index(config), encoding="utf-8")
        if psychopy:
            from attneave.analysis.experiment.psychopy import write_psychopy

            write_psychopy(tmp / "psychopy", options, practice, main, config)
        files = _listing(tmp)
        marker = dict(attneave_experiment=__version__, stimulus_set=str(stimset.directory),
                      practice=[s.id for s in practice], stimuli=[s.id for s in main], lists=options.lists,
                      background=background, options=options.model_dump(mode="json"), files=files + [MARKER])
        (tmp / MARKER).write_text(json.dumps(marker, indent=1) + "\n", encoding="utf-8")
        for p in [tmp, *tmp.rglob("*")]:
            # mkdtemp makes the directory private; a static host must be able to read it
            os.chmod(p, 0o755 if p.is_dir() else 0o644)
        moved = _swap_into_place(tmp, out, action)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return dict(out=out, moved_aside=moved, practice=len(practice), stimuli=len(main), lists=options.lists,
                background=background, files=files + [MARKER])


def _swap_into_place(tmp, out, action):
    """Rename `tmp` to `out`; an old `out` is removed (empty or ours) or moved aside (the user's)."""
    if not out.exists():
        os.replace(tmp, out)
        return None
    if action == "move-aside":
        aside = _aside_name(out)
        os.replace(out, aside)
        os.replace(tmp, out)
        return aside
    replace_directory(tmp, out)
    return None
