"""The experiment's pages: settings embedded as JSON, templates filled in one pass.

``index.html`` (the standalone task, run by ``task.js``) and, with
``--jspsych``, ``jspsych.html`` (the same task as a jsPsych 8 timeline of the
plugin ``attneave-points``, in ``plugin-attneave-points.js``). Both read the
same settings and trial list (:func:`page_config`), embedded in the page so
that it needs no request and runs from ``file://``.
"""

from __future__ import annotations

import json
import re
from importlib import resources

__all__ = ["STATIC", "JSPSYCH_STATIC", "page_config", "render_index", "render_jspsych", "embedded_json",
           "fill_template", "static_file", "write_pages"]

#: The project's own files copied beside every page, and those of the jsPsych page.
STATIC = ("task.js", "task.css")
JSPSYCH_STATIC = ("plugin-attneave-points.js", "attneave-jspsych.js")


def page_config(options, practice, main, background, version, jatos=False):
    """The settings and trial list the page reads (embedded in index.html as JSON).

    Parameters
    ----------
    options : ExperimentOptions
    practice, main : list of Stimulus
    background : str
        ``'#rrggbb'``.
    version : str
    jatos : bool
        The page runs in JATOS (submits through jatos.js).

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
        participant_param=o.recruitment[0],
        record_params=list(o.recruitment[1]),
        completion_url=o.completion_url,
        jatos=jatos,
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
                                    "{{HEAD_SCRIPTS}}": _jatos_script(config),
                                    "{{CONFIG}}": embedded_json(config)})


def _jatos_script(config):
    # JATOS serves its jatos.js beside every component's HTML file; it belongs in the head (JATOS's docs)
    return '<script src="jatos.js"></script>' if config.get("jatos") else ""


def render_jspsych(config, jspsych_path):
    """jspsych.html: the task as a jsPsych 8 timeline, `config` embedded as in :func:`render_index`.

    Parameters
    ----------
    config : dict
        From :func:`page_config`.
    jspsych_path : str
        Folder (ending in ``/``) or URL that holds ``jspsych.js`` and
        ``jspsych.css``; written into the page as it is (validated by
        :class:`~attneave.analysis.experiment.options.ExperimentOptions`).
    """
    import html

    template = _static("jspsych.html").read_text(encoding="utf-8")
    return fill_template(template, {"{{TITLE}}": html.escape(config["title"]),
                                    "{{BACKGROUND}}": config["background"],
                                    "{{JSPSYCH}}": html.escape(jspsych_path, quote=True),
                                    "{{HEAD_SCRIPTS}}": _jatos_script(config),
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


def static_file(name):
    """A file of the package's ``static`` folder (a Traversable)."""
    return _static(name)


def write_pages(directory, config, jspsych_path=None):
    """Write the pages and the project's scripts into `directory` (a new, empty folder being built).

    Parameters
    ----------
    directory : Path
    config : dict
        From :func:`page_config`.
    jspsych_path : str, optional
        Also write the jsPsych page (``jspsych.html``), its plugin and
        timeline, loading jsPsych from this folder or URL.

    Returns
    -------
    list of str
        The pages written (``index.html``, ``jspsych.html``).
    """
    for name in STATIC:
        (directory / name).write_bytes(_static(name).read_bytes())
    (directory / "index.html").write_text(render_index(config), encoding="utf-8")
    pages = ["index.html"]
    if jspsych_path is not None:
        for name in JSPSYCH_STATIC:
            (directory / name).write_bytes(_static(name).read_bytes())
        (directory / "jspsych.html").write_text(render_jspsych(config, jspsych_path), encoding="utf-8")
        pages.append("jspsych.html")
    return pages
