"""``attneave extract``: contours, curvature and surprisal of objects in images.

The pipeline and its outputs are described in :mod:`attneave.stimuli.extraction.pipeline`;
this module parses the arguments, calls
:func:`attneave.stimuli.extraction.pipeline.extract_images` and prints.
"""

from __future__ import annotations

import math
import os
from pathlib import Path


def add_parser(sub):
    from attneave.stimuli.commands.examples import ExamplesFormatter, examples

    p = sub.add_parser(
        "extract",
        epilog=examples('attneave extract photos/ -o out/extracted --method photo', 'attneave extract silhouettes/*.png -o out/mpeg7 --method otsu --polarity dark', 'attneave extract cat.jpg -o out/cat --method grabcut --boxes boxes.csv'),
        formatter_class=ExamplesFormatter,
        help="contours, curvature and surprisal of objects in photos and silhouettes",
        description=(
            "Extract the sub-pixel outer contour of the object in each image (PNG, JPEG, TIFF, BMP; "
            "grey, RGB, RGBA; 8 or 16 bit; turned as its EXIF orientation says, as viewers show it) and write, "
            "per input STEM: STEM.contour.csv (x, y in image pixels, y down), STEM.surprisal.csv (the columns of 'attneave surprisal'), "
            "STEM.overlay.png (the image with the contour coloured by surprisal, peaks circled), "
            "STEM.silhouette.png (black on white, exact coverage, the image's size); and "
            "summary.csv (image, status, reason, n_points, perimeter, area, ...). With --objects all "
            "the per-object files are STEM.0.*, STEM.1.*, ... (largest first). A file that fails is "
            "listed with status 'failed' and its reason (exit status 1); an outline that may be wrong is "
            "written but marked 'suspect' with its reasons (exit status 0). Option mistakes are refused before "
            "any image is read (one line, exit status 2)."
        ),
    )
    p.add_argument("images", nargs="+", metavar="IMAGE",
                   help="image files (PNG, JPEG, TIFF, BMP), or directories: their image files, by name")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="output directory (created if needed)")
    p.add_argument(
        "--method", choices=("auto", "otsu", "threshold", "mask", "alpha", "grabcut", "photo", "model", "rembg"),
        default="auto",
        help="auto (default): a mask or one object on a plain background by otsu, a cut-out by alpha, a "
        "photograph by photo; otsu: one object on a plain background; threshold: a known edge grey level "
        "(--threshold); mask: a binary silhouette of either polarity; alpha: the alpha channel of a "
        "cut-out; grabcut: plain GrabCut (--rect); photo: automatic figure-ground for photographs, or "
        "box/scribble-assisted (--boxes, --scribbles); rembg: a learned salient-object network through rembg "
        "(--rembg-model; needs attneave[rembg]), on each box with --boxes; model: a raw ONNX network that rembg "
        "does not know, with its input size and normalisation (--model-file, --model-size, ...)",
    )
    p.add_argument("--boxes", metavar="BOXES.csv", default=None,
                   help="boxes around the objects: columns image,x,y,width,height (image: file name, stem or path; "
                   "several rows per image with --objects all; methods auto, photo, model, rembg)")
    p.add_argument("--scribbles", metavar="DIR", default=None,
                   help="per image STEM.png of the same size: object strokes pure red, background pure blue "
                   "(methods auto, photo)")
    p.add_argument("--rembg-model", metavar="NAME", default=None,
                   help="rembg network for --method rembg (default isnet-general-use; also u2net, birefnet-general, "
                   "...); its weights must be in U2NET_HOME (default ~/.u2net): nothing is downloaded")
    p.add_argument("--model-file", metavar="FILE.onnx", default=None,
                   help="ONNX network: for --method model (needs attneave[model]), or the weights of --rembg-model "
                   "for --method rembg (a file you have, anywhere)")
    p.add_argument("--model-size", type=int, default=None, metavar="PX",
                   help="network input size (default: the network's own if fixed, else 320)")
    p.add_argument("--model-mean", type=float, nargs=3, default=None, metavar=("R", "G", "B"),
                   help="input normalisation mean on [0, 1] values (default ImageNet's 0.485 0.456 0.406)")
    p.add_argument("--model-std", type=float, nargs=3, default=None, metavar=("R", "G", "B"),
                   help="input normalisation std (default ImageNet's 0.229 0.224 0.225)")
    p.add_argument("--max-pixels", type=float, default=1e8, metavar="N",
                   help="largest image accepted, width x height read from the header before decoding "
                   "(default 1e8 = 100 Mpx)")
    p.add_argument("--threshold", type=float, default=None, metavar="V",
                   help="edge level in the image's units (method threshold) or alpha level (method alpha); "
                   "refused with other methods")
    p.add_argument("--polarity", choices=("auto", "dark", "light"), default="auto",
                   help="which class is the object (default: the one touching the border less)")
    p.add_argument("--objects", choices=("largest", "all"), default="largest",
                   help="the largest object (default) or all of at least --min-area px (STEM.0, STEM.1, ...)")
    p.add_argument("--min-area", type=float, default=None, metavar="PX",
                   help="smallest object in pixels (default max(9, 1e-4 * image pixels))")
    p.add_argument("--holes", action="store_true", help="also trace holes: STEM.holes.csv, and cut them from the silhouette")
    p.add_argument("--rect", type=int, nargs=4, default=None, metavar=("X", "Y", "W", "H"),
                   help="grabcut initial rectangle (method grabcut only; default: the image inset by 5%%)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("-n", type=int, default=None, help="number of equally spaced surprisal points (default 100)")
    g.add_argument("--spacing", type=float, default=None, metavar="PX", help="spacing in pixels instead of -n")
    p.add_argument("--sigma", type=float, default=None, metavar="PX",
                   help="smoothing/curvature scale in px of arc length (default 1%% of the perimeter, >= 1 px; "
                   "at most half the perimeter)")
    p.add_argument("--model", choices=("paper", "vonmises"), default="paper")
    p.add_argument("--A", type=float, default=0.25, help="A' of the paper's form (default 0.25)")
    p.add_argument("--b", type=float, default=None, help="concentration b (default 1 paper, 4 vonmises)")
    p.add_argument("--bits", action="store_true", help="surprisal in bits instead of nats")
    p.add_argument("--workers", type=int, default=1, metavar="N", help="processes to use (default 1)")
    p.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="distribute the images over a Dask cluster (tcp://host:8786; needs attneave[dask]); its "
                   "workers must see the images and -o at the same paths; the files are those of --workers 1")
    p.add_argument("--quiet", action="store_true",
                   help="no progress on stderr (by default a run over ~2 s writes a line there every few seconds, "
                        "terminal or log, and a bar on a terminal)")
    return p


def _check_args(args):
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.extraction.pipeline import check_options

    if args.threshold is not None and not math.isfinite(args.threshold):
        raise InputError(f"--threshold must be a finite number, got {args.threshold}")
    if args.method == "threshold" and args.threshold is None:
        raise InputError("--method threshold needs --threshold V (the edge grey level in the image's units)")
    if args.n is not None and args.n < 3:
        raise InputError(f"-n must be >= 3, got {args.n}")
    if args.spacing is not None and not args.spacing > 0:
        raise InputError(f"--spacing must be > 0, got {args.spacing}")
    if args.spacing is not None and not math.isfinite(args.spacing):
        raise InputError(f"--spacing must be a finite number, got {args.spacing}")
    if args.sigma is not None and not (math.isfinite(args.sigma) and args.sigma > 0):
        raise InputError(f"--sigma must be a finite number > 0 (px of arc length, at most half the outline's "
                         f"perimeter), got {args.sigma}")
    if args.min_area is not None and not (math.isfinite(args.min_area) and args.min_area >= 0):
        raise InputError(f"--min-area must be a finite number >= 0, got {args.min_area}")
    if not (math.isfinite(args.max_pixels) and args.max_pixels >= 1):
        raise InputError(f"--max-pixels must be a number >= 1, got {args.max_pixels}")
    if args.method == "model" and args.model_file is None:
        raise InputError("--method model needs --model-file FILE.onnx (a salient-object network you downloaded)")
    check_options(vars(args))  # an option for another method (--threshold, --rect, --boxes, --model-*, ...)
    if args.model_file is not None and not os.path.isfile(args.model_file):
        raise InputError(f"{args.model_file}: no such model file (an ONNX network, e.g. u2net.onnx)")
    if args.model_size is not None and args.model_size < 8:
        raise InputError(f"--model-size must be >= 8, got {args.model_size}")
    if args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    if not args.A > 0:
        raise InputError(f"--A must be > 0, got {args.A}")
    if args.b is not None and not args.b >= 0:
        raise InputError(f"--b must be >= 0, got {args.b}")


def _expand_directories(paths):
    """Each directory among `paths` replaced by its image files (by suffix, sorted by name; not its
    subdirectories); an InputError for a directory without any."""
    from pathlib import Path

    from attneave.stimuli.errors import InputError
    from attneave.stimuli.extraction.imageio import IMAGE_SUFFIXES

    out = []
    for p in paths:
        if not Path(p).is_dir():
            out.append(p)
            continue
        found = sorted(str(f) for f in Path(p).iterdir() if f.is_file() and f.suffix.lower() in IMAGE_SUFFIXES)
        if not found:
            raise InputError(f"{p}: a directory without image files ({', '.join(IMAGE_SUFFIXES)})")
        out.extend(found)
    return out


def _check_output_outside_input_dirs(output, paths):
    """Refuse ``-o`` that is an input directory or lies inside one (one line).

    The outputs would be mixed with the images: the overlays and silhouettes
    are PNG files that the next ``extract DIR`` would take for new images.
    """
    from attneave.stimuli.errors import InputError

    out = Path(os.path.realpath(Path(output).expanduser()))
    for p in paths:
        if not Path(p).is_dir():
            continue
        d = Path(os.path.realpath(p))
        if out == d or d in out.parents:
            where = "is" if out == d else "is inside"
            raise InputError(f"-o {output}: {where} the input directory {p}; the outputs (PNG overlays and "
                             "silhouettes among them) would be read as images by the next run; choose another -o")


def run(args):
    import sys

    _check_args(args)
    _check_output_outside_input_dirs(args.output, args.images)
    # `attneave extract photos/ -o out`: a folder of images, as people keep them (a directory was
    # one failed input before)
    args.images = _expand_directories(args.images)
    from attneave.stimuli.progress import Stages

    with Stages("extract", quiet=args.quiet, bar=False, total=len(args.images)) as stages:
        stages.stage(f"{len(args.images)} image(s)")
        summary = _extract(args, stages)
    left = summary.left
    if left:
        shown = ", ".join(left[:6]) + (f", ... ({len(left)} files)" if len(left) > 6 else "")
        print(f"attneave extract: warning: left {shown} in {args.output}: per-object outputs of an earlier run "
              "that this run did not write and cannot tell from another image's (an input named STEM.K.png); "
              "remove them if they are stale", file=sys.stderr)
    # a file that failed is named on stderr, one line each (a few; all are in summary.csv), so that
    # "1 failed" does not send the user hunting through the table for which one and why
    for image, reason in summary.failed[:10]:
        print(f"attneave extract: {image}: failed: {reason}", file=sys.stderr)
    n_ok, n_suspect, n_failed = (int(summary.counts.get(k, 0)) for k in ("ok", "suspect", "failed"))
    if n_failed > 10:
        print(f"attneave extract: ... and {n_failed - 10} more failed", file=sys.stderr)
    resumed = f"; {summary.resumed} done by an earlier, interrupted run" if summary.resumed else ""
    print(f"attneave extract: {summary.n} image(s): {n_ok} ok, {n_suspect} suspect, {n_failed} failed "
          f"(status and reason of each in {Path(args.output) / 'summary.csv'}){resumed}", file=sys.stderr)
    return 1 if n_failed else 0


def _extract(args, stages):
    from attneave.stimuli.extraction.pipeline import extract_images

    return extract_images(
        args.images, args.output, workers=args.workers, progress=False if args.quiet else None, stages=stages,
        scheduler=args.scheduler, as_frame=False,
        method=args.method, threshold=args.threshold, polarity=args.polarity, objects=args.objects,
        min_area=args.min_area, holes=args.holes, rect=args.rect, n=args.n, spacing=args.spacing,
        sigma=args.sigma, model=args.model, A=args.A, b=args.b, bits=args.bits, boxes=args.boxes,
        scribbles=args.scribbles, model_file=args.model_file, model_size=args.model_size,
        model_mean=args.model_mean, model_std=args.model_std, rembg_model=args.rembg_model,
        max_pixels=int(args.max_pixels),
    )
