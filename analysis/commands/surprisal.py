"""`attneave surprisal` (not yet implemented)."""


def add_parser(sub):
    return sub.add_parser("surprisal", help="(not yet implemented)")


def run(args):
    from stimuli.errors import InputError

    raise InputError("'surprisal' is not implemented yet")
