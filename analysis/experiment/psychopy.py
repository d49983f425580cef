"""The PsychoPy export: the same task for a lab, in PsychoPy Coder.

``DIR/psychopy/conditions.csv`` lists the stimuli (image path relative to the
script, size in the chosen units, condition, lists) and
``DIR/psychopy/attneave_task.py`` runs the task of the browser page with
``visual.Window``, ``visual.ImageStim`` and ``event.Mouse`` and writes the
page's CSV columns, with clicks converted from window units (origin at the
window centre, y up) to the image's pixels (y down, pixel centres at
integers), so that ``attneave analyze`` reads its files as it does the
page's. PsychoPy is not a dependency of attneave.

Sizes by ``psychopy_units``:

``deg``
    ``size_deg`` for the larger side of the largest image (PsychoPy's
    ``'deg'`` units, the same linear scale as the page; set the monitor's
    width and distance at the top of the script).
``pix``
    ``size_px`` for the larger side of the largest image, or the image's own
    pixels when only ``size_deg`` was given.
``height``
    The larger side of the largest image is 0.8 window heights.

References
----------
.. [1] Peirce, J. et al. (2019). PsychoPy2: Experiments in behavior made easy.
       Behavior Research Methods, 51, 195-203.
"""

from __future__ import annotations

import csv
import pprint
from importlib import resources
from pathlib import Path

from attneave.analysis.experiment.build import fill_template
from attneave.stimuli.errors import InputError
from attneave.stimuli.io import atomic_write

__all__ = ["conditions_rows", "script_text", "write_psychopy", "HEIGHT_FRACTION"]

#: In 'height' units, the larger side of the largest image as a fraction of the window height.
HEIGHT_FRACTION = 0.8
CONDITION_COLUMNS = ("image", "stimulus_id", "condition", "parent_id", "lists", "practice", "width_px",
                     "height_px", "size_w", "size_h", "units")


def _unit_scale(options, max_side):
    """Window units per image pixel."""
    u = options.psychopy_units
    if u == "deg":
        if options.size_deg is None:
            raise InputError("psychopy_units: 'deg' needs size_deg (size_px was given); use psychopy_units: pix")
        return options.size_deg / max_side
    if u == "pix":
        return (options.size_px / max_side) if options.size_px is not None else 1.0
    return HEIGHT_FRACTION / max_side


def conditions_rows(options, practice, main):
    """Rows of ``conditions.csv``: one per stimulus, practice first.

    Parameters
    ----------
    options : ExperimentOptions
    practice, main : list of attneave.analysis.experiment.build.Stimulus

    Returns
    -------
    list of dict
        Keys `CONDITION_COLUMNS`; ``image`` is relative to the psychopy
        directory (``../images/<id>.png``), ``lists`` the 1-based lists
        joined by ``;``, ``size_w, size_h`` in ``options.psychopy_units``.
    """
    every = list(practice) + list(main)
    k = _unit_scale(options, max(max(s.width, s.height) for s in every))
    rows = []
    for s, is_practice in [(s, True) for s in practice] + [(s, False) for s in main]:
        rows.append(dict(image=f"../{s.src}", stimulus_id=s.id, condition=s.condition, parent_id=s.parent_id,
                         lists=";".join(str(v) for v in s.lists), practice=int(is_practice), width_px=s.width,
                         height_px=s.height, size_w=f"{s.width * k:.10g}", size_h=f"{s.height * k:.10g}",
                         units=options.psychopy_units))
    return rows


def script_text(options, config):
    """The PsychoPy Coder script with this experiment's settings filled in.

    Parameters
    ----------
    options : ExperimentOptions
    config : dict
        From :func:`attneave.analysis.experiment.build.page_config`.

    Returns
    -------
    str
        Python source (compiles without PsychoPy; PsychoPy is imported in
        ``main()`` only).
    """
    settings = dict(
        title=config["title"], instructions=config["instructions"], end_text=config["end_text"],
        units=options.psychopy_units, min_clicks=config["min_clicks"], max_clicks=config["max_clicks"],
        undo=config["undo"], order=config["order"], seed=config["seed"], lists=config["lists"],
        fixation_ms=config["fixation_ms"], iti_ms=config["iti_ms"], break_every=config["break_every"],
        background=config["background"],
    )
    text_height = {"deg": "0.8", "pix": "24", "height": "0.035"}[options.psychopy_units]
    wrap = {"deg": "30", "pix": "1000", "height": "1.2"}[options.psychopy_units]
    template = resources.files("attneave.analysis.experiment").joinpath("static", "attneave_task.py.in").read_text("utf-8")
    # one pass: a placeholder's name in the title or instructions stays text
    return fill_template(template, {
        "__SETTINGS__": pprint.pformat(settings, indent=4, width=100, sort_dicts=False),
        "__DISTANCE__": repr(float(options.viewing_distance_cm)), "__TEXT_HEIGHT__": text_height,
        "__WRAP_WIDTH__": wrap})


def write_psychopy(directory, options, practice, main, config):
    """Write ``conditions.csv`` and ``attneave_task.py`` into `directory` (created).

    Parameters
    ----------
    directory : Path
    options : ExperimentOptions
    practice, main : list of Stimulus
    config : dict
        The page's config (:func:`attneave.analysis.experiment.build.page_config`).

    Returns
    -------
    list of Path
        The files written.
    """
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    rows = conditions_rows(options, practice, main)
    cpath = directory / "conditions.csv"
    with atomic_write(cpath, "w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=CONDITION_COLUMNS, lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    spath = directory / "attneave_task.py"
    with atomic_write(spath, "w", encoding="utf-8") as fh:
        fh.write(script_text(options, config))
    return [cpath, spath]
