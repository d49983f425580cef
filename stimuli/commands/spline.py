"""``attneave spline``: an interpolating spline through points, sampled, with
its curvature and a summary of what it adds between the points."""

from __future__ import annotations

METHOD_CHOICES = ("qic", "qic-g2", "cubic", "cubic-natural", "poly2", "poly3", "poly4", "poly5", "lac-g1", "lac")


def add_parser(sub):
    from attneave.stimuli.commands.counts import MAX_ROWS, count
    from attneave.stimuli.commands.examples import ExamplesFormatter, examples

    p = sub.add_parser(
        "spline",
        epilog=examples('attneave spline points.csv -o spline.csv', 'attneave spline points.csv -o spline.csv --method lac --summary fit.json', 'attneave spline polyline.csv -o open.csv --open --samples 400'),
        formatter_class=ExamplesFormatter,
        help="QIC (clothoid), log-aesthetic or polynomial spline through points, with curvature",
        description=(
            "Fit a spline through the points of POINTS.csv (columns x, y in image pixels, y down; "
            "a closed curve's last point may repeat its first: it is then dropped, with a note on "
            "stderr; consecutive points must differ and may not double back exactly) and write samples with columns "
            "s, x, y, curvature, segment: s is arc length from the first point (px), curvature is "
            "1/px, positive where a closed curve is convex (for --open, positive for a left turn "
            "on the screen), and segment is the index of the input point at which the sample's "
            "segment starts; every segment's samples include both of its end points. "
            "qic (default): clothoid segments (monotone curvature on every segment), G2 except at "
            "the few nodes where the G2 spline would loop, swing out or cross itself: there the "
            "tangent is held at the bisector of the polygon's turn (G1) or, at sharp turns or "
            "where that is not enough, the curve has a corner (G0); every such node is listed in "
            "the summary's corners. Where the clothoid curve strays from the periodic cubic through "
            "the points and arcs of a log-aesthetic curve (alpha = -0.3, the same joints, monotone "
            "curvature) stray less, those arcs are used: the summary's alpha says which (-1: clothoids). "
            "qic-g2: the pure G2 clothoid spline (may loop). "
            "cubic: periodic cubic (not-a-knot with --open); cubic-natural: natural cubic (--open); "
            "poly2..poly5: interpolating splines of that degree (periodic, or not-a-knot open); "
            "all polynomial splines use chord-length parameters. lac-g1: G1 log-aesthetic spline "
            "(Yoshida-Saito segments, clothoid fallback where no segment exists). lac: G2 log-aesthetic "
            "spline (every segment a log-aesthetic arc of slope --alpha, monotone curvature, G2 at every "
            "point; alpha -1 is the pure G2 clothoid spline; alpha >= 0 has no inflection and needs points "
            "turning one way). A curve that crosses itself "
            "or has a segment turning by more than pi gets a warning on stderr naming the "
            "segments (--strict: exit 1, nothing written)."
        ),
    )
    p.add_argument("points", metavar="POINTS.csv")
    p.add_argument("-o", "--output", required=True, metavar="OUT.csv")
    p.add_argument("--method", choices=METHOD_CHOICES, default="qic")
    p.add_argument("--open", action="store_true", help="open curve (default: closed)")
    p.add_argument("--samples", type=count(2), default=32, metavar="K",
                   help=f"samples per segment, both ends included (default 32); at most {MAX_ROWS} "
                        "rows in all")
    p.add_argument("--summary", metavar="OUT.json",
                   help="write (to a file other than POINTS.csv and OUT.csv) method, n_points, closed, g2_error, interior_extrema, loops, corners, "
                        "corner_kinds, self_intersections, max_segment_turn, iterations, seconds, "
                        "alpha (and more) as JSON")
    p.add_argument("--strict", action="store_true",
                   help="exit 1 and write nothing when the curve crosses itself or a segment turns "
                        "by more than pi")
    p.add_argument("--alpha", type=float, default=None,
                   help="lac-g1 and lac only (refused with other methods): log-aesthetic slope alpha "
                        "(default 0 for lac-g1, -1 for lac)")
    return p


def run(args):
    import contextlib
    import json
    import os
    import sys

    from attneave.stimuli.commands.counts import MAX_ROWS
    from attneave.stimuli.curves.spline_file import spline_of_file
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.io import atomic_write, check_output_spares_inputs
    from attneave.stimuli.tables import write_table

    check_output_spares_inputs(args.output, [args.points], what="-o")
    if args.summary is not None:
        check_output_spares_inputs(args.summary, [args.points], what="--summary")
        if os.path.realpath(args.summary) == os.path.realpath(args.output):
            raise InputError(f"--summary {args.summary}: is the same file as -o {args.output} (the JSON would "
                             "replace the curve); choose another file")
    fit = spline_of_file(args.points, args.method, closed=not args.open, samples=args.samples, alpha=args.alpha,
                         max_rows=MAX_ROWS, summary=args.summary is not None)
    if fit.problem:
        what = "error" if args.strict else "warning"
        print(f"attneave spline: {what}: {fit.problem}" + (" ; nothing written (--strict)" if args.strict else ""),
              file=sys.stderr)
        if args.strict:
            return 1
    for note in fit.notes:
        print(f"attneave spline: note: {note}", file=sys.stderr)
    with contextlib.ExitStack() as stack:
        # open the summary's temporary file first: an unwritable --summary must fail
        # before OUT.csv is renamed into place, so that no half of the output appears
        fh = stack.enter_context(atomic_write(args.summary, "w")) if fit.summary is not None else None
        write_table(fit.table, args.output, float_format="%.17g")
        if fh is not None:
            json.dump(fit.summary, fh, indent=2)
            fh.write("\n")
    return 0
