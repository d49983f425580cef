"""The code of the Builder export's Code components, in Python and the same in JavaScript.

Kept apart from :mod:`attneave.analysis.experiment.psyexp`, which writes the
XML: a block per Code component and moment (Begin Experiment, Begin Routine,
Each Frame, End Routine), each ``*_PY`` with its ``*_JS``. The variables they
share start with ``attneave_`` (PsychoPy's JavaScript compiler declares every
name a block assigns); ``main_rows`` and ``practice_rows`` are the loop's
``Selected rows``.
"""

__all__ = [
    "BEGIN_PY", "BEGIN_JS", "TRIAL_BEGIN_PY", "TRIAL_BEGIN_JS", "TRIAL_FRAME_PY", "TRIAL_FRAME_JS",
    "TRIAL_END_PY", "TRIAL_END_JS", "PAUSE_PY", "PAUSE_JS", "PRACTICE_END_PY", "PRACTICE_END_JS"
]

BEGIN_PY = '''\
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

BEGIN_JS = '''\
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

TRIAL_BEGIN_PY = '''\
attneave_x, attneave_y, attneave_t, attneave_marks = [], [], [], []
attneave_last_press = None  # set on the stimulus's first frame
'''
TRIAL_BEGIN_JS = '''\
attneave_x = []; attneave_y = []; attneave_t = []; attneave_marks = [];
attneave_last_press = null;  // set on the stimulus's first frame
'''

TRIAL_FRAME_PY = '''\
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
TRIAL_FRAME_JS = '''\
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

TRIAL_END_PY = '''\
for attneave_mark in attneave_marks:
    attneave_mark.setAutoDraw(False)
# the columns of Builder's Mouse component (lists, window units; s from the stimulus's first frame)
thisExp.addData("mouse.x", attneave_x)
thisExp.addData("mouse.y", attneave_y)
thisExp.addData("mouse.time", attneave_t)
thisExp.addData("clicks_n", len(attneave_x))
'''
TRIAL_END_JS = '''\
for (let k = 0; k < attneave_marks.length; k++) attneave_marks[k].setAutoDraw(false);
// the columns of Builder's Mouse component, written as lists "[x1,x2]" (JSON)
psychoJS.experiment.addData("mouse.x", JSON.stringify(attneave_x));
psychoJS.experiment.addData("mouse.y", JSON.stringify(attneave_y));
psychoJS.experiment.addData("mouse.time", JSON.stringify(attneave_t));
psychoJS.experiment.addData("clicks_n", attneave_x.length);
'''

PAUSE_PY = '''\
# a pause screen after every break_every main trials (practice trials do not count), not after the last
attneave_done = trials.thisN + 1 - len(practice_rows)
if attneave_done <= 0 or not (attneave_settings["break_every"] and attneave_done % attneave_settings["break_every"] == 0
                              and attneave_done < len(main_rows)):
    continueRoutine = False
'''
PAUSE_JS = '''\
attneave_done = trials.thisN + 1 - practice_rows.length;
if (attneave_done <= 0 || !(attneave_settings["break_every"]
      && attneave_done % attneave_settings["break_every"] === 0 && attneave_done < main_rows.length)) {
  continueRoutine = false;
}
'''
PRACTICE_END_PY = '''\
# shown once, after the last practice trial
if trials.thisN + 1 != len(practice_rows):
    continueRoutine = False
'''
PRACTICE_END_JS = '''\
if (trials.thisN + 1 !== practice_rows.length) {
  continueRoutine = false;
}
'''
