"""The ``attneave`` command line.

Each package owns its commands: :mod:`attneave.stimuli.commands` those about shapes
(surprisal, curve, spline, generate, extract), :mod:`attneave.analysis.commands` those
about people (figures, analyze, simulate, power, experiment). Each command module defines
``add_parser(subparsers)`` and ``run(args) -> int``; this module only
assembles them. Heavy imports happen inside ``run`` so that ``attneave
--help`` stays fast.

Exit status: 0 on success, 1 when a batch finished but some items failed or
the disk was full, 2 on bad input (one line on stderr, no traceback), 130 on
Ctrl-C.
"""

from __future__ import annotations

import argparse
import importlib
import re
import sys

from attneave.stimuli.errors import InputError

COMMANDS = {
    "surprisal": "attneave.stimuli.commands.surprisal",
    "curve": "attneave.stimuli.commands.curve",
    "figures": "attneave.papers.command",
    "spline": "attneave.stimuli.commands.spline",
    "generate": "attneave.stimuli.commands.generate",
    "extract": "attneave.stimuli.commands.extract",
    "analyze": "attneave.analysis.commands.analyze",
    "simulate": "attneave.analysis.commands.simulate",
    "power": "attneave.analysis.commands.power",
    "experiment": "attneave.analysis.commands.experiment",
}


#: A negative number as an option value: argparse's own pattern takes
#: ``-5`` and ``-0.5`` but not ``-1e9``, ``-1.5E-3`` or ``-5.``, which it
#: reads as unknown options ("expected one argument").
_NEGATIVE_NUMBER = re.compile(r"^-(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$")


class _Parser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line and exit 2, and
    which takes negative numbers in scientific notation as option values
    (``--alpha -1e9``). No option of ``attneave`` looks like a number, so
    nothing else changes."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser():
    parser = _Parser(
        prog="attneave",
        description="Information along shape contours: stimuli, surprisal, QIC splines, analysis.",
    )
    from attneave.stimuli import __version__

    parser.add_argument("--version", action="version", version=f"attneave {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=_Parser)
    for name, module_name in COMMANDS.items():
        module = importlib.import_module(module_name)
        p = module.add_parser(sub)
        p.set_defaults(func=module.run)
    return parser


def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)
    from attneave.analysis.argnames import cli_names

    try:
        with cli_names():  # library messages name the flags, not the Python parameters
            status = args.func(args)
    except InputError as exc:
        print(f"attneave {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"attneave {args.command}: interrupted", file=sys.stderr)
        return 130
    except OSError as exc:
        # a full, over-quota or failing disk is neither bad input nor a bug: one line, exit 1
        # (outputs are written atomically, so nothing is left half-written); anything else is raised
        from attneave.stimuli.io import disk_error_exit

        return disk_error_exit(args.command, getattr(exc, "filename", None) or "output", exc,
                               note="nothing was left half-written")
    return int(status or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
