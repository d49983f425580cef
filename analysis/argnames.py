"""How an error message names an argument: the Python parameter, or the command's flag.

The one rule lives with the validators, :func:`attneave.stimuli.argnames.arg`
and :func:`attneave.stimuli.argnames.cli_names` (the library's checks name
arguments the same way); this module re-exports them for the analysis package.

Examples
--------
>>> arg("group_simulations")
'group_simulations'
>>> with cli_names():
...     arg("group_simulations"), arg("n")
('--group-simulations', '-n')
"""

from __future__ import annotations

from attneave.stimuli.argnames import arg, cli_names

__all__ = ["arg", "cli_names"]
