"""`attneave figures` (not yet implemented)."""


def add_parser(sub):
    return sub.add_parser("figures", help="(not yet implemented)")


def run(args):
    from stimuli.errors import InputError

    raise InputError("'figures' is not implemented yet")
