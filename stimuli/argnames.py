"""How an error message names an argument: the Python parameter, or the command's flag.

One rule for the library's checks and the commands: inside :func:`cli_names`
(``attneave.cli.main`` wraps every command in it) :func:`arg` names the flag
(``--beta-sd``), elsewhere the Python parameter (``beta_sd``). No numpy here:
``attneave --help`` and every command import this module.
"""

from __future__ import annotations

import contextlib
import contextvars

__all__ = ["arg", "cli_names"]

_CLI = contextvars.ContextVar("attneave_cli_names", default=False)
#: Parameters whose flag is not ``--`` + the name with dashes.
_FLAGS = {"n": "-n"}


def arg(name):
    """`name` (a Python parameter), or its ``attneave`` flag inside :func:`cli_names`.

    Examples
    --------
    >>> arg("group_simulations")
    'group_simulations'
    >>> with cli_names():
    ...     arg("group_simulations"), arg("n")
    ('--group-simulations', '-n')
    """
    if not _CLI.get():
        return name
    return _FLAGS.get(name, "--" + name.replace("_", "-"))


@contextlib.contextmanager
def cli_names():
    """Within this block, :func:`arg` names flags (``--beta-sd``) instead of parameters (``beta_sd``)."""
    token = _CLI.set(True)
    try:
        yield
    finally:
        _CLI.reset(token)
