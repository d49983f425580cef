"""The docstring examples of every module of the installed package, run as doctests.

The examples are part of the documentation (numpy style, as in
scikit-image); they may use ``np`` without importing it. They are collected
from the installed ``attneave`` package by module name, not from the
repository's folders, so the names they show are the names users import.
"""

from __future__ import annotations

import doctest
import importlib
import importlib.util
import pkgutil

import numpy as np
import pytest


def _modules():
    # the libraries are mapped into the namespace from their own folders, so each
    # is walked from its own __path__ (an editable install's finder is not a folder)
    names = set()
    for root in ("attneave", "attneave.stimuli", "attneave.analysis"):
        package = importlib.import_module(root)
        names.add(root)
        for info in pkgutil.walk_packages(package.__path__, root + "."):
            spec = importlib.util.find_spec(info.name)
            # the C kernels are shared libraries loaded with ctypes, not Python modules
            if not info.name.endswith("__main__") and spec.origin.endswith(".py"):
                names.add(info.name)
    return sorted(names)


MODULES = _modules()


def test_every_library_folder_is_walked():
    # a sub-package without __init__.py would silently drop its examples
    assert any(m.startswith("attneave.stimuli.curves.qic.") for m in MODULES)
    assert any(m.startswith("attneave.analysis.models.") for m in MODULES)
    assert len(MODULES) > 130


def _examples():
    """(id, module name, test name) of every docstring with examples, one test each (as --doctest-modules)."""
    out = []
    finder = doctest.DocTestFinder(exclude_empty=True)
    for name in MODULES:
        module = importlib.import_module(name)
        for test in finder.find(module, name):
            if test.examples and test.name.startswith(name):  # not a name re-exported from elsewhere
                out.append(test.name)
    return sorted(set(out))


EXAMPLES = _examples()


@pytest.mark.parametrize("test_name", EXAMPLES)
def test_docstring_examples(test_name):
    module_name = next(m for m in sorted(MODULES, key=len, reverse=True) if test_name.startswith(m + ".")
                       or test_name == m)
    module = importlib.import_module(module_name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    (test,) = [t for t in finder.find(module, module_name, globs={"np": np, **vars(module)}) if t.name == test_name]
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS)
    runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed in {test_name}"
