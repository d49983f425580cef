"""``attneave surprisal``: curvature and surprisal at n equally spaced points."""

from __future__ import annotations

#: Largest number of output points: a million rows (~150 MB of CSV) is far more than any
#: contour needs (surprisal peaks are a few per shape); beyond it the run would only
#: exhaust memory or disk.
MAX_POINTS = 1_000_000


def add_parser(sub):
    p = sub.add_parser(
        "surprisal",
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
    from attneave.stimuli.geometry.contour import Contour
    from attneave.stimuli.geometry.information import surprisal
    from attneave.stimuli.io import disk_error_exit
    from attneave.stimuli.tables import write_table

    from attneave.stimuli.io import check_output_spares_inputs
    from attneave.stimuli.tables import read_points

    check_output_spares_inputs(args.output, [args.contour], what="-o")
    closed = not args.open
    pts = read_points(args.contour)
    c = Contour(pts, closed, name=str(args.contour))
    if closed:
        _check_closed_shape(c, args.contour)
    _note_dropped(pts, args.contour, closed)  # after the refusals: one line when refused
    _check_size(args, c)
    r = surprisal(
        c, n=args.n, spacing=args.spacing, model=args.model, A=args.A, b=args.b, bits=args.bits,
        prominence=args.prominence, **({} if args.length_unit is None else {"length_unit": args.length_unit}),
    )
    _check_finite(r)
    try:
        write_table(r.table(), args.output, float_format="%.17g")
    except OSError as exc:  # a full disk: one line, exit 1
        return disk_error_exit('surprisal', args.output, exc)
    return 0


def _check_size(args, contour):
    """Bound the number of output points before anything is allocated."""
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.validate import as_number

    if args.n is not None and not 3 <= args.n <= MAX_POINTS:
        raise InputError(f"-n: must be 3 <= n <= {MAX_POINTS:,} points, got {args.n}")
    if args.spacing is not None:
        spacing = as_number(args.spacing, "--spacing", gt=0)
        n = contour.perimeter / spacing
        if n > MAX_POINTS:
            raise InputError(f"--spacing: {args.spacing:g} px on a contour of {contour.perimeter:.6g} px gives "
                             f"n = {n:.3g} points; n <= {MAX_POINTS:,} (use a larger spacing)")
        least = 1.5 if args.open else 2.5  # round(n) (+ 1, the end point of an open contour) >= 3
        if n < least:
            raise InputError(f"--spacing: {args.spacing:g} px on a contour of {contour.perimeter:.6g} px gives "
                             f"fewer than 3 points (use a spacing below {contour.perimeter / least:.6g} px)")


def _check_finite(result):
    """Refuse a result whose surprisal overflowed (a huge --b on a large contour), rather than write inf."""
    import numpy as np

    from attneave.stimuli.errors import InputError

    u = np.asarray(result.surprisal, dtype=float)
    inner = u if result.params["closed"] else u[1:-1]  # an open curve's ends have no turning angle (NaN)
    if not np.isfinite(inner).all():
        p = result.params
        raise InputError(f"--b {p['b']:g} with ds = {p['ds']:.6g} px: the surprisal overflows (b*ds^2 = "
                         f"{p['b'] * p['ds'] ** 2:.3g}); use a smaller --b or rescale the contour")


def _note_dropped(pts, path, closed):
    """Say on stderr which points the contour drops: consecutive repeats, and a closed
    contour's last point when it repeats the first (common in real data; accepted)."""
    import sys

    import numpy as np

    from attneave.stimuli.tables import read_points

    if len(pts) < 2:
        return
    same = np.flatnonzero((pts[1:] == pts[:-1]).all(axis=1))
    keep = np.ones(len(pts), bool)
    keep[same + 1] = False
    q = pts[keep]
    closing = closed and len(q) > 1 and (q[-1] == q[0]).all()
    if not (len(same) or closing):
        return
    rows = read_points(path, with_lines=True)[1]  # the file again, once, for the lines of the note
    parts = []
    if len(same):
        lines = ", ".join(str(int(rows[i + 1])) for i in same[:5]) + (", ..." if len(same) > 5 else "")
        parts.append(f"{len(same)} point(s) repeating the one before (line(s) {lines})")
    if closing:
        last = int(rows[np.flatnonzero(keep)[-1]])
        parts.append(f"the last point (line {last}), which repeats the first (a closed contour joins "
                     "its last point to its first)")
    print(f"attneave surprisal: note: {path}: dropped " + " and ".join(parts), file=sys.stderr)


def _check_closed_shape(contour, path):
    """A closed contour's curvature sign (convex +, concave -) needs a simple curve of positive area.

    The area is checked where every closed `Contour` is made (the same rule for the library and
    this command: :func:`attneave.stimuli.validate.check_area`); simplicity here, since the
    library accepts a figure eight.
    """
    from attneave.stimuli.errors import InputError

    if not contour.is_simple():
        x, y = contour.self_intersections()[0]
        raise InputError(f"{path}: the closed contour crosses itself near (x={x:.6g}, y={y:.6g}); the sign of "
                         "its curvature (convex +, concave -) needs a simple curve (use --open to treat it as "
                         "an open curve)")
