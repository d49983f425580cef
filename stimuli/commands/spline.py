"""``attneave spline``: an interpolating spline through points, sampled, with
its curvature and a summary of what it adds between the points."""

from __future__ import annotations

METHOD_CHOICES = ("qic", "qic-g2", "cubic", "cubic-natural", "poly2", "poly3", "poly4", "poly5", "lac-g1", "lac")


def add_parser(sub):
    from attneave.stimuli.commands.counts import MAX_ROWS, count

    p = sub.add_parser(
        "spline",
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


def _check_points(P, path, closed):
    """One-line errors that name the file and the CSV lines of the rows at fault."""
    import numpy as np

    from attneave.stimuli.errors import InputError
    from attneave.stimuli.tables import read_points  # again, for the lines of a message

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
        lines = read_points(path, with_lines=True)[1]
        raise InputError(f"{path}: lines {lines[i]} and {lines[j]} are the same point; consecutive points must differ")
    # a polygon that turns back on itself (edges in and out antiparallel) makes every smooth
    # curve through it stop and reverse there: a cusp, where curvature is undefined (a closed
    # curve through collinear points always does this)
    inner = np.arange(len(P)) if closed else np.arange(1, len(P) - 1)
    if len(inner):
        with np.errstate(all="ignore"):  # huge coordinates: edges as unit vectors (half-differences)
            d_in = 0.5 * P - 0.5 * np.roll(P, 1, axis=0)
            d_out = 0.5 * np.roll(P, -1, axis=0) - 0.5 * P
            a, b = d_in[inner], d_out[inner]
            a = a / np.hypot(a[:, 0], a[:, 1])[:, None]
            b = b / np.hypot(b[:, 0], b[:, 1])[:, None]
            cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
            dot = (a * b).sum(axis=1)
            back = (dot < 0) & (np.abs(cross) <= 1e-12)
        if back.any():
            i = int(inner[np.flatnonzero(back)[0]])
            what = " (all the points lie on one line)" if closed and _collinear(P) else ""
            line = read_points(path, with_lines=True)[1][i]
            raise InputError(
                f"{path}: line {line}: the points double back here (the polygon turns by 180 degrees)"
                f"{what}; a smooth curve through them has a cusp, where curvature is undefined"
            )


def _collinear(P):
    import numpy as np

    with np.errstate(all="ignore"):
        c = P - P.mean(axis=0)
        c = c / np.abs(c).max()
        sv = np.linalg.svd(c, compute_uv=False) if np.all(np.isfinite(c)) else np.ones(2)
    return bool(sv[-1] <= 1e-12 * sv[0])


def _drop_closing_repeat(P, path, closed):
    """A closed curve's file that ends on its first point (common in real data): drop that
    last point and say so in one line (the segment indices of the others are unchanged)."""
    import sys

    from attneave.stimuli.tables import read_points  # again, for the lines of the note

    if closed and len(P) > 1 and (P[-1] == P[0]).all():
        lines = read_points(path, with_lines=True)[1]
        print(f"attneave spline: note: {path}: line {lines[-1]} repeats the first point (line {lines[0]}); "
              "dropped it (a closed curve joins its last point to its first)", file=sys.stderr)
        return P[:-1]
    return P


def _frame(P, path):
    """Centre and scale of the frame the fit runs in. Points of ordinary size
    are fitted as they are (centre 0, scale 1); points spanning less than
    1e-4 or more than 1e150 px, or lying more than 1e8 spans from the origin,
    are moved to the origin and scaled by a power of two to a span of about 1,
    so that neither curvature nor arc length overflows (the curve is the same)."""
    import numpy as np

    from attneave.stimuli.errors import InputError

    lo, hi = P.min(axis=0), P.max(axis=0)
    with np.errstate(over="ignore", invalid="ignore"):
        centre = 0.5 * lo + 0.5 * hi
        span = float(np.max(0.5 * hi - 0.5 * lo)) * 2.0
    if not np.isfinite(span) or span > 1e306:
        raise InputError(f"{path}: the points span {span:.3g} px; at most 1e306 can be fitted without overflow")
    if span < 1e-300:
        raise InputError(f"{path}: the points span {span:.3g} px; at least 1e-300 is needed to fit a curve")
    # (the crossing test's Contour refuses a span below 1e-6 px or below 1e-10 of the distance
    # from the origin: such points, e.g. a triangle of side 1e-7, or of side 1e-5 at (1e6, 1e6),
    # ended in an error naming no file although they fit in the moved frame)
    if 1e-4 <= span <= 1e150 and float(np.max(np.abs(P))) <= 1e8 * span:
        return np.zeros(2), 1.0
    return centre, float(2.0 ** np.round(np.log2(span)))


def _summary(args, P, sp, unit, span, closed, crossings):
    """The summary; `unit` is the curve fitted in the frame of span 1."""
    import math

    import numpy as np

    from attneave.stimuli.curves.metrics import curve_metrics

    m = curve_metrics(unit)
    with np.errstate(over="ignore"):  # an overflow is reported as null
        m["max_abs_curvature"] = float(np.float64(m["max_abs_curvature"]) / span)
        m["bending_energy"] = float(np.float64(m["bending_energy"]) / span)
        m["length"] = float(np.float64(m["length"]) * span)
    corners = [int(c) for c in getattr(sp, "corners", ())]
    summary = {
        "method": args.method,
        "n_points": int(len(P)),
        "closed": closed,
        "g2_error": m["g2_error"],
        "interior_extrema": m["interior_extrema"],
        "loops": m["loops"],
        "corners": corners,
        "corner_kinds": list(getattr(sp, "corner_kinds", ())),
        "self_intersections": int(crossings),
        "max_segment_turn": m["max_segment_turn"],
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
    if hasattr(sp, "alpha") or args.method in ("qic", "qic-g2"):
        # the segments' log-aesthetic slope: -1 for clothoids
        summary["alpha"] = float(getattr(sp, "alpha", -1.0))
    if hasattr(sp, "fallback_segments"):
        summary["fallback_segments"] = [int(i) for i in sp.fallback_segments]
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in summary.items()}


def _problems(curve, closed):
    """(crossing count, crossing segments, segments turning by more than pi)."""
    import numpy as np

    from attneave.stimuli.curves.metrics import segment_slices, segment_turning, self_crossing_segments, self_intersections

    crossings = self_intersections(curve.x, curve.y, closed)
    crossing = self_crossing_segments(curve.x, curve.y, curve.segment, closed) if crossings else []
    turn = segment_turning(curve.s, curve.curvature, curve.segment, curve.theta)
    labels = [int(curve.segment[q.start]) for q in segment_slices(curve.segment)]
    looping = [labels[i] for i in np.flatnonzero(turn > np.pi)]
    return crossings, crossing, looping


def run(args):
    import contextlib
    import json
    import sys
    import warnings
    from dataclasses import replace

    import numpy as np

    from attneave.stimuli.commands.counts import MAX_ROWS
    from attneave.stimuli.curves.splines import fit_spline
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.io import atomic_write
    from attneave.stimuli.tables import read_points, write_table

    from attneave.stimuli.io import check_output_spares_inputs

    closed = not args.open
    check_output_spares_inputs(args.output, [args.points], what="-o")
    if args.summary is not None:
        import os

        check_output_spares_inputs(args.summary, [args.points], what="--summary")
        if os.path.realpath(args.summary) == os.path.realpath(args.output):
            raise InputError(f"--summary {args.summary}: is the same file as -o {args.output} (the JSON would "
                             "replace the curve); choose another file")
    if args.method == "cubic-natural" and closed:
        raise InputError("--method cubic-natural: is for open curves (use --open)")
    if args.alpha is not None and args.method not in ("lac-g1", "lac"):
        raise InputError(f"--alpha: applies to the methods lac-g1 and lac only, not to --method {args.method}")
    P = read_points(args.points)
    P = _drop_closing_repeat(P, args.points, closed)
    _check_points(P, args.points, closed)
    n_seg = len(P) if closed else len(P) - 1
    if args.samples * n_seg > MAX_ROWS:
        raise InputError(
            f"--samples: {args.samples} per segment x {n_seg} segments = {args.samples * n_seg} rows; "
            f"at most {MAX_ROWS} rows"
        )
    centre, span = _frame(P, args.points)
    kwargs = {"alpha": args.alpha} if args.method in ("lac-g1", "lac") and args.alpha is not None else {}
    with warnings.catch_warnings():
        # an overflow would show as non-finite output, refused below with one line
        warnings.simplefilter("ignore", RuntimeWarning)
        try:
            sp = fit_spline((P - centre) / span, args.method, closed=closed, **kwargs)
        except InputError as exc:
            raise InputError(f"{args.points}: {exc}") from None
        unit = sp.sample(args.samples)
        # every segment's samples start AND end on its input points exactly: the polynomial
        # splines reach them to round-off only and the G1 log-aesthetic segments to ~1e-10 of the
        # size, and a join that is off by that is a tiny zig-zag that crossing tests count (the
        # summary said 1 self-intersection with no warning; snapping only the first sample made
        # the written curve cross itself at the nodes)
        sl = unit.segment
        first = np.r_[True, sl[1:] != sl[:-1]]
        last = np.r_[sl[1:] != sl[:-1], True]
        node0, node1 = sl[first], (sl[last] + 1) % len(P)
        Pu = (P - centre) / span
        unit.x[first], unit.y[first] = Pu[node0, 0], Pu[node0, 1]
        unit.x[last], unit.y[last] = Pu[node1, 0], Pu[node1, 1]
        curve = replace(unit, s=unit.s * span, x=centre[0] + unit.x * span, y=centre[1] + unit.y * span,
                        curvature=unit.curvature / span)
        # the nodes exactly as given, not to round-off of the change of frame
        curve.x[first], curve.y[first] = P[node0, 0], P[node0, 1]
        curve.x[last], curve.y[last] = P[node1, 0], P[node1, 1]
    table = curve.table()
    if np.any(np.isnan(table["curvature"])):
        # zero speed (a cusp) somewhere: never write blank cells silently
        k = int(np.flatnonzero(np.isnan(table["curvature"]))[0])
        raise InputError(
            f"{args.points}: the {args.method} curve stops and turns back (zero speed, a cusp) at "
            f"s={table['s'][k]:.6g} in segment {int(table['segment'][k])}, where curvature is undefined; "
            "nothing written (try --method qic)"
        )
    if not all(np.all(np.isfinite(v)) for k, v in table.items() if k != "curvature") or np.any(
        np.isinf(table["curvature"])
    ):
        raise InputError(f"{args.points}: the curve does not fit in float64 at this scale (non-finite values)")
    crossings, crossing, looping = _problems(unit, closed)
    if crossing or looping:
        parts = []
        if crossing:
            parts.append(f"crosses itself ({crossings} crossings; segments {', '.join(map(str, crossing))})")
        if looping:
            parts.append(f"has segments turning by more than pi (segments {', '.join(map(str, looping))})")
        what = "error" if args.strict else "warning"
        print(f"attneave spline: {what}: {args.points}: the {args.method} curve " + " and ".join(parts)
              + (" ; nothing written (--strict)" if args.strict else ""), file=sys.stderr)
        if args.strict:
            return 1
    corners = list(getattr(sp, "corners", ()) or ())
    if corners and args.summary is None:
        # the robust fit gave up curvature continuity at these nodes; the summary lists them, and
        # without one the user would not know (the curve is right, but not G2 there)
        kinds = list(getattr(sp, "corner_kinds", ()) or ())
        named = ", ".join(f"{c}" + (f" ({kinds[i]})" if i < len(kinds) else "") for i, c in enumerate(corners[:8]))
        more = f" and {len(corners) - 8} more" if len(corners) > 8 else ""
        print(f"attneave spline: note: {args.points}: curvature is continuous except at {len(corners)} of "
              f"{len(P)} points, where the robust fit relaxed it (G1: tangent kept; G0: a corner): point(s) "
              f"{named}{more}, numbered from 0; --summary lists them", file=sys.stderr)
    summary = _summary(args, P, sp, unit, span, closed, crossings) if args.summary else None
    with contextlib.ExitStack() as stack:
        # open the summary's temporary file first: an unwritable --summary must fail
        # before OUT.csv is renamed into place, so that no half of the output appears
        fh = stack.enter_context(atomic_write(args.summary, "w")) if summary is not None else None
        write_table(table, args.output, float_format="%.17g")
        if fh is not None:
            json.dump(summary, fh, indent=2)
            fh.write("\n")
    return 0
