"""``attneave spline``: an interpolating spline through points, sampled, with
its curvature and a summary of what it adds between the points."""

from __future__ import annotations

METHOD_CHOICES = ("qic", "cubic", "cubic-natural", "poly2", "poly3", "poly4", "poly5", "lac-g1")


def add_parser(sub):
    p = sub.add_parser(
        "spline",
        help="QIC (G2 clothoid) or polynomial spline through points, with curvature",
        description=(
            "Fit a spline through the points of POINTS.csv (columns x, y in image pixels, y down; "
            "a closed curve must not repeat its first point) and write samples with columns "
            "s, x, y, curvature, segment: s is arc length from the first point (px), curvature is "
            "1/px, positive where a closed curve is convex (for --open, positive for a left turn "
            "on the screen), and segment is the index of the input point at which the sample's "
            "segment starts; every segment's samples include both of its end points. "
            "qic (default): G2 spline of clothoid segments, monotone curvature on every segment. "
            "cubic: periodic cubic (not-a-knot with --open); cubic-natural: natural cubic (--open); "
            "poly2..poly5: interpolating splines of that degree (periodic, or not-a-knot open); "
            "all polynomial splines use chord-length parameters. lac-g1: G1 log-aesthetic spline "
            "(Yoshida-Saito segments, clothoid fallback where no segment exists)."
        ),
    )
    p.add_argument("points", metavar="POINTS.csv")
    p.add_argument("-o", "--output", required=True, metavar="OUT.csv")
    p.add_argument("--method", choices=METHOD_CHOICES, default="qic")
    p.add_argument("--open", action="store_true", help="open curve (default: closed)")
    p.add_argument("--samples", type=int, default=32, metavar="K",
                   help="samples per segment, both ends included (default 32)")
    p.add_argument("--summary", metavar="OUT.json",
                   help="write method, n_points, closed, g2_error, interior_extrema, loops, "
                        "iterations, seconds (and more) as JSON")
    p.add_argument("--alpha", type=float, default=0.0,
                   help="lac-g1 only: log-aesthetic slope alpha (default 0)")
    return p


def _check_points(P, path, closed):
    """One-line errors that name the file and CSV line (header = line 1)."""
    import numpy as np

    from stimuli.errors import InputError

    need = 3 if closed else 2
    if len(P) < need:
        raise InputError(
            f"{path}: a {'closed' if closed else 'open'} spline needs at least {need} points, got {len(P)}"
        )
    nxt = np.concatenate((P[1:], P[:1])) if closed else P[1:]
    same = (nxt == P[: len(nxt)]).all(axis=1)
    if same.any():
        i = int(np.flatnonzero(same)[0])
        j = (i + 1) % len(P)
        if closed and j == 0:
            raise InputError(
                f"{path}: line {i + 2} repeats the first point (line 2); a closed curve must not "
                "repeat its first point at the end"
            )
        raise InputError(f"{path}: lines {i + 2} and {j + 2} are the same point; consecutive points must differ")


def _summary(args, P, sp, curve, closed):
    import math

    from stimuli.curves.metrics import curve_metrics

    m = curve_metrics(curve)
    summary = {
        "method": args.method,
        "n_points": int(len(P)),
        "closed": closed,
        "g2_error": m["g2_error"],
        "interior_extrema": m["interior_extrema"],
        "loops": m["loops"],
        "iterations": int(getattr(sp, "iterations", 0)),
        "seconds": float(sp.seconds),
        "samples_per_segment": int(args.samples),
        "max_abs_curvature": m["max_abs_curvature"],
        "bending_energy": m["bending_energy"],
        "length": m["length"],
        "extrema_per_segment": m["extrema_per_segment"],
    }
    if hasattr(sp, "closure_error"):
        summary["closure_error"] = float(sp.closure_error)
    if hasattr(sp, "fallback_segments"):
        summary["fallback_segments"] = [int(i) for i in sp.fallback_segments]
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in summary.items()}


def run(args):
    import contextlib
    import json

    from stimuli.errors import InputError
    from stimuli.io import atomic_write, read_points, write_table
    from stimuli.curves.splines import fit_spline

    if args.samples < 2:
        raise InputError(f"--samples: expected at least 2 per segment, got {args.samples}")
    closed = not args.open
    P = read_points(args.points)
    _check_points(P, args.points, closed)
    kwargs = {"alpha": args.alpha} if args.method == "lac-g1" else {}
    try:
        sp = fit_spline(P, args.method, closed=closed, **kwargs)
    except InputError as exc:
        raise InputError(f"{args.points}: {exc}") from None
    curve = sp.sample(args.samples)
    summary = _summary(args, P, sp, curve, closed) if args.summary else None
    with contextlib.ExitStack() as stack:
        # open the summary's temporary file first: an unwritable --summary must fail
        # before OUT.csv is renamed into place, so that no half of the output appears
        fh = stack.enter_context(atomic_write(args.summary, "w")) if summary is not None else None
        write_table(curve.table(), args.output, float_format="%.17g")
        if fh is not None:
            json.dump(summary, fh, indent=2)
            fh.write("\n")
    return 0
