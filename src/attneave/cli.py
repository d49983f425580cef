"""The ``attneave`` command line.

Each package owns its commands: :mod:`attneave.stimuli.commands` those about shapes
(surprisal, curve, spline, generate, extract), :mod:`attneave.analysis.commands` those
about people (figures, analyze, simulate, power, experiment). Each command module defines
``add_parser(subparsers)`` and ``run(args) -> int``; this module only
assembles them. Heavy imports happen inside ``run`` so that ``attneave
--help`` stays fast.

Exit status: 0 on success, 1 when a batch finished but some items failed or
the disk was full, 2 on bad input (one line on stderr, no traceback), and
128 + the signal's number when stopped by SIGINT (Ctrl-C, 130), SIGTERM (what
``timeout``, SLURM and systemd send, 143) or SIGHUP (a closed terminal, 129).

The three signals are handled alike: the command stops where it is, removes
its temporaries and says so in one line, without a traceback. Every output is
then complete or absent (directories are built aside and swapped in, files
written under a temporary name and renamed); ``generate`` and ``extract``
keep what they completed and a rerun completes it. A signal that arrives
after the output was written still exits with 128 + its number (the line
says the output is complete), unless it comes in the last milliseconds of
the interpreter's shutdown, when it is ignored. A second signal during the
cleanup is ignored; ``kill -9`` is not catchable, and the temporaries it leaves
(``.attneave-tmp-<pid>-...``) are removed by the next run in that place.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import re
import signal
import sys
import threading

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
    "info": "attneave.info",
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


#: The signals that stop a command as Ctrl-C does.
STOP_SIGNALS = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


#: Commands that keep the outputs they completed when stopped, and complete them when rerun.
RESUMABLE = frozenset({"generate", "extract"})


class Interrupted(KeyboardInterrupt):
    """Raised in the main thread by SIGINT, SIGTERM or SIGHUP; `signum` says which.

    A :class:`KeyboardInterrupt`, so that every ``except BaseException:
    cleanup; raise`` of the library removes its temporaries as for Ctrl-C.
    """

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


class _Stopper:
    """Signal handlers of one command: the first stop signal raises :class:`Interrupted`;
    later ones (during the cleanup it starts) are remembered, not raised."""

    def __init__(self, command):
        self.command = command
        self.signum = None

    def during(self, signum, frame):
        if self.signum is None:
            self.signum = signum
            raise Interrupted(signum)

    def swallowed(self, unraisable):
        """`sys.unraisablehook`: the stop landed where Python cannot raise (a weakref or GC
        callback, a ``__del__``, such as importlib's module-lock callbacks) and was dropped
        there with an "Exception ignored" traceback. Say nothing, and deliver it again a
        moment later, when the main thread has left that callback."""
        exc = unraisable.exc_value
        if not isinstance(exc, Interrupted) or self.signum != exc.signum:
            return _PREVIOUS_UNRAISABLEHOOK(unraisable)
        self.signum = None
        # a real signal to the main thread, not _thread.interrupt_main: it also breaks a blocking wait
        timer = threading.Timer(0.01, signal.pthread_kill, args=(threading.main_thread().ident, exc.signum))
        timer.daemon = True
        timer.start()

    def after(self, signum, frame):
        # the command has returned: its output is complete. Raising now would land in an
        # interpreter shutdown hook (tqdm's, concurrent.futures') as a traceback; say it and go.
        _exit_after(self.command, signum)


def _exit_after(command, signum):
    with contextlib.suppress(Exception):
        sys.stdout.flush()
        print(f"attneave {command}: {signal.Signals(signum).name} after the command had finished; "
              "its output is complete", file=sys.stderr)
        sys.stderr.flush()
    os._exit(128 + signum)


_PREVIOUS_UNRAISABLEHOOK = sys.unraisablehook


def _install(handler):
    """Set `handler` for every stop signal; return the previous handlers (None outside the main thread)."""
    if threading.current_thread() is not threading.main_thread():
        return None
    previous = {s: signal.signal(s, handler) for s in STOP_SIGNALS}
    stopper = getattr(handler, "__self__", None)
    previous["unraisablehook"] = sys.unraisablehook
    sys.unraisablehook = stopper.swallowed if isinstance(stopper, _Stopper) else _PREVIOUS_UNRAISABLEHOOK
    return previous


def _restore(previous):
    previous = dict(previous or {})
    if "unraisablehook" in previous:
        sys.unraisablehook = previous.pop("unraisablehook")
    for s, h in previous.items():
        signal.signal(s, h)


def _owns_process():
    """True when this process is the ``attneave`` command (console script or ``python -m attneave``)."""
    top = sys.modules.get("__main__")
    spec = getattr(top, "__spec__", None)
    if spec is not None:
        return spec.name in ("attneave.__main__", "attneave.cli")
    return os.path.basename(getattr(top, "__file__", "") or "") == "attneave"


def _last_exit_hook():
    """At the very end of the process, after every other exit hook: ignore the stop signals.

    The interpreter's shutdown puts back the default action (death by the
    signal, with no word) of every signal whose handler is a Python
    function; an ignored one stays ignored, so a signal in the last
    milliseconds of a finished command changes nothing (exit status 0).
    """
    for s in STOP_SIGNALS:
        with contextlib.suppress(ValueError, OSError):
            signal.signal(s, signal.SIG_IGN)


_OWNER = _owns_process()
_CURRENT = _Stopper("")
if _OWNER:
    # from the first moment: a signal while the commands' modules load is a stop like any other
    _install(_CURRENT.during)
    import atexit

    atexit.register(_last_exit_hook)  # registered first, so it runs last


def main(argv=None):
    """Run one ``attneave`` command; return its exit status.

    Parameters
    ----------
    argv : list of str, optional
        The arguments; None reads ``sys.argv``. When this process is the
        command (the console script, ``python -m attneave``) and `argv` is
        None, the signal handlers stay in place until the process exits;
        otherwise (a caller running commands in its own process) the
        caller's handlers are restored on return.
    """
    global _CURRENT
    stopper = _CURRENT if _OWNER and _CURRENT.signum is None else _Stopper("")
    _CURRENT = stopper
    previous = _install(stopper.during)
    try:
        try:
            parser = build_parser()
            args = parser.parse_args(argv)
        except KeyboardInterrupt as exc:
            return _interrupted("", stopper, exc)
        stopper.command = args.command
        return _run(args, stopper)
    finally:
        if argv is None and _OWNER and previous is not None:
            _install(stopper.after)
        else:
            _restore(previous)


def _interrupted(command, stopper, exc):
    signum = getattr(exc, "signum", None) or stopper.signum or signal.SIGINT
    name = {signal.SIGINT: "interrupted"}.get(signum, f"stopped by {signal.Signals(signum).name}")
    fate = ("what was completed is kept; rerun the same command to complete it" if command in RESUMABLE
            else "nothing was left half-written")
    print(f"attneave{' ' + command if command else ''}: {name}; {fate}", file=sys.stderr)
    return 128 + signum


def _run(args, stopper):
    try:
        from attneave.analysis.argnames import cli_names  # imports numpy: a signal may land there

        with cli_names():  # library messages name the flags, not the Python parameters
            status = args.func(args)
    except InputError as exc:
        if stopper.signum is not None:  # a signal during the error's own cleanup: stopped all the same
            return _interrupted(args.command, stopper, exc)
        print(f"attneave {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        return _interrupted(args.command, stopper, exc)
    except OSError as exc:
        # a full, over-quota or failing disk is neither bad input nor a bug: one line, exit 1
        # (outputs are written atomically, so nothing is left half-written); anything else is raised
        from attneave.stimuli.io import disk_error_exit

        return disk_error_exit(args.command, getattr(exc, "filename", None) or "output", exc,
                               note="nothing was left half-written")
    if stopper.signum is not None:  # a signal that a library swallowed (a worker pool's wait)
        return _interrupted(args.command, stopper, None)
    return int(status or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
