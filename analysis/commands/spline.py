"""`attneave spline` (not yet implemented)."""


def add_parser(sub):
    return sub.add_parser("spline", help="(not yet implemented)")


def run(args):
    from stimuli.errors import InputError

    raise InputError("'spline' is not implemented yet")
