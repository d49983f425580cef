"""Shared test set-up.

``slow_generate.py`` is a script the batch tests run in a child process (it
slows every job so that the test can kill the run midway); it must not be
imported by the doctest collection of this directory.
"""

collect_ignore = ["slow_generate.py"]
