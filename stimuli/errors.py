"""The one exception type that means "the input is wrong"."""


class InputError(ValueError):
    """Bad input: a file, key, row or value that cannot be used.

    The message is one line that names the file, key or row and says what was
    expected. The command line prints it and exits with status 2; library
    callers can catch it as a ``ValueError``.
    """
