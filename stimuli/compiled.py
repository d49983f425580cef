"""Loading the optional compiled kernels: the exact rasteriser's
(:mod:`attneave.stimuli.render.kernel`) and the QIC spline's
(:mod:`attneave.stimuli.curves.qic.kernel`).

Each kernel is plain C99 built by ``setup.py`` as an optional extension and
called through ctypes. Its interface is declared once on each side: the C
prototypes in a header (``coverage_api.h``, ``qic_api.h``) that the C files
include, and the ctypes signatures in the kernel module's ``SIGNATURES``;
``tests/test_kernel_interface.py`` checks that the two agree.

Every load is recorded in :data:`STATUS` (what ``attneave info`` prints):
which path runs and why, so that an install without a C compiler (numpy
path, 2-3x slower) is never silent.
"""

from __future__ import annotations

import ctypes
import importlib.machinery
import os
from pathlib import Path

__all__ = ["load_library", "declare", "address", "STATUS"]

#: kernel stem -> {"path": 'c' or 'numpy', "reason": str, "file": str or None}
STATUS: dict[str, dict] = {}


def _record(stem, path, reason, file=None):
    STATUS[stem] = {"path": path, "reason": reason, "file": None if file is None else str(file)}


def load_library(directory, stem, disable_env, signatures=None):
    """The compiled library ``<directory>/<stem><extension suffix>``, or None.

    None if it was not built, cannot be loaded, lacks an entry of
    `signatures` (a stale build), or the environment variable `disable_env`
    is set (to anything but '' or '0': the numpy path is then forced). The
    outcome and its reason are recorded in :data:`STATUS` under `stem`.

    Parameters
    ----------
    directory : path-like
        Where the extension was built (the kernel module's folder).
    stem : str
        The extension's name without its suffix.
    disable_env : str
        The environment variable that forces the numpy path.
    signatures : dict, optional
        Function name -> ``(restype, argtypes)``, declared on the library.

    Examples
    --------
    >>> load_library(".", "no_such_kernel", "ATTNEAVE_NUMPY_RENDER") is None
    True
    >>> STATUS["no_such_kernel"]["path"]
    'numpy'
    """
    if os.environ.get(disable_env, "") not in ("", "0"):
        _record(stem, "numpy", f"{disable_env}={os.environ[disable_env]} forces the numpy path")
        return None
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        path = Path(directory) / f"{stem}{suffix}"
        if path.exists():
            break
    else:
        _record(stem, "numpy", "not built (no C compiler at install time, or the build failed)")
        return None
    try:
        lib = ctypes.CDLL(str(path))
    except OSError as exc:
        _record(stem, "numpy", f"cannot be loaded: {exc}", path)
        return None
    try:
        declare(lib, signatures or {})
    except AttributeError as exc:
        _record(stem, "numpy", f"stale build, an entry is missing ({exc}); reinstall to rebuild it", path)
        return None
    _record(stem, "c", "compiled kernel loaded", path)
    return lib


def declare(lib, signatures):
    """Set ``restype`` and ``argtypes`` of every function in `signatures`."""
    for name, (restype, argtypes) in signatures.items():
        fn = getattr(lib, name)
        fn.restype = restype
        fn.argtypes = list(argtypes)
    return lib


def address(a):
    """The data address of a numpy array (``a.ctypes.data`` builds a helper
    object, about a microsecond)."""
    return a.__array_interface__["data"][0]
