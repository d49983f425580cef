"""`attneave simulate` (not yet implemented)."""


def add_parser(sub):
    return sub.add_parser("simulate", help="(not yet implemented)")


def run(args):
    from stimuli.errors import InputError

    raise InputError("'simulate' is not implemented yet")
