"""`attneave generate` (not yet implemented)."""


def add_parser(sub):
    return sub.add_parser("generate", help="(not yet implemented)")


def run(args):
    from stimuli.errors import InputError

    raise InputError("'generate' is not implemented yet")
