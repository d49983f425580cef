"""The benchmark and validation scripts import only what the package has.

They are not run by the test command (they need ../shared/data or minutes),
so a module moved or renamed in the package would leave them broken
unnoticed: ``validate_guided.py`` imported ``attneave.stimuli.extraction.core`` for a
while after the extraction package was split. Every ``from X import Y`` of
the project's packages in them, at any depth, must resolve.
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parent.parent / "benchmarks"
SCRIPTS = sorted(BENCHMARKS.glob("*.py"))
PACKAGES = ("stimuli", "analysis")


def project_imports(path):
    """(line, module, name) of every ``from stimuli... / analysis... import name`` in a script."""
    tree = ast.parse(path.read_text(), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] in PACKAGES:
            for alias in node.names:
                yield node.lineno, node.module, alias.name
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] in PACKAGES:
                    yield node.lineno, alias.name, None


def test_there_are_scripts_to_check():
    assert len(SCRIPTS) >= 10


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_every_project_import_of_a_benchmark_resolves(script):
    broken = []
    for line, module, name in project_imports(script):
        try:
            mod = importlib.import_module(module)
        except ImportError as e:
            broken.append(f"{script.name}:{line}: {module}: {e}")
            continue
        if name is None or name == "*" or hasattr(mod, name):
            continue
        try:  # a submodule imported by name
            importlib.import_module(f"{module}.{name}")
        except ImportError:
            broken.append(f"{script.name}:{line}: {module} has no {name}")
    assert not broken, "\n".join(broken)
