"""`attneave extract` (not yet implemented)."""


def add_parser(sub):
    return sub.add_parser("extract", help="(not yet implemented)")


def run(args):
    from stimuli.errors import InputError

    raise InputError("'extract' is not implemented yet")
