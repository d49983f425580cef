"""``attneave figures``: the seed paper's Figs. 1-6 (and companions) as PNGs."""

from __future__ import annotations


def add_parser(sub):
    from attneave.stimuli.commands.examples import ExamplesFormatter, examples

    p = sub.add_parser(
        "figures",
        epilog=examples('attneave figures -o figures', 'attneave figures -o figures --quiet'),
        formatter_class=ExamplesFormatter,
        help="the paper's Figs. 1-6 and a Fig. 10 analogue as PNG files, with a note of what each shows",
        description=(
            "Write the seed paper's Figs. 1-6 into DIR: eq. 5 with A' = 1/4, L = 100, n = 10, "
            "b = 1/2, 1, 2 over curvature k in [-1, 1] (Fig. 1) and along k = exp(s) with ds = s/n, "
            "beside the caption's ds = 10 (Fig. 2), "
            "k = 1/(1 - s) with its cusp at s = 1 (Fig. 3) and the clothoid k = (2*pi/n)*s, beside "
            "k = 2*pi/(n*s), the other reading of the caption's 2*pi/ns (Fig. 4); eq. 7's "
            "curvature for C = 0, +-0.01, +-0.02, +-0.03, n = 10 (Figs. 5-6). Also the constant u "
            "along eq. 7, a gallery of the curve families, a Fig. 10 analogue (a bird outline reduced to 30 "
            "points: polynomial splines of degree 3-5 against the QIC spline, with the curvature "
            "extrema each adds), and figures.md describing each file. "
            "Files of DIR with these names (figures.md, fig1_u_vs_curvature.png, ...) are replaced, and "
            "stderr lists each one replaced; other files in DIR are left alone."
        ),
    )
    p.add_argument("-o", "--output", required=True, metavar="DIR",
                   help="output directory (created with its parents if missing); existing files of the "
                        "same names are replaced and listed on stderr")
    p.add_argument("--quiet", action="store_true",
                   help="no progress on stderr (by default a run over ~2 s is a line there, terminal or log)")
    return p


def run(args):
    import sys

    from attneave.papers.draw import make_figures
    from attneave.stimuli.io import make_output_dir

    out = make_output_dir(args.output, what="-o")
    before = {p.name for p in out.iterdir() if p.is_file()}
    from attneave.stimuli.progress import Stages

    with Stages("figures", quiet=getattr(args, "quiet", False), bar=False) as stages:
        stages.stage("drawing the figures")
        written = make_figures(out)
    replaced = [p.name for p in written if p.name in before]
    for path in written:
        print(path)
    if replaced:
        print(f"attneave figures: note: {out}: replaced {len(replaced)} existing file(s): {', '.join(replaced)}",
              file=sys.stderr)
    return 0
