"""Refresh the usage lines and option tables of docs/commands.md from the command line itself.

    python docs/make_commands.py          # rewrite docs/commands.md in place
    python docs/make_commands.py --check  # exit 1 if docs/commands.md is out of date

The prose of commands.md is written by hand; only the text between the markers
``<!-- usage:COMMAND -->`` ... ``<!-- /usage -->`` and ``<!-- options:COMMAND -->`` ...
``<!-- /options -->`` is generated, from the parser of ``attneave COMMAND --help``, so
that the page lists every option with the help text the command prints.
"""

import argparse
import re
import sys
from pathlib import Path

from attneave.cli import build_parser

PAGE = Path(__file__).with_name("commands.md")

#: Words for the arguments whose --help says nothing (positional inputs, plain values).
FILL = {
    "CONTOUR.csv": "contour file: columns x, y in image pixels (y down), in order",
    "POINTS.csv": "points to interpolate: columns x, y in image pixels (y down)",
    "CONFIG.yaml": "batch config (commented examples in configs/)",
    "--model {paper,vonmises}": "form of the surprisal model (default paper)",
    "--participants P": "number of simulated participants",
    "--seed S": "seed of the simulation",
    "--seed SEED": "seed of the simulation",
    "--title TEXT": "title of the first screen",
    "--end-text TEXT": "text of the last screen",
}


def _flags(action):
    if not action.option_strings:
        return action.metavar or action.dest
    flags = ", ".join(action.option_strings)
    if action.nargs == 0:
        return flags
    if action.metavar is not None:
        value = action.metavar if isinstance(action.metavar, str) else " ".join(action.metavar)
    elif action.choices:
        value = "{" + ",".join(map(str, action.choices)) + "}"
    else:
        value = action.dest.upper()
    return f"{flags} {value}"


def _row(action):
    flags = _flags(action)
    text = " ".join((action.help or "").replace("%%", "%").split())
    text = text.replace("%(default)s", str(action.default))
    if not text:
        text = FILL.get(flags) or ("output file or directory" if flags.startswith("-o,") else
                                   "one of the values listed" if action.choices else "")
    return f"| `{flags}` | {text.replace('|', chr(92) + '|')} |"


def _table(parser):
    rows = [_row(a) for a in parser._actions if not isinstance(a, argparse._HelpAction)]
    return "| option | meaning |\n|---|---|\n" + "\n".join(rows)


def _subparsers(parser):
    return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices


def generated():
    """{('usage' | 'options', command): markdown} for every command."""
    out = {}
    for name, sub in _subparsers(build_parser()).items():
        out["usage", name] = "```\n" + " ".join(sub.format_usage().split()).replace("usage: ", "") + "\n```"
        if name == "curve":  # one table per family
            out["options", name] = "\n\n".join(f"`attneave curve {family}`\n\n{_table(p)}"
                                               for family, p in _subparsers(sub).items())
        else:
            out["options", name] = _table(sub)
    return out


def refresh(text):
    """`text` with every marked block replaced; raises SystemExit naming a command without markers."""
    parts = generated()
    missing = [name for kind, name in parts if f"<!-- {kind}:{name} -->" not in text]
    if missing:
        raise SystemExit(f"{PAGE}: no markers for {', '.join(sorted(set(missing)))}; add a section for each")

    def fill(match):
        kind, name = match.group(1), match.group(2)
        return f"<!-- {kind}:{name} -->\n{parts[kind, name]}\n<!-- /{kind} -->"

    return re.sub(r"<!-- (usage|options):([\w-]+) -->\n.*?<!-- /\1 -->", fill, text, flags=re.S)


def main(argv):
    old = PAGE.read_text(encoding="utf-8")
    new = refresh(old)
    if "--check" in argv:
        if new != old:
            print(f"{PAGE} is out of date: run python docs/make_commands.py", file=sys.stderr)
            return 1
        return 0
    PAGE.write_text(new, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
