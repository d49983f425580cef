"""``attneave analyze``: participants' clicks against the information predicted along contours."""

from __future__ import annotations


def add_parser(sub):
    from attneave.stimuli.commands.examples import ExamplesFormatter, examples

    p = sub.add_parser(
        "analyze",
        epilog=examples('attneave analyze attneave_P*.csv --stimuli out/polygons -o results', 'attneave analyze jspsych_data.json --stimuli out/polygons -o results --trial-type attneave-points', 'attneave analyze clicks.csv --stimuli out/polygons -o results --columns participant=subj,stimulus_id=stim'),
        formatter_class=ExamplesFormatter,
        help="test clicks on contours against predicted surprisal",
        description=(
            "Map every click of CLICKS.csv (columns participant, stimulus_id, x, y; others kept) to the "
            "nearest point of its stimulus's contour in the stimulus set DIR (manifest.csv + contours/*.csv; "
            "images optional), and test whether clicks favour high-surprisal points: ML fit of "
            "p(j) ~ exp(beta*z_j) over n equally spaced points (z = standardised surprisal) with rivals, "
            "per-participant mean z tested across participants (t statistic calibrated by Monte Carlo under "
            "uniform clicking, one-sided), Spearman correlation of click density "
            "with surprisal against circular shifts, peak hit rate, AUC, concave vs convex share. "
            "Writes OUT/clicks.csv (every row, with excluded and reason), per_stimulus.csv, "
            "per_participant.csv, models.csv, summary.json, figures/ and report.html; OUT appears "
            "complete or not at all."
        ),
    )
    p.add_argument("clicks", metavar="CLICKS.csv", nargs="+",
                   help="click file(s), e.g. one per participant as the experiment writes them (attneave_*.csv); "
                        "read one by one and pooled, with a column source_file in clicks.csv")
    p.add_argument("--stimuli", required=True, metavar="DIR", help="stimulus-set directory (manifest.csv)")
    p.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="output directory (new or empty; an earlier analysis is replaced with --force); it may not be an input, hold an input "
                        "(CLICKS.csv, DIR) or be the working directory")
    p.add_argument("-n", type=int, default=100, help="equally spaced points per contour (default 100)")
    p.add_argument("--model", choices=("paper", "vonmises"), default="paper", help="surprisal model (default paper)")
    p.add_argument("--coords", choices=("image", "centered", "pix", "height", "norm"), default="image",
                   help="image: pixels, origin top-left, y down (default); centered or pix: PsychoPy 'pix', "
                        "origin at the image centre, y up; height, norm: PsychoPy's window units (image at "
                        "the window centre; need --window-size)")
    p.add_argument("--window-size", default=None, metavar="W,H",
                   help="window size in pixels, for --coords height or norm")
    p.add_argument("--scale", type=float, default=1.0, help="shown image size / image size (default 1)")
    p.add_argument("--columns", default=None, metavar="MAP",
                   help="column names, e.g. participant=subj,stimulus_id=stim,x=mouse_x,y=mouse_y; the "
                        "stimulus column may hold ids, image file names or image paths")
    p.add_argument("--sep", default=None, metavar="SEP",
                   help="field separator of CLICKS.csv: ',', ';', 'tab' or '|' (default: found from the header)")
    p.add_argument("--trial-type", default=None, metavar="NAME",
                   help="jsPsych data: the trial_type whose rows hold the clicks (default attneave-points, or the "
                        "only one whose rows hold clicks); rows of other types are set aside and counted")
    p.add_argument("--decimal", choices=(".", ","), default=None, metavar="{.|,}",
                   help="decimal mark of x and y (default: ',' when values look like 12,5)")
    p.add_argument("--tolerance", type=float, default=None, metavar="PX",
                   help="exclude clicks farther than PX from the contour (default 5%% of the image diagonal)")
    p.add_argument("--bandwidth", type=float, default=None, metavar="PX",
                   help="click-density kernel sd in px of arc length (default 2%% of the perimeter)")
    p.add_argument("--peak-tolerance", type=float, default=None, metavar="PX",
                   help="arc length within which a click hits a peak (default 2%% of the perimeter)")
    p.add_argument("--permutations", type=int, default=1000, metavar="K",
                   help="circular shifts per stimulus for the correlation null (default 1000)")
    p.add_argument("--grid", type=int, default=1024, metavar="M",
                   help="positions along the contour for density and correlation (default 1024)")
    p.add_argument("--click-sd", type=float, default=None, metavar="PX",
                   help="localisation error of clicks along the contour (sd, px) built into the pooled fit of "
                        "beta; without it beta_hat is attenuated by click noise")
    p.add_argument("--group-simulations", type=int, default=1999, metavar="R",
                   help="Monte Carlo replicates of the null of the group and items tests: each used click is "
                        "redrawn uniformly along its contour (default 1999; smallest p = 1/(R+1); 0 skips)")
    p.add_argument("--seed", type=int, default=0,
                   help="seed of the Monte Carlo nulls (mean correlation, group and items tests; default 0)")
    p.add_argument("--predictors", default="surprisal", metavar="P1,P2,...",
                   help="predictors fitted jointly, with a likelihood-ratio test of each against the model without "
                        "it: surprisal, abs_curvature, concavity (minima rule), convexity, extremum_proximity "
                        "(Attneave's points), medial_axis (skeleton salience); default surprisal")
    p.add_argument("--length-unit", default=None, metavar="UNIT",
                   help="unit of arc length of the surprisal model, passed to the library (default: its default); "
                        "recorded in summary.json")
    p.add_argument("--models", default=None, metavar="M1,M2,...",
                   help="models to run: choice (always), rivals, joint, blurred (with --click-sd), mixed, group "
                        "(the Monte Carlo nulls); default all that fit in memory. summary.json (models_skipped) "
                        "and report.html say which were left out and why")
    p.add_argument("--workers", type=int, default=1, metavar="N",
                   help="local processes for the predictions, a few ms per stimulus (default 1; the results are "
                        "the same for any N)")
    p.add_argument("--quiet", action="store_true",
                   help="no progress on stderr (by default every stage over ~2 s is a line there, and a bar "
                        "is drawn on a terminal)")
    p.add_argument("--no-figures", action="store_true", help="skip the figures (report.html keeps the tables)")
    p.add_argument("--force", action="store_true",
                   help="replace OUT if it is an earlier analysis output (it holds summary.json and only files "
                        "analyze writes); a directory holding anything else is refused, never deleted")
    return p


def run(args):
    import sys

    from attneave.analysis.analyze import analyze
    from attneave.analysis.clicks.exclusions import exclusion_report, resolve_stimulus_ids
    from attneave.analysis.clicks.files import participants_in_several_files, read_click_files, repeated_rows
    from attneave.analysis.clicks.read import WINDOW_UNITS, parse_window_size, window_units_to_pixels
    from attneave.analysis.report.outputs import check_output_dir, write_analysis
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.stimulus_set import read_stimulus_set

    # everything that can be wrong with the inputs is found before anything is written; first that
    # OUT (replaced whole) is neither an input, nor holds one, nor is the working directory
    check_output_dir(args.output, args.force, (*args.clicks, args.stimuli))
    from attneave.stimuli.progress import Stages

    with Stages("analyze", quiet=args.quiet, bar=False) as reading:  # the timer ends with an error too
        reading.stage("reading clicks")
        clicks = read_click_files(args.clicks, columns=args.columns, sep=args.sep, decimal=args.decimal,
                                  trial_type=args.trial_type)
        set_aside = dict(clicks.attrs.get("set_aside", {}))  # rows that are no click of the task (layouts.py)
        if "psychopy-builder" in clicks.attrs.get("layout", "") and (args.coords != "image" or args.scale != 1.0):
            raise InputError("--coords/--scale: a PsychoPy Builder data file of attneave's export is converted to "
                             "image pixels with its conditions' sizes; leave --coords and --scale out")
        window, coords = parse_window_size(args.window_size), args.coords
        if coords in WINDOW_UNITS:  # the analysis maps pixels from the window centre
            clicks, coords = window_units_to_pixels(clicks, coords, window), "centered"
        elif window is not None:
            raise InputError(f"--window-size is for --coords {' or '.join(WINDOW_UNITS)}, not --coords {coords}")
        reading.stage("reading the stimulus set")
        stimset = read_stimulus_set(args.stimuli)
        clicks = resolve_stimulus_ids(clicks, stimset)
    res = analyze(
        clicks, stimset, n=args.n, model=args.model, coords=coords, scale=args.scale,
        tolerance=args.tolerance, bandwidth=args.bandwidth, peak_tolerance=args.peak_tolerance,
        permutations=args.permutations, grid=args.grid, seed=args.seed, click_sd=args.click_sd,
        group_simulations=args.group_simulations, predictors=args.predictors, length_unit=args.length_unit,
        models=args.models, quiet=args.quiet, workers=args.workers,
    )
    if res.summary["n_used"] == 0:
        why = exclusion_report(res.clicks, threshold=0.0)
        print(f"attneave analyze: error: no usable click, nothing analysed or written: {why}", file=sys.stderr)
        return 1
    res.summary["params"].update(coords=args.coords, window_size=list(window) if window else None,
                                 trial_type=args.trial_type)
    res.summary["rows_set_aside"] = set_aside
    for warning in (participants_in_several_files(clicks), repeated_rows(clicks)):  # analyze() adds the exclusions
        if warning:
            res.summary["warnings"].append(warning)
    click_files = args.clicks[0] if len(args.clicks) == 1 else list(args.clicks)
    with Stages("analyze", quiet=args.quiet, bar=False) as stages:
        stages.stage("writing tables" + ("" if args.no_figures else ", figures") + " and report")
        write_analysis(res, args.output, figures=not args.no_figures, force=args.force,
                       inputs=dict(clicks=click_files, stimuli=args.stimuli))
    from attneave.analysis.report.html import t_text

    s = res.summary
    g = s["group"]

    def f(v):
        return "n/a" if v is None else f"{v:.4g}"

    reasons = ", ".join(f"{k} {v}" for k, v in s["exclusions"].items() if v)
    print(
        f"{s['n_clicks']} clicks, {s['n_used']} used, {s['n_excluded']} excluded"
        + (f" ({reasons})" if reasons else "")
        + (f"; beta_hat = {f(s['beta_hat'])} (the search bound, not an estimate)" if s.get("beta_at_bound") else
           f"; beta_hat = {f(s['beta_hat'])} [{f(s['beta_ci'][0])}, {f(s['beta_ci'][1])}]")
        + f"; group t = {t_text(g, 4) if g['statistic'] is None else f(g['statistic'])} ({g['n']} participants), "
        + f"Monte Carlo p = {f(g['p_value'])} "
        + f"(one-sided, R = {g['simulations']}); wrote {args.output}",
        file=sys.stdout,
    )
    if set_aside:
        rows = ", ".join(f"{k}: {v}" for k, v in set_aside.items())
        print(f"attneave analyze: rows set aside, no clicks of the task (not counted as excluded): {rows}",
              file=sys.stderr)
    for w in s["warnings"]:
        print(f"attneave analyze: warning: {w}", file=sys.stderr)
    return 0
