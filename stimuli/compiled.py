"""Loading the optional compiled kernels (plain C99 files built by
``setup.py`` as optional extensions, called through ctypes): the exact
rasteriser's (:mod:`attneave.stimuli.render.kernel`) and the QIC spline's
(:mod:`attneave.stimuli.curves.qic.kernel`).
"""

from __future__ import annotations

import ctypes
import importlib.machinery
import os
from pathlib import Path

__all__ = ["load_library", "address"]


def load_library(directory, stem, disable_env):
    """The compiled library ``<directory>/<stem><extension suffix>``, or None
    if it was not built, cannot be loaded, or the environment variable
    `disable_env` is set (to anything but '' or '0': the numpy path is then
    forced).

    Examples
    --------
    >>> load_library(".", "no_such_kernel", "ATTNEAVE_NUMPY_RENDER") is None
    True
    """
    if os.environ.get(disable_env, "") not in ("", "0"):
        return None
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        path = Path(directory) / f"{stem}{suffix}"
        if path.exists():
            try:
                return ctypes.CDLL(str(path))
            except OSError:
                return None
    return None


def address(a):
    """The data address of a numpy array (``a.ctypes.data`` builds a helper
    object, about a microsecond)."""
    return a.__array_interface__["data"][0]
