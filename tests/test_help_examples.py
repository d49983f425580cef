"""Every command's --help ends with an ``examples:`` section of command lines that the parser accepts."""

import argparse
import shlex

import pytest

from attneave.cli import COMMANDS, build_parser


def _subparsers(parser):
    (action,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return action.choices


PARSER = build_parser()


def examples_of(help_text):
    """The command lines of the examples section (backslash continuations joined, redirections cut)."""
    assert "\nexamples:\n" in help_text, "no examples: section"
    section = help_text.split("\nexamples:\n", 1)[1]
    lines, current = [], ""
    for raw in section.splitlines():
        if not raw.startswith("  "):
            break
        current += " " + raw.strip()
        if current.endswith("\\"):
            current = current[:-1]
            continue
        lines.append(current.strip())
        current = ""
    return lines


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_help_has_examples_the_parser_accepts(name):
    help_text = _subparsers(PARSER)[name].format_help()
    lines = examples_of(help_text)
    assert 2 <= len(lines) <= 3, lines
    for line in lines:
        words = shlex.split(line)
        if ">" in words:
            words = words[:words.index(">")]
        assert words[0] == "attneave" and words[1] == name, line
        assert words[1] in _subparsers(PARSER)        # the command exists
        try:
            PARSER.parse_args(words[1:])               # and its flags and values are the command's
        except SystemExit as exc:
            pytest.fail(f"{line!r}: the parser refuses it (exit {exc.code})")


def test_long_descriptions_are_still_wrapped():
    for name, p in _subparsers(PARSER).items():
        help_text = p.format_help()
        body = help_text.split("\nexamples:\n", 1)[0]
        # argparse's own usage lines may run long; the description must be wrapped (it was before examples)
        description = body.split("\n\n", 1)[1]
        too_long = [line for line in description.splitlines() if len(line) > 100]
        assert not too_long, (name, too_long[:2])
