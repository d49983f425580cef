"""`attneave analyze` (not yet implemented)."""


def add_parser(sub):
    return sub.add_parser("analyze", help="(not yet implemented)")


def run(args):
    from stimuli.errors import InputError

    raise InputError("'analyze' is not implemented yet")
