"""``attneave experiment``: a self-contained browser experiment that collects clicks on a stimulus set."""

from __future__ import annotations

EXAMPLES = (
    "attneave experiment out/polygons -o out/exp --config configs/experiment.yaml",
    "attneave experiment out/polygons -o out/exp_prolific --jspsych --jatos --participant-param prolific \\\n"
    "  --completion-url 'https://app.prolific.com/submissions/complete?cc=C1A2B3'",
    "attneave experiment out/polygons -o out/exp_lab --psychopy --monitor labMonitor --practice 2",
)


def _flag(p, name, **kw):
    # every setting is also a YAML key (dashes -> underscores); None means "not given"
    p.add_argument(f"--{name}", default=None, dest=name.replace("-", "_"), **kw)


def add_parser(sub):
    from attneave.stimuli.commands.examples import ExamplesFormatter, examples

    p = sub.add_parser(
        "experiment",
        help="write a browser experiment (and optionally a PsychoPy script) that collects clicks",
        description=(
            "Write DIR/index.html with task.js, task.css and copies of the set's images: a point-selection "
            "experiment that runs from file:// or any static host (JATOS, Pavlovia, a web server) and gives "
            "each participant a CSV of clicks in image pixels that 'attneave analyze' reads as it is. "
            "Settings come from --config YAML (keys = the flags' names with underscores) and flags, which "
            "win. See docs/experiment.md for the page contract (URL parameters, element ids)."
        ),
        epilog=examples(*EXAMPLES),
        formatter_class=ExamplesFormatter,
    )
    p.add_argument("stimuli", metavar="SET", help="stimulus-set directory (manifest.csv, images/, contours/)")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="experiment directory to write")
    p.add_argument("--config", default=None, metavar="EXP.yaml", help="YAML file of settings (see configs/experiment.yaml)")
    _flag(p, "title", metavar="TEXT")
    _flag(p, "instructions", metavar="TEXT", help="instructions shown before the first trial")
    _flag(p, "end-text", metavar="TEXT")
    _flag(p, "practice", metavar="K|ID,ID", help="practice trials: the first K stimuli or these ids (default 0)")
    _flag(p, "clicks", metavar="K|done", help="K clicks per stimulus, or 'done': until Next (default 5)")
    _flag(p, "min-clicks", metavar="N", help="with --clicks done: fewest clicks (default 1)")
    _flag(p, "max-clicks", metavar="N", help="with --clicks done: most clicks (default none)")
    p.add_argument("--no-undo", dest="undo", action="store_const", const=False, default=None,
                   help="no Undo button (default: Undo, Backspace and Z remove the last click)")
    _flag(p, "order", choices=("random", "blocked", "fixed"),
          help="random per participant (seeded by the id; default), blocked by condition, or manifest order")
    _flag(p, "seed", metavar="TEXT", help="study seed mixed into each participant's order (default '')")
    _flag(p, "conditions", metavar="C,C", help="only stimuli of these conditions")
    _flag(p, "lists", metavar="K", help="K counterbalanced participant lists (Latin square over conditions; default 1)")
    _flag(p, "fixation-ms", metavar="MS", help="fixation cross before each stimulus (default 500; 0: none)")
    _flag(p, "iti-ms", metavar="MS", help="blank inter-trial interval (default 300)")
    _flag(p, "break-every", metavar="N", help="a break screen every N trials (default 0: none)")
    _flag(p, "size-deg", type=float, metavar="DEG",
          help="visual angle of the largest image's larger side (default 10; needs calibration or --px-per-deg)")
    _flag(p, "size-px", type=float, metavar="PX", help="instead of --size-deg: that side in CSS pixels")
    _flag(p, "px-per-deg", type=float, metavar="F", help="fixed CSS px per degree (skips the card calibration)")
    _flag(p, "viewing-distance-cm", type=float, metavar="CM", help="viewing distance (default 57)")
    _flag(p, "background", metavar="auto|#rrggbb|G", help="page colour (default auto: the images' ground)")
    _flag(p, "submit-url", metavar="URL", help="POST the data as JSON {participant, rows, csv} at the end")
    _flag(p, "participant-param", metavar="NAME",
          help="URL parameter of the participant's id (default participant), or prolific (PROLIFIC_PID; "
               "STUDY_ID and SESSION_ID recorded), sona (id), mturk (workerId; assignmentId and hitId recorded)")
    _flag(p, "completion-url", metavar="URL",
          help="send the participant here once the data are saved or submitted (Prolific's completion link); "
               "{participant} in it is replaced by the id")
    p.add_argument("--jspsych", action="store_true",
                   help="also write DIR/jspsych.html: the task as a jsPsych 8 timeline of the plugin "
                        "attneave-points (plugin-attneave-points.js); jsPsych itself is the lab's (--jspsych-path)")
    _flag(p, "jspsych-path", metavar="DIR/|URL",
          help="with --jspsych: folder beside the page, or URL, holding jspsych.js and jspsych.css "
               "(default jspsych/)")
    p.add_argument("--jatos", action="store_true",
                   help="the pages submit through JATOS's jatos.js (no download) and DIR/attneave_<DIR>.jzip is "
                        "written, a study archive JATOS imports")
    p.add_argument("--psychopy", action="store_true",
                   help="also write DIR/psychopy/: a PsychoPy Builder experiment (attneave_task.psyexp, which "
                        "PsychoPy compiles for Pavlovia too), a Coder script (attneave_task.py), conditions.csv "
                        "and images/")
    _flag(p, "psychopy-units", choices=("deg", "pix", "height"),
          help="units of the PsychoPy exports (default: deg with --monitor, else height)")
    _flag(p, "monitor", metavar="NAME", help="with --psychopy: a monitor of PsychoPy's Monitor Center, by name "
          "(default testMonitor); its width, distance and resolution give the 'deg' units")
    p.add_argument("--force", action="store_true",
                   help="DIR exists with other content: move it aside to DIR.old-N (nothing is deleted)")
    return p


_SETTINGS = ("title", "instructions", "end_text", "practice", "clicks", "min_clicks", "max_clicks", "undo", "order",
             "seed", "conditions", "lists", "fixation_ms", "iti_ms", "break_every", "size_deg", "size_px",
             "px_per_deg", "viewing_distance_cm", "background", "submit_url", "psychopy_units", "monitor",
             "participant_param", "completion_url", "jspsych_path")


def run(args):
    from attneave.analysis.experiment.build import build_experiment
    from attneave.analysis.experiment.options import load_options
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.io import check_output_spares_inputs
    from attneave.stimuli.stimulus_set import read_stimulus_set

    check_output_spares_inputs(args.output, [args.stimuli, args.config])
    options = load_options(args.config, {k: getattr(args, k) for k in _SETTINGS})
    # the flag asks for the export; a config's key is a setting kept for when it is made (the shipped
    # configs/experiment.yaml has one and serves runs with and without --psychopy)
    for flag in ("psychopy_units", "monitor"):
        if not args.psychopy and getattr(args, flag) is not None:
            raise InputError(f"--{flag.replace('_', '-')}: applies only to the PsychoPy export; add --psychopy "
                             "(or leave it out)")
    if not args.jspsych and args.jspsych_path is not None:
        raise InputError("--jspsych-path: applies only to the jsPsych page; add --jspsych (or leave it out)")
    if args.jatos and options.submit_url is not None:
        raise InputError(f"{options.origin('submit_url')}: with --jatos the data go to JATOS; leave submit_url out")
    stimset = read_stimulus_set(args.stimuli)
    res = build_experiment(stimset, args.output, options, psychopy=args.psychopy, force=args.force,
                           jspsych=args.jspsych, jatos=args.jatos)
    if res["moved_aside"] is not None:
        print(f"attneave experiment: the old {args.output} is now {res['moved_aside']}")
    if args.psychopy:
        import csv
        import sys

        from attneave.analysis.experiment.psychopy import mixed_columns

        with open(res["out"] / "psychopy" / "conditions.csv", newline="", encoding="utf-8") as fh:
            warning = mixed_columns(list(csv.DictReader(fh)))
        if warning:
            print(f"attneave experiment: warning: {warning}", file=sys.stderr)
    lists = f", {res['lists']} lists" if res["lists"] > 1 else ""
    print(f"{res['stimuli']} trials + {res['practice']} practice{lists}, background {res['background']} -> "
          f"{res['out']}/" + " and ".join(res["pages"] + (["psychopy/"] if args.psychopy else [])
                                         + ([res["jzip"]] if res["jzip"] else [])))
    return 0
