"""Settings of the experiment page: one validated object, from YAML and flags.

Every setting has a YAML key (``--config exp.yaml``) and a command-line flag
of the same name with dashes (``break_every`` / ``--break-every``); a flag
overrides the file. Validation happens here, once; the rest of the package
receives an :class:`ExperimentOptions`.
"""

from __future__ import annotations

import difflib
import re
from pathlib import Path
from typing import Literal, Optional, Union

from pydantic import BaseModel, ConfigDict, Field, PrivateAttr, ValidationError, field_validator, model_validator

from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_int, as_number

__all__ = ["ExperimentOptions", "load_options", "DEFAULT_INSTRUCTIONS", "DEFAULT_SIZE_DEG", "RECRUITMENT"]

DEFAULT_SIZE_DEG = 10.0
#: Bounds that keep a page usable and its build small: clicks a trial may ask for, counterbalanced
#: lists (each is a list of every trial), and an image side in CSS pixels (the largest canvas).
MAX_CLICKS = 1000
MAX_LISTS = 1000
MAX_SIZE_PX = 16384.0

# The task of Attneave (1954) and Norman et al. (2001), in words a participant reads.
DEFAULT_INSTRUCTIONS = (
    "On each screen you will see a shape.\n\n"
    "Click the points on its outline that you think are the most important for telling what the shape "
    "looks like: the points you would keep if you had to draw the shape from memory with only a few dots.\n\n"
    "Click as precisely as you can, right on the outline. If a click went wrong, press Undo (or Backspace / Z). "
    "Press Next (or the space bar) when you have placed your points."
)

#: submit_url: an absolute http(s) URL with a host, or a path on the page's host
_ABSOLUTE_URL = re.compile(r"^https?://[A-Za-z0-9.\-\[\]:@%_~!$&'()*+,;=]+(?:[/?#][^\s\\]*)?$")
_RELATIVE_URL = re.compile(r"^(?:/|\./|\.\./)[^\s]*$")
_HEX = re.compile(r"^#(?:[0-9a-fA-F]{3}|[0-9a-fA-F]{6})$")
#: a URL query parameter's name, as recruitment platforms spell theirs (PROLIFIC_PID, workerId, id)
_PARAM = re.compile(r"^[A-Za-z_][A-Za-z0-9_.-]{0,63}$")
#: jspsych_path: a folder beside the page or on another host, written into src="..." as it is
_LIBRARY_PATH = re.compile(r"^(?:https?://[A-Za-z0-9.\-\[\]:@%_~!$&()*+,;=]+)?[A-Za-z0-9_.~%/-]*$")

#: Recruitment platforms: the URL parameter of the participant's id, and the others they add to the
#: study link, recorded in the data (Prolific's and MTurk's documented names; SONA's id).
RECRUITMENT = {
    "prolific": ("PROLIFIC_PID", ("STUDY_ID", "SESSION_ID")),
    "sona": ("id", ()),
    "mturk": ("workerId", ("assignmentId", "hitId")),
}


def _whole(value, name, low):
    """A whole number >= low from YAML or a flag's text; ValueError otherwise."""
    if isinstance(value, bool):
        raise ValueError(f"expected a whole number >= {low}, got {value!r}")
    if isinstance(value, str):
        value = value.strip()
        if not re.fullmatch(r"[+-]?\d+", value):
            raise ValueError(f"expected a whole number >= {low}, got {value!r}")
        value = int(value)
    try:  # the library's rule for integers (attneave.stimuli.validate); text above is a flag's
        return as_int(value, name or "value", lo=low)
    except InputError:
        raise ValueError(f"expected a whole number >= {low}, got {value!r}") from None


def _refuse_repeats(values, what):
    """ValueError naming the first value given twice (a practice trial or a condition would count twice)."""
    seen = set()
    for v in values:
        if v in seen:
            raise ValueError(f"{what} {v!r} is given twice; give each once")
        seen.add(v)


class ExperimentOptions(BaseModel):
    """Everything that shapes the experiment page (see docs/experiment.md for the page contract).

    Attributes
    ----------
    title : str
        Page title.
    instructions : str
        Shown before the first trial; blank lines separate paragraphs.
    end_text : str
        Shown on the last screen, above the download link.
    practice : int or list of str
        The first K stimuli of the set (in manifest order) or these stimulus
        ids are practice trials: shown first, in that order, with the same
        task, and not part of the main trials nor of the data file.
    clicks : int or 'done'
        K: every trial takes exactly K clicks. ``'done'``: the participant
        clicks between `min_clicks` and `max_clicks` times and presses Next.
    min_clicks, max_clicks : int
        Bounds for ``clicks: done`` (max: no bound when absent).
    undo : bool
        Offer an Undo button (and Backspace / Z) that removes the last click.
    order : {'random', 'blocked', 'fixed'}
        Main-trial order: shuffled per participant (seeded by the participant
        id, reproducible, see :mod:`attneave.analysis.experiment.order`), blocked by
        condition (block order and trials within blocks shuffled), or the
        manifest's.
    seed : str
        Study seed mixed into the participant's seed; change it to give every
        participant a new order in a new study.
    conditions : list of str, optional
        Only stimuli of these conditions (manifest column ``condition``).
    lists : int
        Counterbalancing: K participant lists by a Latin square over
        conditions (see :func:`attneave.analysis.experiment.order.latin_square_lists`).
    fixation_ms : int
        A fixation cross before each stimulus for this long (0: none).
    iti_ms : int
        Blank inter-trial interval after each trial.
    break_every : int
        A break screen after every N main trials (0: none).
    size_deg : float
        Visual angle of the larger side of the largest image; every image is
        shown at the same scale, so relative sizes are kept. Needs px per
        degree: from `px_per_deg`, the URL, or the card calibration and
        `viewing_distance_cm`.
    size_px : float
        Instead of `size_deg`: the larger side of the largest image in CSS
        pixels (no calibration).
    px_per_deg : float, optional
        A fixed scale (CSS px per degree) for a lab with known screens; skips
        the calibration.
    viewing_distance_cm : float
        Eye-to-screen distance the participant is asked to keep.
    background : str or float
        ``'auto'`` (the grey of the set's images, read from their corner
        pixels), ``'#rrggbb'``, or a grey level in [0, 1].
    submit_url : str, optional
        POST the data here at the end (JSON ``{participant, rows, csv}``).
    participant_param : str
        The URL parameter that carries the participant's id (default
        ``participant``, which the page always reads too), or a platform:
        ``prolific`` (``PROLIFIC_PID``; ``STUDY_ID`` and ``SESSION_ID``
        recorded), ``sona`` (``id``), ``mturk`` (``workerId``;
        ``assignmentId`` and ``hitId`` recorded). See :attr:`recruitment`.
    completion_url : str, optional
        Where the participant is sent once the data are saved (Prolific's
        completion link, SONA's credit link); ``{participant}`` in it is
        replaced by the participant's id (URL-encoded).
    jspsych_path : str
        With the jsPsych page: the folder (beside the page, or a URL) that
        holds ``jspsych.js`` and ``jspsych.css`` (default ``jspsych/``).
    psychopy_units : {'deg', 'pix', 'height'}, optional
        Units of the PsychoPy exports (default: 'deg' with `monitor`, else
        'height'; see :mod:`attneave.analysis.experiment.psyexp`).
    monitor : str, optional
        A monitor of PsychoPy's Monitor Center, by name, for the PsychoPy
        exports (default: PsychoPy's ``testMonitor``).
    """

    model_config = ConfigDict(extra="forbid", validate_assignment=False)
    #: where each setting was given, for messages found later (``'exp.yaml: line 4: conditions'``)
    _origins: dict = PrivateAttr(default_factory=dict)
    #: no size_deg nor size_px was given: the size is the default (or the stimulus set's degrees)
    _size_default: bool = PrivateAttr(default=False)

    title: str = "Points on shapes"
    instructions: str = DEFAULT_INSTRUCTIONS
    end_text: str = "Thank you! The experiment is over."
    practice: Union[int, list[str]] = 0
    clicks: Union[int, Literal["done"]] = 5
    min_clicks: int = Field(default=1, le=MAX_CLICKS)
    max_clicks: Optional[int] = Field(default=None, le=MAX_CLICKS)
    undo: bool = True
    order: Literal["random", "blocked", "fixed"] = "random"
    seed: str = ""
    conditions: Optional[list[str]] = None
    lists: int = Field(default=1, le=MAX_LISTS)
    fixation_ms: int = 500
    iti_ms: int = 300
    break_every: int = 0
    size_deg: Optional[float] = Field(default=None, gt=0, le=90)
    size_px: Optional[float] = Field(default=None, gt=0, le=MAX_SIZE_PX)
    px_per_deg: Optional[float] = Field(default=None, gt=0)
    viewing_distance_cm: float = Field(default=57.0, gt=0)
    background: Union[str, float] = "auto"
    submit_url: Optional[str] = None
    participant_param: str = "participant"
    completion_url: Optional[str] = None
    jspsych_path: str = "jspsych/"
    psychopy_units: Optional[Literal["deg", "pix", "height"]] = None
    monitor: Optional[str] = Field(default=None, pattern=r"^[A-Za-z0-9_][A-Za-z0-9_ .-]{0,63}$")

    @field_validator("practice", mode="before")
    @classmethod
    def _practice(cls, v):
        if isinstance(v, str) and not re.fullmatch(r"\s*\d+\s*", v):
            v = [s.strip() for s in v.split(",") if s.strip()]
        if isinstance(v, (list, tuple)):
            if not all(isinstance(s, str) and s for s in v):
                raise ValueError("expected a number of stimuli or a list of stimulus ids")
            _refuse_repeats(v, "stimulus id")
            return list(v)
        return _whole(v, "practice", 0)

    @field_validator("clicks", mode="before")
    @classmethod
    def _clicks(cls, v):
        if isinstance(v, str) and v.strip().lower() == "done":
            return "done"
        try:
            k = _whole(v, "clicks", 1)
        except ValueError:
            raise ValueError(f"expected a whole number >= 1 or 'done', got {v!r}") from None
        if k > MAX_CLICKS:
            raise ValueError(f"at most {MAX_CLICKS} clicks per trial, got {k}")
        return k

    @field_validator("min_clicks", "lists", mode="before")
    @classmethod
    def _at_least_one(cls, v):
        return _whole(v, "", 1)

    @field_validator("max_clicks", mode="before")
    @classmethod
    def _max_clicks(cls, v):
        return None if v is None else _whole(v, "", 1)

    @field_validator("fixation_ms", "iti_ms", "break_every", mode="before")
    @classmethod
    def _non_negative(cls, v):
        return _whole(v, "", 0)

    @field_validator("conditions", mode="before")
    @classmethod
    def _conditions(cls, v):
        if isinstance(v, str):
            v = [s.strip() for s in v.split(",") if s.strip()]
        if v is not None and (not isinstance(v, list) or not v or not all(isinstance(s, str) for s in v)):
            raise ValueError("expected a non-empty list of condition names")
        if v is not None:
            _refuse_repeats(v, "condition")
        return v

    @field_validator("size_deg", "size_px", "px_per_deg", "viewing_distance_cm", mode="before")
    @classmethod
    def _finite(cls, v):
        # the library's rule (attneave.stimuli.validate): these flags are read as numbers
        # (type=float), so text here is a quoted YAML value, refused like r0: "50" of a batch config;
        # NaN fails every bound, and pydantic would name the bound rather than the NaN
        if v is not None:
            try:
                as_number(v, "value")
            except InputError as exc:
                raise ValueError(str(exc).removeprefix("value: ")) from None
        return v

    @field_validator("background", mode="before")
    @classmethod
    def _background(cls, v):
        if isinstance(v, bool):
            raise ValueError(f"expected 'auto', '#rrggbb' or a grey level in [0, 1], got {v!r}")
        if isinstance(v, str):
            s = v.strip()
            if s == "auto" or _HEX.match(s):
                return s
            try:
                v = float(s)
            except ValueError:
                raise ValueError(f"expected 'auto', '#rrggbb' or a grey level in [0, 1], got {v!r}") from None
        if isinstance(v, (int, float)) and 0 <= float(v) <= 1:
            return float(v)
        raise ValueError(f"expected 'auto', '#rrggbb' or a grey level in [0, 1], got {v!r}")

    @field_validator("participant_param")
    @classmethod
    def _param(cls, v):
        if v.strip().lower() in RECRUITMENT:
            return v.strip().lower()
        if not _PARAM.match(v):
            raise ValueError(f"expected a URL parameter's name (letters, digits, _ . -; PROLIFIC_PID, workerId) "
                             f"or one of {', '.join(RECRUITMENT)}, got {v!r}")
        return v

    @field_validator("jspsych_path")
    @classmethod
    def _library_path(cls, v):
        if not v.strip() or not _LIBRARY_PATH.match(v) or "//" in v.split("://", 1)[-1]:
            raise ValueError(f"expected a folder beside the page (jspsych/, lib/jspsych-8/) or an http(s) URL, "
                             f"without quotes, spaces or '//', got {v!r}")
        return v if v.endswith("/") else v + "/"

    @field_validator("submit_url", "completion_url")
    @classmethod
    def _url(cls, v):
        # '//host/x' and '/\\host/x' are paths to a browser's eye only: it sends them to another origin
        if v is not None and not (_ABSOLUTE_URL.match(v) or (_RELATIVE_URL.match(v) and "//" not in v
                                                             and "\\" not in v)):
            raise ValueError(f"expected an http(s) URL (https://host/path) or a path on the same host without "
                             f"'//' or '\\' (/collect, ./save.php), got {v!r}")
        return v

    @model_validator(mode="after")
    def _consistent(self):
        given = self.model_fields_set
        if self.size_deg is not None and self.size_px is not None:
            raise ValueError("size_deg and size_px: give one of them, not both")
        if self.size_px is not None and self.px_per_deg is not None:
            raise ValueError("px_per_deg: has no use with size_px (the size is already in pixels)")
        if self.clicks != "done" and given & {"min_clicks", "max_clicks"}:
            raise ValueError("min_clicks and max_clicks apply only with clicks: done")
        if self.max_clicks is not None and self.max_clicks < self.min_clicks:
            raise ValueError(f"max_clicks ({self.max_clicks}) is smaller than min_clicks ({self.min_clicks})")
        if self.size_px is None and self.size_deg is None:
            self.size_deg = DEFAULT_SIZE_DEG
            self._size_default = True
        return self

    @property
    def recruitment(self):
        """(parameter of the id, parameters recorded beside it) of `participant_param`.

        Examples
        --------
        >>> ExperimentOptions(participant_param="prolific").recruitment
        ('PROLIFIC_PID', ('STUDY_ID', 'SESSION_ID'))
        >>> ExperimentOptions(participant_param="workerId").recruitment
        ('workerId', ('assignmentId', 'hitId'))
        >>> ExperimentOptions().recruitment
        ('participant', ())
        """
        p = self.participant_param
        if p in RECRUITMENT:
            return RECRUITMENT[p]
        # a platform's own parameter named directly records the platform's others too
        for param, extra in RECRUITMENT.values():
            if p == param:
                return param, extra
        return p, ()

    @property
    def size_given(self):
        """True when size_deg or size_px was given (False: the default size).

        Examples
        --------
        >>> ExperimentOptions().size_given, ExperimentOptions(size_deg=10).size_given
        (False, True)
        """
        return not self._size_default

    def origin(self, key):
        """Where setting `key` was given, to begin a message about its value.

        ``'--conditions'`` for a flag, ``'exp.yaml: line 4: conditions'`` for
        a key of the config file, the key alone otherwise.

        Examples
        --------
        >>> ExperimentOptions().origin("conditions")
        'conditions'
        """
        return self._origins.get(key, key)

    @property
    def grey(self):
        """The background as ``'#rrggbb'``, or None for ``'auto'``."""
        b = self.background
        if b == "auto":
            return None
        if isinstance(b, float):
            g = round(b * 255)
            return f"#{g:02x}{g:02x}{g:02x}"
        if len(b) == 4:
            return "#" + "".join(c * 2 for c in b[1:]).lower()
        return b.lower()


def _yaml_lines(root):
    """Line (1-based) of each top-level key of a composed YAML mapping, for messages."""
    import yaml

    if not isinstance(root, yaml.MappingNode):
        return {}
    return {getattr(k, "value", None): k.start_mark.line + 1 for k, _ in root.value}


def _read_yaml(path):
    # the batch config's bounded reader: a FIFO, a device, a huge file, deep nesting or an
    # alias bomb ("billion laughs") is refused in one line instead of hanging or exhausting memory
    from attneave.stimuli.batch.config_file import parse_yaml, read_text

    path = Path(path)
    root, data = parse_yaml(read_text(path), path)  # also refuses a key given twice
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise InputError(f"{path}: expected a mapping of settings (key: value), got {type(data).__name__}")
    return data, _yaml_lines(root)


def load_options(config=None, overrides=None):
    """Validate the settings from a YAML file and command-line overrides.

    Parameters
    ----------
    config : str or Path, optional
        YAML file with a mapping of setting names (see
        :class:`ExperimentOptions`) to values; read with a safe loader.
    overrides : dict of str -> object, optional
        Settings given as flags (not None), which replace the file's.

    Returns
    -------
    ExperimentOptions

    Raises
    ------
    InputError
        One line naming the file and line and the key, or the flag, and what
        was expected: an unknown key, a bad value, inconsistent settings.
    """
    data, lines = ({}, {}) if config is None else _read_yaml(config)
    overrides = {k: v for k, v in (overrides or {}).items() if v is not None}
    merged = {**data, **overrides}
    try:
        options = ExperimentOptions(**{str(k): v for k, v in merged.items()})
    except ValidationError as exc:
        raise InputError(_message(exc, config, lines, overrides)) from None
    for key in data:
        line = lines.get(key)
        options._origins[str(key)] = f"{config}:{f' line {line}:' if line else ''} {key}"
    for key in overrides:
        options._origins[key] = f"--{key.replace('_', '-')}"
    return options


def _message(exc, config, lines, overrides):
    """One line for the first validation error, naming the flag or the file, line and key."""
    errors = exc.errors(include_url=False)
    # a typo in a key explains everything else: report it first
    e = min(errors, key=lambda err: err["type"] != "extra_forbidden")
    key = str(e["loc"][0]) if e["loc"] else ""
    msg = str(e["msg"]).removeprefix("Value error, ")
    if e["type"] == "extra_forbidden":
        known = list(ExperimentOptions.model_fields)
        close = difflib.get_close_matches(key, known, n=1)
        msg = "unknown key" + (f" (did you mean {close[0]!r}?)" if close else "") + f"; known keys: {', '.join(known)}"
    if key in overrides:
        return f"--{key.replace('_', '-')}: {msg}"
    if config is None:
        return msg
    if key:
        line = lines.get(key)
        return f"{config}:{f' line {line}:' if line else ''} {key}: {msg}"
    return f"{config}: {msg}"
