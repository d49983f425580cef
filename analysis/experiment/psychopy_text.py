"""What the two PsychoPy exports share: their units, monitor and the words participants read.

The browser page has Next and Undo buttons; PsychoPy's window has none, so the
exports state the keys they do have (:func:`psychopy_instructions`).
"""

from __future__ import annotations

from attneave.analysis.experiment.options import DEFAULT_INSTRUCTIONS
from attneave.stimuli.errors import InputError

__all__ = ["DEFAULT_MONITOR", "TEXT_HEIGHT", "WRAP_WIDTH", "psychopy_units", "psychopy_instructions", "controls_text"]

#: The monitor of PsychoPy's Monitor Center used without ``--monitor`` (every installation has it).
DEFAULT_MONITOR = "testMonitor"
#: Letter height and wrap width of the texts, by units.
TEXT_HEIGHT = {"deg": "0.8", "pix": "24", "height": "0.035"}
WRAP_WIDTH = {"deg": "30", "pix": "1000", "height": "1.2"}

# the page's default instructions up to its sentences about the buttons
_TASK = DEFAULT_INSTRUCTIONS.split("\n\n")[:2]


def psychopy_units(options):
    """The exports' units: ``psychopy_units`` if given, else 'deg' with a named monitor, else 'height'.

    Raises
    ------
    InputError
        'deg' without a monitor (degrees need the monitor's width, distance
        and resolution from PsychoPy's Monitor Center) or without
        ``size_deg``.

    Examples
    --------
    >>> from attneave.analysis.experiment.options import ExperimentOptions
    >>> psychopy_units(ExperimentOptions()), psychopy_units(ExperimentOptions(monitor="lab"))
    ('height', 'deg')
    """
    units = options.psychopy_units or ("deg" if options.monitor else "height")
    if units == "deg" and not options.monitor:
        raise InputError(f"{options.origin('psychopy_units')}: 'deg' needs --monitor NAME (a monitor set up in "
                         "PsychoPy's Monitor Center, whose width, distance and resolution turn degrees into "
                         "pixels); or use psychopy_units: height")
    if units == "deg" and options.size_deg is None:
        raise InputError("psychopy_units: 'deg' needs size_deg (size_px was given); use psychopy_units: pix")
    return units


def controls_text(config):
    """The keys of a PsychoPy trial, in words (what the task does, and nothing it does not).

    Examples
    --------
    >>> controls_text(dict(min_clicks=3, max_clicks=3, undo=True))
    'Each click on the shape leaves a mark. If a click went wrong, press Backspace (or Z) to remove the last one. Place 3 points, then press the space bar to go on.'
    """
    lo, hi = int(config["min_clicks"]), config["max_clicks"]
    words = ["Each click on the shape leaves a mark."]
    if config["undo"]:
        words.append("If a click went wrong, press Backspace (or Z) to remove the last one.")
    if hi is not None and int(hi) == lo:
        words.append(f"Place {lo} point{'s' if lo > 1 else ''}, then press the space bar to go on.")
    else:
        bounds = f"at least {lo}" + (f" and at most {int(hi)}" if hi is not None else "")
        words.append(f"Press the space bar when you have placed your points ({bounds}).")
    return " ".join(words)


def psychopy_instructions(options, config):
    """The instructions of the PsychoPy exports.

    The page's default instructions name its buttons; here its first
    paragraphs (the task) are followed by :func:`controls_text`. Instructions
    of the user's own are kept and :func:`controls_text` follows them, so
    that the keys are always stated as the exports have them.
    """
    head = "\n\n".join(_TASK) if options.instructions == DEFAULT_INSTRUCTIONS else options.instructions.rstrip()
    return head + "\n\n" + controls_text(config)
