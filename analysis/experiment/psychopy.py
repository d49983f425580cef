"""The PsychoPy exports: the same task for a lab, in PsychoPy Builder and Coder.

``DIR/psychopy/`` is a complete PsychoPy project (upload it as it is to
Pavlovia): ``conditions.csv`` lists the stimuli (image path relative to the
folder, size in the chosen units, and ``width_px, height_px``, which convert
window units back to image pixels), ``images/`` holds copies of the images,
``attneave_task.psyexp`` is the Builder experiment
(:mod:`attneave.analysis.experiment.psyexp`; Builder compiles it to Python and
to PsychoJS) and ``attneave_task.py`` the Coder script, which runs the same
task with ``visual.Window``, ``visual.ImageStim`` and ``event.Mouse`` and
writes the browser page's CSV columns, with clicks in the image's pixels
(y down, pixel centres at integers). ``attneave analyze`` reads the data of
both. PsychoPy is not a dependency of attneave.

Units (:func:`attneave.analysis.experiment.psychopy_text.psychopy_units`):
'deg' when a monitor of PsychoPy's Monitor Center is named (``monitor``),
otherwise 'height'; ``psychopy_units`` chooses:

``deg``
    ``size_deg`` for the larger side of the largest image (the same linear
    scale as the page), converted to pixels with the named monitor's width,
    distance and resolution.
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
import shutil
from importlib import resources
from pathlib import Path

from attneave.analysis.experiment.pages import fill_template
from attneave.analysis.experiment.psychopy_text import (
    DEFAULT_MONITOR,
    TEXT_HEIGHT,
    WRAP_WIDTH,
    psychopy_instructions,
    psychopy_units,
)
from attneave.analysis.experiment.psyexp import write_psyexp
from attneave.stimuli.io import atomic_write

__all__ = ["conditions_rows", "script_text", "write_psychopy", "mixed_columns", "HEIGHT_FRACTION"]

#: In 'height' units, the larger side of the largest image as a fraction of the window height.
HEIGHT_FRACTION = 0.8
CONDITION_COLUMNS = ("image", "stimulus_id", "condition", "parent_id", "lists", "practice", "width_px",
                     "height_px", "size_w", "size_h", "units")


def _unit_scale(options, max_side):
    """Window units per image pixel."""
    u = psychopy_units(options)
    if u == "deg":
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
        directory (``images/<id>.png``, a copy there), ``lists`` the 1-based
        lists, each followed by ``;`` (``2;``, never a number: PsychoPy's
        ``importConditions`` turns a text cell that reads as a number into
        one, and fails on a text column holding both under pandas 3), ``size_w, size_h`` in the units
        (:func:`attneave.analysis.experiment.psychopy_text.psychopy_units`).
    """
    every = list(practice) + list(main)
    k = _unit_scale(options, max(max(s.width, s.height) for s in every))
    units = psychopy_units(options)
    rows = []
    for s, is_practice in [(s, True) for s in practice] + [(s, False) for s in main]:
        rows.append(dict(image=s.src, stimulus_id=s.id, condition=s.condition, parent_id=s.parent_id,
                         lists="".join(f"{v};" for v in s.lists), practice=int(is_practice), width_px=s.width,
                         height_px=s.height, size_w=f"{s.width * k:.10g}", size_h=f"{s.height * k:.10g}",
                         units=units))
    return rows


def _number(text):
    """True when PsychoPy's importConditions would read `text` as a number (it tries float(), ',' as '.')."""
    try:
        float(text.replace(",", "."))
    except ValueError:
        return False
    return True


def mixed_columns(rows):
    """A warning when a text column of conditions.csv holds both numbers and text ('' if none).

    PsychoPy's ``importConditions`` converts each text cell that reads as a
    number; under pandas 3 such a column then fails with a TypeError, so the
    Builder experiment would not start.

    Examples
    --------
    >>> mixed_columns([dict(stimulus_id="a", condition="1"), dict(stimulus_id="b", condition="x")])[:40]
    "conditions.csv: column 'condition' holds"
    """
    for c in ("stimulus_id", "condition", "parent_id"):
        values = [str(r.get(c, "")) for r in rows if str(r.get(c, "")).strip()]
        numbers = [v for v in values if _number(v)]
        if numbers and len(numbers) < len(values):
            text = next(v for v in values if not _number(v))
            return (f"conditions.csv: column {c!r} holds numbers ({numbers[0][:20]!r}) and text ({text[:20]!r}); "
                    f"PsychoPy's importConditions fails on such a column under pandas 3 (TypeError), so the "
                    f"Builder experiment may not start: give the {c} values a letter (e.g. 'c{numbers[0][:20]}')")
    return ""


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
    units = psychopy_units(options)
    settings = dict(
        title=config["title"], instructions=psychopy_instructions(options, config), end_text=config["end_text"],
        units=units, min_clicks=config["min_clicks"], max_clicks=config["max_clicks"],
        undo=config["undo"], order=config["order"], seed=config["seed"], lists=config["lists"],
        fixation_ms=config["fixation_ms"], iti_ms=config["iti_ms"], break_every=config["break_every"],
        background=config["background"],
    )
    template = resources.files("attneave.analysis.experiment").joinpath("static", "attneave_task.py.in").read_text("utf-8")
    # one pass: a placeholder's name in the title or instructions stays text
    return fill_template(template, {
        "__SETTINGS__": pprint.pformat(settings, indent=4, width=100, sort_dicts=False),
        "__MONITOR__": repr(options.monitor or DEFAULT_MONITOR),
        "__DISTANCE__": repr(float(options.viewing_distance_cm)), "__TEXT_HEIGHT__": TEXT_HEIGHT[units],
        "__WRAP_WIDTH__": WRAP_WIDTH[units]})


def write_psychopy(directory, options, practice, main, config):
    """Write the PsychoPy project into `directory` (created).

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
        The files written: ``conditions.csv``, ``attneave_task.py``,
        ``attneave_task.psyexp`` and the images under ``images/``.
    """
    directory = Path(directory)
    (directory / "images").mkdir(parents=True, exist_ok=True)
    rows = conditions_rows(options, practice, main)
    cpath = directory / "conditions.csv"
    with atomic_write(cpath, "w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=CONDITION_COLUMNS, lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    # Builder and Pavlovia take a project's files from inside its folder only
    images = []
    for s in list(practice) + list(main):
        images.append(directory / s.src)
        shutil.copyfile(s.source, images[-1])
    spath = directory / "attneave_task.py"
    with atomic_write(spath, "w", encoding="utf-8") as fh:
        fh.write(script_text(options, config))
    # a click's mark: 1/80 of the largest image's width, as the Coder script draws it
    radius = max(float(r["size_w"]) for r in rows) / 80.0
    xpath = write_psyexp(directory / "attneave_task.psyexp", options, config, bool(practice), radius)
    return [cpath, spath, xpath, *images]
