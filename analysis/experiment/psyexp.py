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

# --- code run by the experiment (Python and the same in JavaScript) ----------------------------

_BEGIN_PY = '''\
# attneave: the page's participant list and seeded order (task.js; attneave.analysis.experiment.order)
def attneave_fnv1a32(text):
    h = 0x811C9DC5
    for byte in str(text).encode("utf-8"):
        h = ((h ^ byte) * 0x01000193) & 0xFFFFFFFF
    return h


def attneave_mulberry32(seed):
    state = [seed & 0xFFFFFFFF]

    def draw():
        a = state[0] = (state[0] + 0x6D2B79F5) & 0xFFFFFFFF
        t = ((a ^ (a >> 15)) * (1 | a)) & 0xFFFFFFFF
        t = ((t + (((t ^ (t >> 7)) * (61 | t)) & 0xFFFFFFFF)) & 0xFFFFFFFF) ^ t
        return ((t ^ (t >> 14)) & 0xFFFFFFFF) / 4294967296.0
    return draw


def attneave_shuffle(items, rng):
    out = list(items)
    for i in range(len(out) - 1, 0, -1):
        j = int(rng() * (i + 1))
        out[i], out[j] = out[j], out[i]
    return out


def attneave_order(participant, ids, conditions, order, seed):
    if order == "fixed":
        return list(ids)
    rng = attneave_mulberry32(attneave_fnv1a32("%s:%s" % (seed, participant)))
    if order == "random":
        return attneave_shuffle(ids, rng)
    out = []
    for block in attneave_shuffle(list(dict.fromkeys(conditions)), rng):
        out += attneave_shuffle([s for s, c in zip(ids, conditions) if c == block], rng)
    return out


attneave_rows = data.importConditions("conditions.csv")
attneave_participant = str(expInfo["participant"]).strip()
if str(expInfo.get("list", "")).strip():
    attneave_list = int(str(expInfo["list"]).strip())
else:
    attneave_list = attneave_fnv1a32("list:%s:%s" % (attneave_settings["seed"], attneave_participant)) \\
        % attneave_settings["lists"] + 1
expInfo["list"] = attneave_list
# rows, not ids, are shuffled (the same draws): importConditions may have made an id '007' the number 7
practice_rows = [i for i, r in enumerate(attneave_rows) if float(r["practice"]) == 1]
attneave_mine = [i for i, r in enumerate(attneave_rows)
                 if float(r["practice"]) != 1 and str(attneave_list) in str(r["lists"]).split(";")]
main_rows = attneave_order(attneave_participant, attneave_mine,
                           [str(attneave_rows[i]["condition"]) for i in attneave_mine],
                           attneave_settings["order"], attneave_settings["seed"])
'''

_BEGIN_JS = '''\
// attneave: the page's participant list and seeded order (task.js; attneave.analysis.experiment.order)
function attneave_fnv1a32(text) {
  const bytes = new TextEncoder().encode(String(text));
  let h = 0x811c9dc5;
  for (let i = 0; i < bytes.length; i++) {
    h ^= bytes[i];
    h = Math.imul(h, 0x01000193) >>> 0;
  }
  return h >>> 0;
}
function attneave_mulberry32(seed) {
  let a = seed >>> 0;
  return function () {
    a = (a + 0x6d2b79f5) | 0;
    let t = Math.imul(a ^ (a >>> 15), 1 | a);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}
function attneave_shuffle(items, rng) {
  const out = items.slice();
  for (let i = out.length - 1; i > 0; i--) {
    const j = Math.floor(rng() * (i + 1));
    const tmp = out[i]; out[i] = out[j]; out[j] = tmp;
  }
  return out;
}
function attneave_order(participant, ids, conditions, order, seed) {
  if (order === "fixed") return ids.slice();
  const rng = attneave_mulberry32(attneave_fnv1a32(String(seed) + ":" + participant));
  if (order === "random") return attneave_shuffle(ids, rng);
  const blocks = [];
  conditions.forEach(function (c) { if (blocks.indexOf(c) < 0) blocks.push(c); });
  let out = [];
  attneave_shuffle(blocks, rng).forEach(function (b) {
    out = out.concat(attneave_shuffle(ids.filter(function (_, k) { return conditions[k] === b; }), rng));
  });
  return out;
}
attneave_rows = TrialHandler.importConditions(psychoJS.serverManager, "conditions.csv");
attneave_participant = String(expInfo["participant"]).trim();
if (String(expInfo["list"] || "").trim()) {
  attneave_list = parseInt(String(expInfo["list"]).trim(), 10);
} else {
  attneave_list = attneave_fnv1a32("list:" + attneave_settings["seed"] + ":" + attneave_participant)
    % attneave_settings["lists"] + 1;
}
expInfo["list"] = attneave_list;
// rows, not ids, are shuffled (the same draws): a numeric-looking id may have become a number
practice_rows = [];
attneave_mine = [];
attneave_rows.forEach(function (r, i) {
  if (Number(r["practice"]) === 1) practice_rows.push(i);
  else if (String(r["lists"]).split(";").indexOf(String(attneave_list)) >= 0) attneave_mine.push(i);
});
main_rows = attneave_order(attneave_participant, attneave_mine,
  attneave_mine.map(function (i) { return String(attneave_rows[i]["condition"]); }),
  attneave_settings["order"], attneave_settings["seed"]);
'''

_TRIAL_BEGIN_PY = '''\
attneave_x, attneave_y, attneave_t, attneave_marks = [], [], [], []
attneave_last_press = None  # set on the stimulus's first frame
'''
_TRIAL_BEGIN_JS = '''\
attneave_x = []; attneave_y = []; attneave_t = []; attneave_marks = [];
attneave_last_press = null;  // set on the stimulus's first frame
'''

_TRIAL_FRAME_PY = '''\
if stimulus.status == STARTED:
    if attneave_last_press is None:
        mouse.clickReset()  # press times count from the stimulus's first frame
        event.clearEvents()
        attneave_last_press = 0.0
    attneave_buttons, attneave_times = mouse.getPressed(getTime=True)
    # every press stamps its own time when it happens: a tap that starts and ends between
    # two frames is seen here, where the button's state at the frame would miss it
    if attneave_times[0] > attneave_last_press:
        attneave_last_press = attneave_times[0]
        if stimulus.contains(mouse) and len(attneave_x) < attneave_settings["max_clicks"]:
            attneave_pos = mouse.getPos()
            attneave_x.append(float(attneave_pos[0]))
            attneave_y.append(float(attneave_pos[1]))
            attneave_t.append(float(attneave_times[0]))
            attneave_mark = visual.Circle(win, radius=attneave_settings["mark_radius"], pos=attneave_pos,
                                          fillColor="#e6007e", lineColor="white", units=stimulus.units)
            attneave_mark.setAutoDraw(True)
            attneave_marks.append(attneave_mark)
    for attneave_key in event.getKeys(keyList=["space", "backspace", "z"]):
        if attneave_key in ("backspace", "z") and attneave_settings["undo"] and attneave_x:
            attneave_x.pop()
            attneave_y.pop()
            attneave_t.pop()
            attneave_marks.pop().setAutoDraw(False)
        elif attneave_key == "space" and len(attneave_x) >= attneave_settings["min_clicks"]:
            continueRoutine = False
'''
_TRIAL_FRAME_JS = '''\
if (stimulus.status === PsychoJS.Status.STARTED) {
  if (attneave_last_press === null) {
    mouse.clickReset();  // press times count from the stimulus's first frame
    psychoJS.eventManager.clearEvents();
    attneave_last_press = 0.0;
  }
  attneave_pressed = mouse.getPressed(true);
  // every press stamps its own time when it happens: a tap between two frames is seen too
  if (attneave_pressed[1][0] > attneave_last_press) {
    attneave_last_press = attneave_pressed[1][0];
    if (stimulus.contains(mouse) && attneave_x.length < attneave_settings["max_clicks"]) {
      attneave_pos = mouse.getPos();
      attneave_x.push(attneave_pos[0]);
      attneave_y.push(attneave_pos[1]);
      attneave_t.push(attneave_pressed[1][0]);
      attneave_mark = new visual.Polygon({win: psychoJS.window, name: "attneave_mark", edges: 32,
        radius: attneave_settings["mark_radius"], pos: attneave_pos, units: stimulus.units,
        fillColor: new util.Color("#e6007e"), lineColor: new util.Color("white")});
      attneave_mark.setAutoDraw(true);
      attneave_marks.push(attneave_mark);
    }
  }
  attneave_keys = psychoJS.eventManager.getKeys({keyList: ["space", "backspace", "z"]});
  for (let k = 0; k < attneave_keys.length; k++) {
    if ((attneave_keys[k] === "backspace" || attneave_keys[k] === "z") && attneave_settings["undo"]
        && attneave_x.length > 0) {
      attneave_x.pop(); attneave_y.pop(); attneave_t.pop();
      attneave_marks.pop().setAutoDraw(false);
    } else if (attneave_keys[k] === "space" && attneave_x.length >= attneave_settings["min_clicks"]) {
      continueRoutine = false;
    }
  }
}
'''

_TRIAL_END_PY = '''\
for attneave_mark in attneave_marks:
    attneave_mark.setAutoDraw(False)
# the columns of Builder's Mouse component (lists, window units; s from the stimulus's first frame)
thisExp.addData("mouse.x", attneave_x)
thisExp.addData("mouse.y", attneave_y)
thisExp.addData("mouse.time", attneave_t)
thisExp.addData("clicks_n", len(attneave_x))
'''
_TRIAL_END_JS = '''\
for (let k = 0; k < attneave_marks.length; k++) attneave_marks[k].setAutoDraw(false);
// the columns of Builder's Mouse component, written as lists "[x1,x2]" (JSON)
psychoJS.experiment.addData("mouse.x", JSON.stringify(attneave_x));
psychoJS.experiment.addData("mouse.y", JSON.stringify(attneave_y));
psychoJS.experiment.addData("mouse.time", JSON.stringify(attneave_t));
psychoJS.experiment.addData("clicks_n", attneave_x.length);
'''

_PAUSE_PY = '''\
# a pause screen after every break_every main trials (practice trials do not count), not after the last
attneave_done = trials.thisN + 1 - len(practice_rows)
if attneave_done <= 0 or not (attneave_settings["break_every"] and attneave_done % attneave_settings["break_every"] == 0
                              and attneave_done < len(main_rows)):
    continueRoutine = False
'''
_PAUSE_JS = '''\
attneave_done = trials.thisN + 1 - practice_rows.length;
if (attneave_done <= 0 || !(attneave_settings["break_every"]
      && attneave_done % attneave_settings["break_every"] === 0 && attneave_done < main_rows.length)) {
  continueRoutine = false;
}
'''
_PRACTICE_END_PY = '''\
# shown once, after the last practice trial
if trials.thisN + 1 != len(practice_rows):
    continueRoutine = False
'''
_PRACTICE_END_JS = '''\
if (trials.thisN + 1 !== practice_rows.length) {
  continueRoutine = false;
}
'''


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
        js = key.replace("Before ", "Before JS ").replace("Begin ", "Begin JS ").replace("Each ", "Each JS ") \
                .replace("End ", "End JS ")
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
    _code(r, "setup_code", begin_experiment=(py_settings + _BEGIN_PY, js_settings + _BEGIN_JS))
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
    _code(r, "trial_code", begin_routine=(_TRIAL_BEGIN_PY, _TRIAL_BEGIN_JS),
          each_frame=(_TRIAL_FRAME_PY, _TRIAL_FRAME_JS), end_routine=(_TRIAL_END_PY, _TRIAL_END_JS))

    iti_s = config["iti_ms"] / 1000.0
    if iti_s > 0:
        r = _routine(routines, "iti")
        _text(r, "blank", " ", units, 0.0, iti_s)
    if config["break_every"]:
        r = _routine(routines, "pause")
        _code(r, "pause_code", begin_routine=(_PAUSE_PY, _PAUSE_JS))
        _text(r, "pause_text", "Take a short break.\n\n(press the space bar to go on)", units)
        _space_key(r, "pause_key")
    if practice:
        r = _routine(routines, "practice_end")
        _code(r, "practice_end_code", begin_routine=(_PRACTICE_END_PY, _PRACTICE_END_JS))
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
