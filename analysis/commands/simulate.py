"""``attneave simulate``: clicks of simulated observers who follow the information model."""

from __future__ import annotations


def add_parser(sub):
    p = sub.add_parser(
        "simulate",
        help="clicks of simulated observers on a stimulus set",
        description=(
            "Each simulated participant clicks K times on every stimulus of DIR: point j of the n equally "
            "spaced contour points with probability exp(beta*z_j)/sum_i exp(beta*z_i) (z = standardised "
            "surprisal, the model that 'attneave analyze' fits), uniformly within that point's arc, "
            "displaced by Gaussian noise of sd PX. Writes CLICKS.csv with columns participant, "
            "stimulus_id, trial, x, y, true_t, true_point, participant_beta."
        ),
    )
    p.add_argument("--stimuli", required=True, metavar="DIR", help="stimulus-set directory (manifest.csv)")
    p.add_argument("-o", "--output", required=True, metavar="CLICKS.csv")
    p.add_argument("--participants", type=int, required=True, metavar="P")
    p.add_argument("--clicks", type=int, required=True, metavar="K", help="clicks per participant per stimulus")
    p.add_argument("--beta", type=float, required=True, metavar="B", help="weight of z (0: uniform clicking)")
    p.add_argument("--seed", type=int, required=True, metavar="S")
    p.add_argument("--noise", type=float, default=0.0, metavar="PX", help="click noise sd in pixels (default 0)")
    p.add_argument("--beta-sd", type=float, default=0.0, metavar="SD", help="between-participant sd of beta (default 0)")
    p.add_argument("-n", type=int, default=100, help="equally spaced points per contour (default 100)")
    p.add_argument("--model", choices=("paper", "vonmises"), default="paper")
    p.add_argument("--coords", choices=("image", "centered"), default="image", help="coordinates written (default image)")
    p.add_argument("--scale", type=float, default=1.0, help="shown image size / image size (default 1)")
    return p


def run(args):
    from analysis.mapping import predict
    from analysis.observers import simulate
    from stimuli.stimulus_set import read_stimulus_set
    from stimuli.io import write_table

    stimset = read_stimulus_set(args.stimuli)
    pred = predict(stimset, n=args.n, model=args.model)
    df, params = simulate(pred, args.participants, args.clicks, args.beta, args.seed, noise=args.noise,
                          beta_sd=args.beta_sd, coords=args.coords, scale=args.scale)
    write_table(df, args.output, float_format="%.17g")
    print(f"{len(df)} clicks ({params['participants']} participants x {params['stimuli']} stimuli x "
          f"{params['clicks']} clicks, beta = {params['beta']:g}, seed = {params['seed']}) -> {args.output}")
    return 0
