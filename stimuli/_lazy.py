"""Lazy package entrances.

A package's ``__init__`` lists the public names it offers and the module
each one lives in; the module is imported on first access. This keeps
``import stimuli`` (and every ``attneave`` command) from paying for OpenCV,
pydantic, scipy and the renderer when it needs none of them.
"""

from __future__ import annotations

import importlib
import importlib.util


def attach(package, exports):
    """Return ``(__getattr__, __dir__, __all__)`` for a package.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    exports : dict of str to str
        Public name -> module that defines it, absolute or relative to
        `package` (leading dot). A name that equals its module's last
        component and maps to that module (``"curves": ".curves"``) exports
        the module itself.

    Returns
    -------
    getattr, dir, all
        Functions to assign to the package's ``__getattr__`` and
        ``__dir__`` (PEP 562), and the sorted ``__all__``.
    """
    resolved = {name: importlib.util.resolve_name(mod, package) for name, mod in exports.items()}

    def __getattr__(name):
        try:
            module_name = resolved[name]
        except KeyError:
            raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
        module = importlib.import_module(module_name)
        value = module if module_name.rpartition(".")[2] == name and not hasattr(module, name) else getattr(module, name)
        return value

    def __dir__():
        return sorted(resolved)

    return __getattr__, __dir__, sorted(resolved)
