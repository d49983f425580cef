"""``attneave extract``: contours, curvature and surprisal of objects in images.

The pipeline and its outputs are described in :mod:`stimuli.extraction.pipeline`;
this module parses the arguments, calls
:func:`stimuli.extraction.pipeline.extract_images` and prints.
"""

from __future__ import annotations

import math


def add_parser(sub):
    p = sub.add_parser(
        "extract",
        help="contours, curvature and surprisal of objects in photos and silhouettes",
        description=(
            "Extract the sub-pixel outer contour of the object in each image (PNG, JPEG, TIFF, BMP; "
            "grey, RGB, RGBA; 8 or 16 bit) and write, per input STEM: STEM.contour.csv (x, y in image "
            "pixels, y down), STEM.surprisal.csv (the columns of 'attneave surprisal'), "
            "STEM.overlay.png (the image with the contour coloured by surprisal, peaks circled), "
            "STEM.silhouette.png (black on white, exact coverage, the image's size); and "
            "summary.csv (image, status, reason, n_points, perimeter, area, ...). With --objects all "
            "the per-object files are STEM.0.*, STEM.1.*, ... (largest first). A file that fails is "
            "listed with status 'failed' and its reason; the exit status is then 1."
        ),
    )
    p.add_argument("images", nargs="+", metavar="IMAGE", help="image files (PNG, JPEG, TIFF, BMP)")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="output directory (created if needed)")
    p.add_argument(
        "--method", choices=("otsu", "threshold", "mask", "alpha", "grabcut"), default="otsu",
        help="otsu: one object on a plain background (default); threshold: a known edge grey level "
        "(--threshold); mask: a binary silhouette of either polarity; alpha: the alpha channel of a "
        "cut-out; grabcut: cluttered backgrounds (slow; --rect)",
    )
    p.add_argument("--threshold", type=float, default=None, metavar="V",
                   help="edge level in the image's units (method threshold) or alpha level (method alpha)")
    p.add_argument("--polarity", choices=("auto", "dark", "light"), default="auto",
                   help="which class is the object (default: the one touching the border less)")
    p.add_argument("--objects", choices=("largest", "all"), default="largest",
                   help="the largest object (default) or all of at least --min-area px (STEM.0, STEM.1, ...)")
    p.add_argument("--min-area", type=float, default=None, metavar="PX",
                   help="smallest object in pixels (default max(9, 1e-4 * image pixels))")
    p.add_argument("--holes", action="store_true", help="also trace holes: STEM.holes.csv, and cut them from the silhouette")
    p.add_argument("--rect", type=int, nargs=4, default=None, metavar=("X", "Y", "W", "H"),
                   help="grabcut initial rectangle (default: the image inset by 5%%)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("-n", type=int, default=None, help="number of equally spaced surprisal points (default 100)")
    g.add_argument("--spacing", type=float, default=None, metavar="PX", help="spacing in pixels instead of -n")
    p.add_argument("--sigma", type=float, default=None, metavar="PX",
                   help="smoothing/curvature scale in px of arc length (default 1%% of the perimeter, >= 1 px)")
    p.add_argument("--model", choices=("paper", "vonmises"), default="paper")
    p.add_argument("--A", type=float, default=0.25, help="A' of the paper's form (default 0.25)")
    p.add_argument("--b", type=float, default=None, help="concentration b (default 1 paper, 4 vonmises)")
    p.add_argument("--bits", action="store_true", help="surprisal in bits instead of nats")
    p.add_argument("--workers", type=int, default=1, metavar="N", help="processes to use (default 1)")
    return p


def _check_args(args):
    from stimuli.errors import InputError

    if args.threshold is not None and not math.isfinite(args.threshold):
        raise InputError(f"--threshold must be a finite number, got {args.threshold}")
    if args.method == "threshold" and args.threshold is None:
        raise InputError("--method threshold needs --threshold V (the edge grey level in the image's units)")
    if args.n is not None and args.n < 3:
        raise InputError(f"-n must be >= 3, got {args.n}")
    if args.spacing is not None and not args.spacing > 0:
        raise InputError(f"--spacing must be > 0, got {args.spacing}")
    if args.sigma is not None and not args.sigma > 0:
        raise InputError(f"--sigma must be > 0, got {args.sigma}")
    if args.min_area is not None and not args.min_area >= 0:
        raise InputError(f"--min-area must be >= 0, got {args.min_area}")
    if args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    if not args.A > 0:
        raise InputError(f"--A must be > 0, got {args.A}")
    if args.b is not None and not args.b >= 0:
        raise InputError(f"--b must be >= 0, got {args.b}")


def run(args):
    import sys

    from stimuli.extraction.pipeline import extract_images

    _check_args(args)
    summary = extract_images(
        args.images, args.output, workers=args.workers,
        method=args.method, threshold=args.threshold, polarity=args.polarity, objects=args.objects,
        min_area=args.min_area, holes=args.holes, rect=args.rect, n=args.n, spacing=args.spacing,
        sigma=args.sigma, model=args.model, A=args.A, b=args.b, bits=args.bits,
    )
    failed = summary[summary["status"] != "ok"]
    for image, reason in zip(failed["image"], failed["reason"]):
        print(f"attneave extract: {image}: failed: {reason}", file=sys.stderr)
    return 1 if len(failed) else 0
