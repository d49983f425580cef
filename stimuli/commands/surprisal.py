"""``attneave surprisal``: curvature and surprisal at n equally spaced points."""

from __future__ import annotations

#: Largest number of output points: a million rows (~150 MB of CSV) is far more than any
#: contour needs (surprisal peaks are a few per shape); beyond it the run would only
#: exhaust memory or disk.
MAX_POINTS = 1_000_000


def add_parser(sub):
    from attneave.stimuli.commands.examples import ExamplesFormatter, examples

    p = sub.add_parser(
        "surprisal",
        epilog=examples('attneave surprisal out/polygons/contours/attneave_000_000_polygon.csv -o surprisal.csv', 'attneave surprisal contour.csv -o surprisal.csv -n 200 --model vonmises', 'attneave surprisal contour.csv -o surprisal.csv --spacing 2 --bits'),
        formatter_class=ExamplesFormatter,
        help="curvature and surprisal along a contour",
        description=(
            "Resample a contour (CSV with columns x, y in image pixels, y down) at n equally "
            "spaced points from its first point and write, per point: i, s, t, x, y, "
            "turning_angle, curvature, surprisal, peak, length_unit. Curvature is positive on convex "
            "parts. With --model paper, surprisal = -ln A - b*ds^2*cos(turning_angle - 2*pi/n) "
            "(eq. 5; eq. 4 with --open), ds = L/n in the --length-unit."
        ),
    )
    p.add_argument("contour", metavar="CONTOUR.csv")
    p.add_argument("-o", "--output", required=True, metavar="OUT.csv")
    g = p.add_mutually_exclusive_group()
    g.add_argument("-n", type=int, default=None,
                   help=f"number of equally spaced points, 3..{MAX_POINTS:,} (default 100)")
    g.add_argument("--spacing", type=float, default=None, metavar="PX",
                   help=f"spacing in pixels instead of -n (giving at most {MAX_POINTS:,} points)")
    p.add_argument("--model", choices=("paper", "vonmises"), default="paper")
    p.add_argument("--A", type=float, default=0.25, help="A' of the paper's form (default 0.25)")
    p.add_argument("--b", type=float, default=None, help="concentration b (default 1 paper, 4 vonmises)")
    p.add_argument("--open", action="store_true", help="the contour is open (eq. 4, mean turn 0)")
    p.add_argument("--bits", action="store_true", help="surprisal in bits instead of nats")
    # the choices mirror attneave.stimuli.geometry.information.LENGTH_UNITS (not imported here: --help stays fast)
    p.add_argument("--length-unit", choices=("sample", "perimeter", "radius", "px"), default=None,
                   help="unit of ds in eq. 4-5: sample (ds = 1, default), perimeter (ds = 1/n), radius of the "
                        "equal-area circle (all three scale-free), or px (the paper's literal pixels)")
    p.add_argument("--prominence", type=float, default=None, help="peak prominence (default 5%% of the range)")
    return p


def run(args):
    import sys

    from attneave.stimuli.geometry.surprisal_file import surprisal_of_file
    from attneave.stimuli.io import check_output_spares_inputs, disk_error_exit
    from attneave.stimuli.tables import write_table

    check_output_spares_inputs(args.output, [args.contour], what="-o")
    r, note = surprisal_of_file(
        args.contour, n=args.n, spacing=args.spacing, closed=not args.open, max_points=MAX_POINTS,
        model=args.model, A=args.A, b=args.b, bits=args.bits, prominence=args.prominence,
        **({} if args.length_unit is None else {"length_unit": args.length_unit}),
    )
    if note:
        print(f"attneave surprisal: note: {args.contour}: {note}", file=sys.stderr)
    try:
        write_table(r.table(), args.output, float_format="%.17g")
    except OSError as exc:  # a full disk: one line, exit 1
        return disk_error_exit('surprisal', args.output, exc)
    return 0
