"""``attneave simulate``: clicks of simulated observers who follow the information model."""

from __future__ import annotations

#: Most clicks one simulated experiment may hold (participants x stimuli x clicks): twice the
#: 1,000,000 that 'attneave analyze' is built to handle; beyond it memory runs out (~100 B a click).
MAX_CLICKS = 2_000_000
#: Largest |beta| and beta sd: exp(beta*z) at |z| ~ 10 stays finite, and 50 already puts every
#: click on the single most surprising point (the bound --top-share is solved within).
MAX_BETA = 50.0
#: Most points per contour in the choice model: far below a pixel's spacing on any stimulus
#: (a perimeter of 100,000 px); the rival predictors' tables grow as n x peaks.
MAX_MODEL_POINTS = 100_000
#: Largest click noise in pixels (the bound on --scale's image sizes); more only overflows.
MAX_NOISE_PX = 1e6


def check_design(n_stimuli, participants, clicks, args):
    """Check the size and effect options shared by 'simulate' and 'power' before any work.

    Parameters
    ----------
    n_stimuli : int
        Stimuli in the set.
    participants, clicks : int
        The largest number of participants and the clicks per participant per stimulus.
    args : argparse.Namespace
        With ``n``, ``seed``, ``beta``, ``beta_sd`` and ``noise``.

    Raises
    ------
    InputError
        One line naming the option and its bound.
    """
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.validate import as_int, as_number

    as_int(args.n, "-n", lo=3, hi=MAX_MODEL_POINTS)
    as_int(args.seed, "--seed", lo=0)
    if args.beta is not None:
        as_number(args.beta, "--beta", ge=-MAX_BETA, le=MAX_BETA)
    as_number(args.beta_sd, "--beta-sd", ge=0, le=MAX_BETA)
    as_number(args.noise, "--noise", ge=0, le=MAX_NOISE_PX)
    as_int(participants, "--participants", lo=1)
    as_int(clicks, "--clicks", lo=1)
    total = participants * clicks * max(n_stimuli, 1)
    if total > MAX_CLICKS:
        raise InputError(f"--participants {participants} x {n_stimuli} stimuli x --clicks {clicks} = {total:,} "
                         f"clicks; at most {MAX_CLICKS:,} per experiment")


def add_effect_arguments(p):
    """The effect, in one of three units (shared with 'attneave power')."""
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--top-share", type=float, metavar="F",
                   help="share of clicks on the top 10%% of each contour's points by surprisal (chance 0.1; "
                        "e.g. 0.4); beta is solved for on this stimulus set")
    g.add_argument("--lift", type=float, metavar="L", help="top share / chance share (e.g. 3 for 30%% of clicks "
                                                          "on the top 10%% of points)")
    g.add_argument("--beta", type=float, metavar="B",
                   help="weight of standardised surprisal z (0: uniform clicking); not portable across stimulus "
                        "sets, prefer --top-share or --lift")


def add_parser(sub):
    from attneave.stimuli.commands.examples import ExamplesFormatter, examples

    p = sub.add_parser(
        "simulate",
        epilog=examples('attneave simulate --stimuli out/polygons -o clicks.csv --participants 20 --clicks 5 --top-share 0.3 --seed 1', 'attneave simulate --stimuli out/polygons -o null.csv --participants 20 --clicks 5 --beta 0 --seed 2'),
        formatter_class=ExamplesFormatter,
        help="clicks of simulated observers on a stimulus set",
        description=(
            "Each simulated participant clicks K times on every stimulus of DIR: point j of the n equally "
            "spaced contour points with probability exp(beta*z_j)/sum_i exp(beta*z_i) (z = standardised "
            "surprisal, the model that 'attneave analyze' fits), uniformly within that point's arc, "
            "displaced by Gaussian noise of sd PX. The effect is given as beta, or portably as the share of "
            "clicks on the top 10% of points (--top-share) or its lift over chance (--lift), from which beta "
            "is solved on this stimulus set. Writes CLICKS.csv with columns participant, "
            "stimulus_id, trial, x, y, true_t, true_point, participant_beta."
        ),
    )
    p.add_argument("--stimuli", required=True, metavar="DIR", help="stimulus-set directory (manifest.csv)")
    p.add_argument("-o", "--output", required=True, metavar="CLICKS.csv",
                   help="click file to write (not a file of the stimulus set)")
    p.add_argument("--participants", type=int, required=True, metavar="P")
    p.add_argument("--clicks", type=int, required=True, metavar="K", help="clicks per participant per stimulus")
    add_effect_arguments(p)
    p.add_argument("--seed", type=int, required=True, metavar="S")
    p.add_argument("--noise", type=float, default=0.0, metavar="PX",
                   help="click noise sd in pixels (default 0); a warning gives the share of clicks it puts "
                        "outside their image")
    p.add_argument("--beta-sd", type=float, default=0.0, metavar="SD", help="between-participant sd of beta (default 0)")
    p.add_argument("-n", type=int, default=100, help="equally spaced points per contour (default 100)")
    p.add_argument("--model", choices=("paper", "vonmises"), default="paper")
    p.add_argument("--coords", choices=("image", "centered"), default="image", help="coordinates written (default image)")
    p.add_argument("--scale", type=float, default=1.0, help="shown image size / image size (default 1)")
    return p


def run(args):
    import numpy as np

    from attneave.analysis.clicks.mapping import predict
    from attneave.analysis.models.effect import resolve_effect
    from attneave.analysis.simulate.observers import simulate
    from attneave.stimuli.io import check_output_spares_inputs, disk_error_exit
    from attneave.stimuli.stimulus_set import read_stimulus_set
    from attneave.stimuli.tables import write_table

    check_output_spares_inputs(args.output, [args.stimuli])
    stimset = read_stimulus_set(args.stimuli)
    # the output may not overwrite a file of the set (its manifest, a contour, an image)
    check_output_spares_inputs(args.output, stimset.files())
    check_design(len(stimset), args.participants, args.clicks, args)
    pred = predict(stimset, n=args.n, model=args.model)
    eff = resolve_effect(np.stack([p.z["surprisal"] for p in pred.values()]), beta=args.beta, lift=args.lift,
                         top_share=args.top_share)
    df, params = simulate(pred, args.participants, args.clicks, eff["beta"], args.seed, noise=args.noise,
                          beta_sd=args.beta_sd, coords=args.coords, scale=args.scale)
    try:
        write_table(df, args.output, float_format="%.17g")
    except OSError as exc:  # a full disk: one line, exit 1
        return disk_error_exit('simulate', args.output, exc)
    print(f"{len(df)} clicks ({params['participants']} participants x {params['stimuli']} stimuli x "
          f"{params['clicks']} clicks, beta = {params['beta']:.4g}, expected top share {eff['top_share']:.3f} "
          f"(chance {eff['chance_share']:g}, lift {eff['lift']:.2f}), seed = {params['seed']}) -> {args.output}")
    if params["outside_share"] > 0:
        import sys

        k = round(params["outside_share"] * len(df))
        print(f"attneave simulate: warning: {k} of {len(df)} clicks ({100 * params['outside_share']:.3g}%) lie "
              f"outside their image: --noise {args.noise:g} px is large for these images; 'attneave analyze' "
              "excludes clicks farther from the contour than its --tolerance", file=sys.stderr)
    return 0
