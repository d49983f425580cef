"""``attneave generate``: make a stimulus set from a YAML batch config."""

from __future__ import annotations


def add_parser(sub):
    from attneave.stimuli.commands.examples import ExamplesFormatter, examples

    p = sub.add_parser(
        "generate",
        epilog=examples('attneave generate configs/attneave_polygons.yaml -o out/polygons', 'attneave generate configs/radial_frequency.yaml -o out/rf --workers 2', 'attneave generate configs/attneave_polygons.yaml -o out/polygons --resume'),
        formatter_class=ExamplesFormatter,
        help="make a stimulus set (images, contours, manifest) from a YAML batch config",
        description=(
            "Validate CONFIG.yaml, then write the stimulus set to DIR: manifest.csv, "
            "images/<id>.png (and .svg), contours/<id>.csv (x, y in image pixels, y down) and the "
            "resolved config.yaml. The same config gives byte-identical files whatever the number "
            "of workers. A rerun into DIR completes an interrupted batch; a DIR made by another "
            "config is refused unless --force. See configs/ for commented examples."
        ),
    )
    p.add_argument("config", metavar="CONFIG.yaml")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="stimulus-set directory")
    p.add_argument("--workers", type=int, default=1, metavar="N", help="local worker processes (default 1)")
    p.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="run on a Dask distributed scheduler, e.g. tcp://host:8786 (needs attneave[dask]; "
                        "the workers must see DIR at the same path)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--resume", action="store_true",
                   help="complete an interrupted batch of the same config in DIR (an error if there is none)")
    g.add_argument("--force", action="store_true",
                   help="delete an earlier batch's files in DIR and start again")
    p.add_argument("--dry-run", action="store_true",
                   help="validate the config and print what would be made; write nothing")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--quiet", action="store_true",
                   help="no progress on stderr at all (by default a run over ~2 s writes a line there every few "
                        "seconds, terminal or log)")
    return p


def run(args):
    import os
    import sys

    from attneave.stimuli.batch.config import load_config
    from attneave.stimuli.batch.runner import BatchError, run_batch
    from attneave.stimuli.errors import InputError
    from attneave.stimuli.io import disk_error_exit

    if args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    if args.output == "":
        raise InputError("-o: empty output path; name a directory")
    batch = load_config(args.config)
    if args.dry_run:
        for c in batch.conditions:
            print(f"{c.name}: recipe {c.recipe}, {len(c.cells)} cell(s) x {c.repeats} repeat(s) "
                  f"= {c.n_jobs} call(s)")
        print(f"{batch.n_jobs} recipe call(s); config sha256 {batch.sha256[:12]}")
        return 0
    cpus = os.cpu_count() or 1
    if args.scheduler is None and args.workers > cpus:
        print(f"attneave generate: warning: --workers {args.workers} is more than the {cpus} CPUs; "
              f"more processes than cores only compete (at most one per recipe call is started)",
              file=sys.stderr)
    from attneave.stimuli.progress import Stages

    try:
        with _one_line_warnings(), Stages("generate", quiet=args.quiet, bar=False, total=batch.n_jobs) as stages:
            stages.stage(f"{batch.n_jobs} recipe call(s)")
            res = run_batch(
                batch, args.output, workers=args.workers, scheduler=args.scheduler, resume=args.resume,
                force=args.force, progress=False if args.no_progress or args.quiet else None, stages=stages,
            )
    except OSError as exc:
        # the disk, not the input: exit 1; every file in place is complete, the rerun completes the set
        return disk_error_exit("generate", args.output, exc, "the files written so far are complete: free space "
                                                               "and run the same command again to finish the set")
    except BatchError as exc:
        # a bug, not the input: the traceback for a report, then one line on what became of DIR
        import traceback

        traceback.print_exception(exc.__cause__ or exc, file=sys.stderr)
        print(f"attneave generate: internal error (please report it): {exc}", file=sys.stderr)
        return 1
    for sid, warning in res.warnings:
        print(f"attneave generate: warning: {sid}: {warning}", file=sys.stderr)
    for note in res.notes:
        print(f"attneave generate: warning: {note}", file=sys.stderr)
    skipped = res.n_jobs - res.n_run
    note = f" ({skipped} already complete)" if skipped else ""
    flagged = (f"; {len(res.warnings)} flagged as possibly poor (manifest column 'warning')"
               if res.warnings else "")
    print(f"attneave generate: {res.n_stimuli} stimuli from {res.n_jobs} recipe calls in {res.directory}"
          f"{note}{flagged}", file=sys.stderr)
    return 0


def _one_line_warnings():
    """Python warnings met while generating as one line each (no file name and source line).

    Set before the workers are forked, so that they print the same way.
    """
    import contextlib
    import sys
    import warnings

    @contextlib.contextmanager
    def scope():
        old = warnings.showwarning

        def show(message, category, filename, lineno, file=None, line=None):
            text = " ".join(str(message).split())
            print(f"attneave generate: warning: {text}", file=file or sys.stderr)

        warnings.showwarning = show
        try:
            yield
        finally:
            warnings.showwarning = old

    return scope()
