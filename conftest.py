"""Doctest namespace for the docstring examples in ``stimuli`` and ``analysis``.

The examples are run by the test command (``--doctest-modules``); they may
use ``np`` without importing it, as the scikit-image docstrings do.
"""

import numpy as np
import pytest


@pytest.fixture(autouse=True)
def _doctest_numpy(doctest_namespace):
    doctest_namespace["np"] = np
