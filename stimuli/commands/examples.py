"""The help formatter of every command: descriptions wrapped, the ``examples:`` epilog kept as written.

Each command's ``--help`` ends with an ``examples:`` section of real
command lines (one per line, continuations indented), which argparse's
default formatter would re-wrap into one paragraph.
"""

from __future__ import annotations

import argparse

__all__ = ["ExamplesFormatter", "examples"]


class ExamplesFormatter(argparse.RawDescriptionHelpFormatter):
    """Like argparse's default formatter, but a text beginning ``examples:`` is printed as written.

    Examples
    --------
    >>> p = argparse.ArgumentParser(prog="x", description="a " * 60, formatter_class=ExamplesFormatter,
    ...                             epilog=examples("x run", "x stop"))
    >>> help_text = p.format_help()
    >>> max(len(line) for line in help_text.splitlines()) <= 80, "examples:\\n  x run\\n  x stop" in help_text
    (True, True)
    """

    def _fill_text(self, text, width, indent):
        if text.lstrip().startswith(("examples:", "families and their parameters:")):
            return super()._fill_text(text, width, indent)  # raw: as written
        return argparse.HelpFormatter._fill_text(self, text, width, indent)


def examples(*lines):
    """An ``examples:`` epilog of command lines (a line may hold ``\\n`` and an indented continuation).

    Examples
    --------
    >>> print(examples("attneave info", "attneave info --json > install.json"))
    examples:
      attneave info
      attneave info --json > install.json
    """
    return "examples:\n" + "\n".join("  " + line.replace("\n", "\n  ") for line in lines)
