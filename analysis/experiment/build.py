"""Writing the experiment directory.

``DIR/index.html`` (the trial list and settings embedded as a JSON block, so
the page needs no request and runs from ``file://``), ``DIR/task.js``,
``DIR/task.css`` (the project's own, no CDN), ``DIR/images/<id>.<ext>`` (copies
of the set's images), ``DIR/experiment.json`` (what was built, from what; it
also marks the directory as one this module wrote) and, on request,
``DIR/jspsych.html`` with the jsPsych plugin (:mod:`~attneave.analysis.experiment.pages`),
``DIR/psychopy/`` (:mod:`~attneave.analysis.experiment.psychopy`) and a JATOS
study archive ``DIR/<study>.jzip`` (:mod:`~attneave.analysis.experiment.jatos`).
Which stimuli, and the checks of their images, are in
:mod:`~attneave.analysis.experiment.selection`.

The directory is built in a temporary directory beside it and renamed into
place, so it appears complete or not at all. An existing ``DIR`` is replaced
only when it is empty or holds exactly a previous experiment's files; any
other content is the user's, and is moved aside (never deleted) with
``force=True``.
"""

from __future__ import annotations

import json
import os
import shutil
import sys
from pathlib import Path

from attneave.analysis.experiment import jatos as jatos_archive
from attneave.analysis.experiment.options import ExperimentOptions
from attneave.analysis.experiment.pages import embedded_json, fill_template, page_config, write_pages
from attneave.analysis.experiment.selection import (
    Stimulus,
    background_colour,
    check_image_sizes,
    select_stimuli,
    set_px_per_deg,
)
from attneave.stimuli.errors import InputError
from attneave.stimuli.io import replace_directory, temporary_directory

# the names other modules and tests took from here before the split stay importable from here
__all__ = ["Stimulus", "select_stimuli", "background_colour", "page_config", "build_experiment", "MARKER",
           "embedded_json", "fill_template", "check_output"]

#: File that marks a directory written by :func:`build_experiment`.
MARKER = "experiment.json"


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


def build_experiment(stimset, out, options=None, psychopy=False, force=False, jspsych=False, jatos=False):
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
    jspsych : bool
        Also write ``out/jspsych.html``, the task as a jsPsych 8 timeline of
        the plugin ``attneave-points`` (``plugin-attneave-points.js``),
        loading jsPsych from ``options.jspsych_path``.
    jatos : bool
        The pages submit through JATOS's ``jatos.js`` instead of offering a
        download, and ``out/<study>.jzip`` is written, a study archive JATOS
        imports (its component: ``jspsych.html`` with `jspsych`, else
        ``index.html``).

    Returns
    -------
    dict
        ``out`` (Path), ``moved_aside`` (Path or None), ``practice`` and
        ``stimuli`` (counts), ``lists``, ``background``, ``files``, ``pages``,
        ``jzip`` (the archive's name, or None).

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
    options = _set_degrees(stimset, options, every)
    background = options.grey or background_colour([s.source for s in every])
    config = page_config(options, practice, main, background, __version__, jatos=jatos)
    if psychopy:
        from attneave.analysis.experiment.psychopy import conditions_rows

        conditions_rows(options, practice, main)  # its units' checks, before anything is written
    action = check_output(out, force)

    tmp = temporary_directory(out)
    try:
        (tmp / "images").mkdir()
        for s in every:
            shutil.copyfile(s.source, tmp / s.src)
        pages = write_pages(tmp, config, options.jspsych_path if jspsych else None)
        if psychopy:
            from attneave.analysis.experiment.psychopy import write_psychopy

            write_psychopy(tmp / "psychopy", options, practice, main, config)
        jzip = None
        if jatos:
            jzip = _write_jzip(tmp, out, options, pages[-1])
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
                background=background, files=files + [MARKER], pages=pages, jzip=jzip)


def _set_degrees(stimset, options, stimuli):
    """`options` with size_deg from the set's canvas in degrees, when no size was given.

    A set made in degrees (``px_per_deg`` image px per degree) is shown at
    those degrees: the largest image's larger side at ``max_side / px_per_deg``.
    """
    if options.size_given:
        return options
    ppd = set_px_per_deg(stimset, stimuli)
    if ppd is None:
        return options
    max_side = max(max(s.width, s.height) for s in stimuli)
    return options.model_copy(update={"size_deg": max_side / ppd})


def _write_jzip(tmp, out, options, page):
    """Write the JATOS study archive of the files in `tmp` (the experiment being built); its name."""
    name = jatos_archive.study_dir_name(out)
    assets = _listing(tmp)
    if page == "jspsych.html" and "://" not in options.jspsych_path and not (tmp / options.jspsych_path).is_dir():
        # jsPsych is the lab's, never shipped: without it in the study's assets the page stops with a message
        print(f"attneave experiment: the JATOS study's page loads jsPsych from {options.jspsych_path}jspsych.js: "
              f"add that folder to the study's assets in JATOS (or give --jspsych-path an http(s) URL)",
              file=sys.stderr)
    props = jatos_archive.study_properties(name, options.title, page, {"completion_url": options.completion_url},
                                           description="A point-selection experiment (attneave experiment).")
    jatos_archive.write_jzip(tmp / f"{name}.jzip", tmp, assets, props)
    return f"{name}.jzip"


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
