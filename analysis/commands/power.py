"""``attneave power``: how many participants detect a given beta, by simulation."""

from __future__ import annotations

from attneave.analysis.commands.simulate import add_effect_arguments, check_design

#: Most simulated experiments per design and Monte Carlo replicates of the null: each is a
#: float per replicate held at once, and beyond these the p-value's resolution gains nothing.
MAX_SIMULATIONS = 100_000
MAX_GROUP_SIMULATIONS = 1_000_000
#: Fewest experiments per design: :data:`attneave.analysis.simulate.observers.MIN_SIMULATIONS`, repeated here (and
#: checked equal by the tests) so that 'attneave --help' does not import scipy.
MIN_SIMULATIONS = 20


def _int_list(text):
    import argparse

    try:
        out = [int(v) for v in str(text).split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected whole numbers separated by commas, got {text!r}") from None
    if not out:
        raise argparse.ArgumentTypeError("expected at least one number")
    return out


def add_parser(sub):
    from attneave.stimuli.commands.examples import ExamplesFormatter, examples

    p = sub.add_parser(
        "power",
        epilog=examples('attneave power --stimuli out/polygons --top-share 0.3 --participants 10,20,40', 'attneave power --stimuli out/polygons --beta 0.5 --clicks 5 --simulations 200 -o power.csv'),
        formatter_class=ExamplesFormatter,
        help="power of the group test for a given effect (top share, lift or beta), by simulation",
        description=(
            "Simulate experiments with observers who follow the information model with weight beta "
            "(see 'attneave simulate') on the stimulus set DIR, analyse each as 'attneave analyze' does "
            "(one-sample t statistic across participants of per-participant mean z, Monte Carlo null under "
            "uniform clicking, one-sided) and report, for "
            "each number of participants, the share of experiments with p <= alpha, and the smallest "
            "number reaching the target power."
        ),
    )
    p.add_argument("--stimuli", required=True, metavar="DIR", help="stimulus-set directory (manifest.csv)")
    add_effect_arguments(p)
    p.add_argument("--participants", type=_int_list, default=[4, 6, 8, 12, 16, 24, 32], metavar="P1,P2,...",
                   help="numbers of participants (default 4,6,8,12,16,24,32)")
    p.add_argument("--clicks", type=int, default=10, metavar="K", help="clicks per participant per stimulus (default 10)")
    p.add_argument("--simulations", type=int, default=200, metavar="R",
                   help=f"experiments per design (default 200, at least {MIN_SIMULATIONS}: fewer give no estimate; "
                        "the table's mc_se is the Monte Carlo standard error of each power)")
    p.add_argument("--alpha", type=float, default=0.05,
                   help="significance level (default 0.05); at least 1/(R+1), the smallest p of the group test's "
                        "Monte Carlo null with --group-simulations R")
    p.add_argument("--target", type=float, default=0.8, help="power wanted (default 0.8)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--noise", type=float, default=0.0, metavar="PX", help="click noise sd in px (default 0; >0 is slower)")
    p.add_argument("--beta-sd", type=float, default=0.0, metavar="SD", help="between-participant sd of beta")
    p.add_argument("--group-simulations", type=int, default=1999, metavar="R",
                   help="Monte Carlo replicates of the group test's null, simulated once per design (default 1999)")
    p.add_argument("-n", type=int, default=100, help="equally spaced points per contour (default 100)")
    p.add_argument("--model", choices=("paper", "vonmises"), default="paper")
    p.add_argument("-o", "--output", default=None, metavar="OUT.csv", help="also write the table")
    p.add_argument("--quiet", action="store_true",
                   help="no progress on stderr (by default every stage over ~2 s is a line there, terminal or log)")
    return p


def run(args):
    import numpy as np

    from attneave.analysis.clicks.mapping import predict
    from attneave.analysis.models.effect import resolve_effect
    from attneave.analysis.simulate.observers import power
    from attneave.stimuli.io import check_output_spares_inputs, disk_error_exit
    from attneave.stimuli.progress import Stages
    from attneave.stimuli.stimulus_set import read_stimulus_set
    from attneave.stimuli.tables import write_table
    from attneave.stimuli.validate import as_int, as_number

    if args.output is not None:
        # found before minutes of simulation, not after
        from pathlib import Path

        from attneave.stimuli.errors import InputError

        check_output_spares_inputs(args.output, [args.stimuli])
        out = Path(args.output)
        if out.is_dir():
            raise InputError(f"{out}: is a directory; expected a file name to write")
        if not out.parent.is_dir():
            raise InputError(f"{out}: cannot write there (no directory {out.parent})")
    stimset = read_stimulus_set(args.stimuli)
    if args.output is not None:  # nor a file of the set (its manifest, a contour, an image)
        check_output_spares_inputs(args.output, stimset.files())
    check_design(len(stimset), max(args.participants), args.clicks, args)
    as_int(args.simulations, "--simulations", lo=MIN_SIMULATIONS, hi=MAX_SIMULATIONS)
    as_int(args.group_simulations, "--group-simulations", lo=1, hi=MAX_GROUP_SIMULATIONS)
    as_number(args.target, "--target", gt=0, le=1)
    with Stages("power", quiet=args.quiet, bar=False) as stages:
        stages.stage(f"predictions of {len(stimset)} stimuli")
        pred = predict(stimset, n=args.n, model=args.model)
        eff = resolve_effect(np.stack([p.z["surprisal"] for p in pred.values()]), beta=args.beta, lift=args.lift,
                             top_share=args.top_share)
        stages.stage(f"{len(args.participants)} designs x {args.simulations} simulations")
        table, info = power(pred, eff["beta"], participants=args.participants, clicks=args.clicks,
                            simulations=args.simulations, alpha=args.alpha, seed=args.seed, noise=args.noise,
                            beta_sd=args.beta_sd, target=args.target, group_simulations=args.group_simulations)
    if args.output:
        try:
            write_table(table, args.output)
        except OSError as exc:  # a full disk: one line, exit 1
            return disk_error_exit('power', args.output, exc)
    print(f"beta = {info['beta']:.4g} (expected top share {eff['top_share']:.3f}, chance {eff['chance_share']:g}, "
          f"lift {eff['lift']:.2f}), {info['stimuli']} stimuli x {info['clicks']} clicks, alpha = {info['alpha']:g}, "
          f"{info['simulations']} simulations per design")
    print(table.to_string(index=False, float_format=lambda v: f"{v:.3f}"))
    req = info["required_participants"]
    print(f"participants for power >= {info['target']:g}: "
          + (str(req) if req is not None else f"more than {max(args.participants)}"))
    return 0
