"""The PsychoPy Builder export: the task as a ``.psyexp`` experiment (and so for Pavlovia).

``DIR/psychopy/attneave_task.psyexp`` is a Builder experiment [1]_ over
``DIR/psychopy/conditions.csv`` (one row per stimulus, the images copied to
``DIR/psychopy/images/`` so that the folder is a complete Builder or Pavlovia
project). PsychoPy compiles it to a Python script (Builder, *Compile*) and to
PsychoJS for Pavlovia; the XML is written here without importing PsychoPy,
which is not a dependency of attneave, and the test suite compiles it with
PsychoPy's own compiler.

Flow
----
``instructions`` (text, space) -> ``practice`` loop -> ``practice_end`` ->
``trials`` loop (``trial``, ``iti``, ``pause``) -> ``end``.

The ``trial`` routine shows a fixation cross for ``fixation_ms``, then the
Image component ``stimulus`` at the window centre; a Code component reads the
Mouse component ``mouse`` every frame. A press is taken from the press's own
time stamp (``mouse.getPressed(getTime=True)`` in PsychoPy and PsychoJS), not
from the button's state at the frame: Builder's Mouse component saving "on
click" compares the button state once per frame (``prevButtonState``), so a
tap that starts and ends between two frames would be lost, and with a fixed
number of clicks the participant's next click would count for the missing
one. Each press on the image leaves a mark; Backspace or Z removes the last
one (unless ``undo`` is off); the space bar ends the trial once its clicks are
in. At the end of the routine the clicks go to the data file as Builder's
Mouse component writes them: ``mouse.x``, ``mouse.y`` (lists, in the window
units) and ``mouse.time`` (s from the stimulus's first frame), in the row
that also holds the conditions' columns, which carry what converts the
clicks back to image pixels (``size_w, size_h`` in those units, ``width_px,
height_px``); ``attneave analyze`` reads that file as it is.

Order and lists are the page's: a Code component at the start of the
experiment computes the participant's list and seeded order
(:mod:`attneave.analysis.experiment.order`, in Python and JavaScript) and the
loops take them as ``Selected rows``.

Units and monitor
-----------------
``monitor`` names a monitor of PsychoPy's Monitor Center (``--monitor``); its
width, distance and resolution turn degrees into pixels. Units are ``'deg'``
when a monitor is named and ``'height'`` otherwise (no calibration needed,
and the units PsychoJS has: PsychoJS has no ``'deg'``, so an experiment for
Pavlovia must use ``'height'`` or ``'pix'``). Without ``--monitor`` the
experiment names PsychoPy's ``testMonitor``, which exists in every
installation.

References
----------
.. [1] Peirce, J. et al. (2019). PsychoPy2: Experiments in behavior made easy.
       Behavior Research Methods, 51, 195-203.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

from attneave.analysis.experiment import psyexp_code as code
from attneave.analysis.experiment.psychopy_text import (
    DEFAULT_MONITOR,
    TEXT_HEIGHT,
    WRAP_WIDTH,
    psychopy_instructions,
    psychopy_units,
)
from attneave.stimuli.io import atomic_write

__all__ = ["PSYCHOPY_VERSION", "psyexp_text", "write_psyexp"]

#: The PsychoPy release this export is written for and tested with.
PSYCHOPY_VERSION = "2026.2.5"
#: What Builder would call "no end": an empty duration.
_FOREVER = ""

# --- the XML -----------------------------------------------------------------------------------

def _param(parent, name, val, val_type="str", updates="None"):
    ET.SubElement(parent, "Param", dict(val=str(val), valType=val_type, updates=updates, name=name))


def _timing(el, start=0.0, duration=_FOREVER):
    _param(el, "startType", "time (s)")
    _param(el, "startVal", f"{start:g}", "code")
    _param(el, "stopType", "duration (s)")
    _param(el, "stopVal", duration if isinstance(duration, str) else f"{duration:g}", "code", "constant")


def _builder_text(text):
    """`text` as a Builder str param: a leading $ would make it code."""
    return "\\" + text if text.startswith("$") else text


def _text(routine, name, text, units, start=0.0, duration=_FOREVER):
    el = ET.SubElement(routine, "TextComponent", dict(name=name, plugin="None"))
    _param(el, "name", name, "code")
    _param(el, "text", _builder_text(text), "str", "constant")
    _param(el, "color", "black", "color", "constant")
    _param(el, "colorSpace", "named", "str", "constant")
    _param(el, "letterHeight", TEXT_HEIGHT[units], "num", "constant")
    _param(el, "wrapWidth", WRAP_WIDTH[units], "num", "constant")
    _param(el, "pos", "(0, 0)", "list", "constant")
    _param(el, "units", "from exp settings")
    _timing(el, start, duration)
    return el


def _space_key(routine, name):
    el = ET.SubElement(routine, "KeyboardComponent", dict(name=name, plugin="None"))
    _param(el, "name", name, "code")
    _param(el, "allowedKeys", "'space'", "list", "constant")
    _param(el, "forceEndRoutine", "True", "bool")
    _param(el, "store", "nothing")
    _param(el, "discard previous", "True", "bool")
    _timing(el)
    return el


def _code(routine, name, **blocks):
    el = ET.SubElement(routine, "CodeComponent", dict(name=name, plugin="None"))
    _param(el, "name", name, "code")
    _param(el, "Code Type", "Both")
    for key in ("Before Experiment", "Begin Experiment", "Begin Routine", "Each Frame", "End Routine",
                "End Experiment"):
        first, rest = key.split(" ")
        js = f"{first} JS {rest}"  # Builder's name of the JavaScript beside it ("Each JS Frame")
        py, jscode = blocks.get(key.replace(" ", "_").lower(), ("", ""))
        _param(el, key, py, "extendedCode", "constant")
        _param(el, js, jscode, "extendedCode", "constant")
    return el


def _routine(routines, name):
    r = ET.SubElement(routines, "Routine", dict(name=name))
    s = ET.SubElement(r, "RoutineSettingsComponent", dict(name=name, plugin="None"))
    _param(s, "name", name, "code")
    _param(s, "stopType", "duration (s)")
    _param(s, "stopVal", "", "code", "constant")
    return r


def _loop(flow, name, rows, body):
    init = ET.SubElement(flow, "LoopInitiator", dict(loopType="TrialHandler", name=name))
    for pname, val, vt in (("Selected rows", f"${rows}", "code"), ("conditions", "[]", "str"),
                           ("conditionsFile", "conditions.csv", "file"), ("endPoints", "[0, 1]", "code"),
                           ("isTrials", "True", "bool"), ("loopType", "sequential", "str"),
                           ("nReps", "1", "code"), ("name", name, "code"), ("random seed", "", "code")):
        ET.SubElement(init, "Param", dict(name=pname, updates="None", val=val, valType=vt))
    for r in body:
        ET.SubElement(flow, "Routine", dict(name=r))
    ET.SubElement(flow, "LoopTerminator", dict(name=name))


def _settings_code(options, config, units, mark_radius):
    """The experiment's settings as a Python and a JavaScript assignment."""
    s = dict(min_clicks=int(config["min_clicks"]), max_clicks=int(config["max_clicks"] or 10 ** 9),
             undo=bool(config["undo"]), order=config["order"], seed=str(config["seed"]),
             lists=int(config["lists"]), break_every=int(config["break_every"]), mark_radius=mark_radius,
             units=units)
    return f"attneave_settings = {s!r}\n", f"attneave_settings = {json.dumps(s)};\n"


def psyexp_text(options, config, practice, mark_radius):
    """The ``.psyexp`` XML of the task.

    Parameters
    ----------
    options : ExperimentOptions
    config : dict
        From :func:`attneave.analysis.experiment.build.page_config`.
    practice : bool
        There are practice stimuli (rows with ``practice`` 1 in conditions.csv).
    mark_radius : float
        Radius of the mark left by a click, in the experiment's units.

    Returns
    -------
    str
        XML that PsychoPy's ``Experiment.loadFromXML`` reads (UTF-8).
    """
    units = psychopy_units(options)
    root = ET.Element("PsychoPy2experiment", dict(encoding="utf-8", version=PSYCHOPY_VERSION))
    settings = ET.SubElement(root, "Settings")
    for name, val, vt in (
            ("expName", "attneave_task", "str"), ("Monitor", options.monitor or DEFAULT_MONITOR, "str"),
            ("Units", units, "str"), ("Experiment info", "{'participant': '', 'list': ''}", "code"),
            ("color", config["background"], "color"), ("colorSpace", "hex", "str"),
            ("Full-screen window", "True", "bool"), ("Show mouse", "True", "bool"),
            ("Show info dlg", "True", "bool"), ("Save wide csv file", "True", "bool"),
            ("Save psydat file", "False", "bool"), ("Save log file", "True", "bool"),
            ("Use version", "", "str"), ("Enable Escape", "True", "bool"),
            ("End Message", "", "str")):
        _param(settings, name, val, vt)
    routines = ET.SubElement(root, "Routines")
    py_settings, js_settings = _settings_code(options, config, units, mark_radius)

    r = _routine(routines, "instructions")
    _code(r, "setup_code", begin_experiment=(py_settings + code.BEGIN_PY, js_settings + code.BEGIN_JS))
    _text(r, "instructions_text", psychopy_instructions(options, config) + "\n\n(press the space bar to start)", units)
    _space_key(r, "instructions_key")

    fixation_s = config["fixation_ms"] / 1000.0
    r = _routine(routines, "trial")
    if fixation_s > 0:
        _text(r, "fixation", "+", units, 0.0, fixation_s)
    image = ET.SubElement(r, "ImageComponent", dict(name="stimulus", plugin="None"))
    _param(image, "name", "stimulus", "code")
    _param(image, "image", "$image", "file", "set every repeat")
    _param(image, "size", "(size_w, size_h)", "list", "set every repeat")
    _param(image, "pos", "(0, 0)", "list", "constant")
    _param(image, "units", "from exp settings")
    _param(image, "interpolate", "linear", "str", "constant")
    _timing(image, fixation_s)
    mouse = ET.SubElement(r, "MouseComponent", dict(name="mouse", plugin="None"))
    _param(mouse, "name", "mouse", "code")
    # the Code component records each press from its time stamp (see the module docstring)
    _param(mouse, "saveMouseState", "never")
    _param(mouse, "forceEndRoutineOnPress", "never", "str", "constant")
    _param(mouse, "timeRelativeTo", "mouse onset", "str", "constant")
    _timing(mouse, fixation_s)
    _code(r, "trial_code", begin_routine=(code.TRIAL_BEGIN_PY, code.TRIAL_BEGIN_JS),
          each_frame=(code.TRIAL_FRAME_PY, code.TRIAL_FRAME_JS), end_routine=(code.TRIAL_END_PY, code.TRIAL_END_JS))

    iti_s = config["iti_ms"] / 1000.0
    if iti_s > 0:
        r = _routine(routines, "iti")
        _text(r, "blank", " ", units, 0.0, iti_s)
    if config["break_every"]:
        r = _routine(routines, "pause")
        _code(r, "pause_code", begin_routine=(code.PAUSE_PY, code.PAUSE_JS))
        _text(r, "pause_text", "Take a short break.\n\n(press the space bar to go on)", units)
        _space_key(r, "pause_key")
    if practice:
        r = _routine(routines, "practice_end")
        _code(r, "practice_end_code", begin_routine=(code.PRACTICE_END_PY, code.PRACTICE_END_JS))
        _text(r, "practice_end_text", "The practice is over. The experiment starts now.\n\n"
              "(press the space bar to go on)", units)
        _space_key(r, "practice_end_key")
    r = _routine(routines, "end")
    _text(r, "end_text", config["end_text"] + "\n\n(press the space bar to close)", units)
    _space_key(r, "end_key")

    flow = ET.SubElement(root, "Flow")
    ET.SubElement(flow, "Routine", dict(name="instructions"))
    # one loop over practice and main rows: two loops over one conditions file would define its
    # variables twice
    body = (["trial"] + (["iti"] if iti_s > 0 else []) + (["practice_end"] if practice else [])
            + (["pause"] if config["break_every"] else []))
    _loop(flow, "trials", "practice_rows + main_rows", body)
    ET.SubElement(flow, "Routine", dict(name="end"))
    ET.indent(root, space="  ")
    return '<?xml version="1.0" ?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write_psyexp(path, options, config, practice, mark_radius):
    """Write :func:`psyexp_text` to `path` atomically (UTF-8 with a byte-order mark, as Builder saves)."""
    with atomic_write(path, "w", encoding="utf-8-sig") as fh:
        fh.write(psyexp_text(options, config, practice, mark_radius))
    return path
