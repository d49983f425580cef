"""The architecture, checked: the rules of docs/design.md ("Architecture") that code review alone does not keep.

* one import name: every module is ``attneave.*``, and the folders that hold
  them are the ones setup.py maps into that namespace;
* ``attneave.stimuli`` never imports ``attneave.analysis`` or ``attneave.papers``;
* no import circle between the project's modules (lazy imports inside
  functions count: a circle is a design fault wherever the import sits);
* no private name (``_x``) imported from another module;
* modules stay small enough to hold one topic, and folders few enough to
  read (sub-packages show the architecture).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: package -> its folder in the repository, as setup.py maps them
ROOTS = {"attneave": ROOT / "src" / "attneave", "attneave.stimuli": ROOT / "stimuli",
         "attneave.analysis": ROOT / "analysis"}
MAX_LINES = 500
MAX_MODULES_PER_FOLDER = 16  # "about 15"; a package's __init__ counts


def _modules():
    out = {}
    for pkg, folder in ROOTS.items():
        for path in sorted(folder.rglob("*.py")):
            if pkg == "attneave" and any(path.is_relative_to(f) for f in ROOTS.values() if f != folder):
                continue
            parts = path.relative_to(folder).with_suffix("").parts
            parts = parts[:-1] if parts[-1] == "__init__" else parts
            out[".".join((pkg, *parts))] = path
    return out


MODULES = _modules()


def _imports(name, path):
    """(target module, imported names) of every import statement in a module."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, []
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            names = [a.name for a in node.names]
            # "from pkg import module" imports the module
            subs = [f"{base}.{n}" for n in names if f"{base}.{n}" in MODULES]
            yield base, [n for n in names if f"{base}.{n}" not in MODULES]
            for s in subs:
                yield s, []


def _graph():
    graph = {}
    for name, path in MODULES.items():
        targets = set()
        for target, _ in _imports(name, path):
            while target and target not in MODULES:
                target = target.rpartition(".")[0]
            if target and target != name:
                targets.add(target)
        graph[name] = targets
    return graph


def test_setup_maps_the_same_folders():
    tree = ast.parse((ROOT / "setup.py").read_text(encoding="utf-8"))
    roots = next(ast.literal_eval(n.value) for n in tree.body
                 if isinstance(n, ast.Assign) and [t.id for t in n.targets] == ["ROOTS"])
    assert roots == {k: str(v.relative_to(ROOT)) for k, v in ROOTS.items()}


def test_stimuli_never_imports_analysis_or_papers():
    bad = [(m, t) for m, ts in _graph().items() if m.startswith("attneave.stimuli")
           for t in ts if t.startswith(("attneave.analysis", "attneave.papers"))]
    assert not bad, bad


def test_every_import_of_the_project_is_absolute_and_under_attneave():
    bad = []
    for name, path in MODULES.items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level:
                bad.append(f"{name}: relative import")
            mods = ([a.name for a in node.names] if isinstance(node, ast.Import)
                    else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            bad += [f"{name}: imports {m}" for m in mods if m.split(".")[0] in ("stimuli", "analysis")]
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("folder", sorted({str(p.parent.relative_to(ROOT)) for p in MODULES.values()}))
def test_folder_is_small(folder):
    n = len(list((ROOT / folder).glob("*.py")))
    assert n <= MAX_MODULES_PER_FOLDER, f"{folder}: {n} modules (group them into sub-packages)"


def test_no_private_name_is_imported_from_another_module():
    bad = []
    for name, path in MODULES.items():
        for target, names in _imports(name, path):
            if target.split(".")[0] == "attneave" and target != name:
                bad += [f"{name} imports {target}.{n}" for n in names if n.startswith("_") and not n.startswith("__")]
    assert not bad, "\n".join(bad)


def test_no_import_circle():
    graph = _graph()
    state, stack, cycles = {}, [], []

    def visit(m):
        state[m] = 1
        stack.append(m)
        for t in sorted(graph[m]):
            if t.startswith(m + "."):
                continue  # a package entrance naming its own sub-modules is its face, not a circle
            if state.get(t) == 1:
                cycles.append(stack[stack.index(t):] + [t])
            elif t not in state:
                visit(t)
        stack.pop()
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m)
    assert not cycles, "\n".join(" -> ".join(c) for c in cycles)


@pytest.mark.parametrize("name", sorted(MODULES))
def test_module_is_small(name):
    n = len(MODULES[name].read_text(encoding="utf-8").splitlines())
    assert n <= MAX_LINES, f"{MODULES[name].relative_to(ROOT)}: {n} lines (split it by topic)"
