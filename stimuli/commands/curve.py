"""``attneave curve``: a curve from its natural equation, written as a CSV table.

One sub-command per family (``attneave curve clothoid --help`` lists its
parameters). Output columns: ``s, x, y, theta, curvature`` in y-UP
mathematical coordinates, starting at the origin with ``theta = 0``.
"""

from __future__ import annotations

_COMMON_DESC = (
    "Columns: s, x, y, theta, curvature. Coordinates are y-UP (mathematical: x right, y up, "
    "angles counter-clockwise, positive curvature turns left); for image pixels (y down) use "
    "(x, -y). The curve starts at the origin with theta = 0 at its first arc length."
)

# family -> (help, description, [(flag, kwargs)], s-range mode)
_FAMILIES = {
    "clothoid": (
        "Euler/Cornu spiral, curvature k0 + c*s",
        "Clothoid with curvature k0 + c*s (Fresnel integrals in closed form; c = 0 gives a circle "
        "or a line, negative c is allowed).",
        [
            ("--k0", dict(type=float, default=0.0, help="curvature at s = 0 (default 0)")),
            ("--c", dict(type=float, required=True, help="rate of change of curvature d(kappa)/ds")),
        ],
        "s",
    ),
    "pseudospiral": (
        "pseudospiral rho = a*s^m (paper eq. 8)",
        "Pseudospiral with radius of curvature rho = a*s^m (paper eq. 8): m = 1 logarithmic "
        "spiral, m = -1 Cornu spiral, m = 1/2 involute of a circle, m = 0 circle. Needs s >= 0, "
        "and s > 0 when m > 0 (rho = 0 at s = 0).",
        [
            ("--a", dict(type=float, required=True, help="scale a (nonzero; negative turns right)")),
            ("--m", dict(type=float, required=True, help="exponent m")),
        ],
        "s",
    ),
    "lac": (
        "log-aesthetic curve (paper eq. 9)",
        "Log-aesthetic curve (paper eq. 9): rho = exp(lam*s) when alpha = 0, otherwise "
        "rho = (lam*alpha*s + 1)^(1/alpha). alpha = -1 clothoid, 0 Nielsen's spiral, "
        "1 logarithmic spiral, 2 involute of a circle. Needs lam*alpha*s + 1 > 0 on [s-start, s-end].",
        [
            ("--alpha", dict(type=float, required=True, help="shape parameter alpha (any real)")),
            ("--lam", dict(type=float, required=True, help="rate lambda")),
        ],
        "s",
    ),
    "superspiral": (
        "superspiral rho(psi) = 2F1(a,b;c;-psi) (paper eq. 10)",
        "Superspiral (paper eq. 10): radius of curvature rho(psi) = 2F1(a, b; c; -psi) as a "
        "function of the tangent angle psi, c > b > 0, a > 0; x, y = integrals over psi of "
        "rho*cos(psi), rho*sin(psi) by adaptive Gauss-Kronrod quadrature. The curve is "
        "parametrised by tangent angle, so it takes --theta-end instead of --s-start/--s-end; "
        "points are equally spaced in tangent angle over [0, theta-end] and the s column is the "
        "computed arc length.",
        [
            ("--a", dict(type=float, required=True, help="a > 0")),
            ("--b", dict(type=float, required=True, help="b > 0")),
            ("--c", dict(type=float, required=True, help="c > b")),
            ("--theta-end", dict(type=float, required=True, help="final tangent angle in radians (> 0)")),
        ],
        "theta",
    ),
    "constant-info": (
        "constant-information curve (paper eq. 7)",
        "Curve with curvature (1/s)*(n*arccos(C*n^2/s^2) + 2*pi) (paper eq. 7), along which eq. 5 "
        "with ds = s/n is the constant -ln A' - b*C. Defined only where s > 0 and |C|*n^2 <= s^2; "
        "--s-start defaults to the start of that domain, sqrt(|C|)*n (or s-end/1000 when C = 0).",
        [
            ("--C", dict(type=float, required=True, help="the constant C of eq. 7")),
            ("--n", dict(type=float, default=10.0, help="number of points n (default 10, as in the paper)")),
        ],
        "s-optional",
    ),
}


def _epilog():
    lines = ["families and their parameters:"]
    for name, (help_, _desc, options, srange) in _FAMILIES.items():
        flags = " ".join(
            f"{flag} {flag.lstrip('-').replace('-', '_').upper()}" if kw.get("required")
            else f"[{flag} {flag.lstrip('-').replace('-', '_').upper()}]"
            for flag, kw in options
        )
        rng = {
            "s": "--s-start S0 --s-end S1" if name == "pseudospiral" else "[--s-start S0] --s-end S1",
            "s-optional": "[--s-start S0] --s-end S1",
            "theta": "",
        }[srange]
        lines.append(f"  {name:<14s}{help_}")
        lines.append(" " * 16 + " ".join(f"{flags} {rng} [--points K] -o OUT.csv".split()))
    from attneave.stimuli.commands.examples import examples

    return "\n".join(lines) + "\n\n" + examples(
        "attneave curve clothoid --c 0.05 --s-end 20 -o clothoid.csv",
        "attneave curve lac --alpha 1.5 --lam 0.1 --s-end 10 --points 500 -o lac.csv")


def add_parser(sub):
    import textwrap

    from attneave.stimuli.commands.counts import MAX_ROWS, count
    from attneave.stimuli.commands.examples import ExamplesFormatter

    p = sub.add_parser(
        "curve",
        help="a curve from its natural equation (clothoid, pseudospiral, lac, superspiral, constant-info)",
        description=textwrap.fill(
            "Write a curve given by its natural equation as a CSV table. " + _COMMON_DESC
            + " Run 'attneave curve FAMILY --help' for the details of each family.", 79
        ),
        epilog=_epilog(),
        formatter_class=ExamplesFormatter,
    )
    fam = p.add_subparsers(dest="family", required=True, metavar="FAMILY", parser_class=type(p))
    for name, (help_, desc, options, srange) in _FAMILIES.items():
        fp = fam.add_parser(name, help=help_, description=desc + " " + _COMMON_DESC)
        fp.add_argument("-o", "--output", required=True, metavar="OUT.csv", help="output CSV file")
        for flag, kw in options:
            fp.add_argument(flag, **kw)
        if srange == "s":
            fp.add_argument(
                "--s-start", type=float,
                required=name == "pseudospiral",
                default=None if name == "pseudospiral" else 0.0,
                help="first arc length" + ("" if name == "pseudospiral" else " (default 0)"),
            )
            fp.add_argument("--s-end", type=float, required=True, help="last arc length")
        elif srange == "s-optional":
            fp.add_argument(
                "--s-start", type=float, default=None, help="first arc length (default: start of the domain)"
            )
            fp.add_argument("--s-end", type=float, required=True, help="last arc length")
        fp.add_argument("--points", type=count(2), default=201, metavar="K",
                        help=f"number of points, 2 .. {MAX_ROWS} (default 201)")
    return p


def make_curve(args):
    """Build the :class:`attneave.stimuli.curves.Curve` that `args` describe."""
    from attneave.stimuli import curves

    fam = args.family
    if fam == "clothoid":
        return curves.clothoid(args.k0, args.c, args.s_start, args.s_end, args.points)
    if fam == "pseudospiral":
        return curves.pseudospiral(args.a, args.m, args.s_start, args.s_end, args.points)
    if fam == "lac":
        return curves.log_aesthetic(args.alpha, args.lam, args.s_start, args.s_end, args.points)
    if fam == "superspiral":
        return curves.superspiral(args.a, args.b, args.c, args.theta_end, args.points)
    if fam == "constant-info":
        return curves.constant_info(args.C, args.n, args.s_start, args.s_end, args.points)
    raise AssertionError(fam)  # argparse restricts the choices


def run(args):
    from pathlib import Path

    from attneave.stimuli.errors import InputError
    from attneave.stimuli.tables import write_table

    out = Path(args.output)
    if not out.parent.is_dir():
        raise InputError(f"{out}: output directory {out.parent} does not exist")
    curve = make_curve(args)
    write_table(curve.table(), out, float_format="%.17g")
    return 0
