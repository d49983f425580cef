"""`attneave curve` (not yet implemented)."""


def add_parser(sub):
    return sub.add_parser("curve", help="(not yet implemented)")


def run(args):
    from stimuli.errors import InputError

    raise InputError("'curve' is not implemented yet")
