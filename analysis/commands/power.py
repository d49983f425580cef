"""`attneave power` (not yet implemented)."""


def add_parser(sub):
    return sub.add_parser("power", help="(not yet implemented)")


def run(args):
    from stimuli.errors import InputError

    raise InputError("'power' is not implemented yet")
