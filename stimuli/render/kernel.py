"""The compiled kernel of the exact rasteriser, if it was built.

``coverage_kernel.c`` (plain C99, built at install by ``setup.py`` as an
optional extension with ``coverage_bands.c``) walks a stream's pieces
across the pixel cells and deposits their area and cover exactly as
:func:`attneave.stimuli.render.raster.accumulate` does, then takes the column prefix
sum and paints 8-bit pixels in one pass. 8-bit silhouettes
(:func:`ring_u8`, :func:`stream_u8`) are painted band by band of rows,
every pixel of the image in one call, so that the working set stays in the
cache (see ``coverage_bands.c``). It is loaded with ctypes; if it was not
built, cannot be loaded, lacks an entry (a stale build), or
``ATTNEAVE_NUMPY_RENDER=1`` is set, :data:`KERNEL` is ``'numpy'`` and the
numpy path, the reference, is used.
"""

from __future__ import annotations

import ctypes
from pathlib import Path

import numpy as np

from attneave.stimuli.compiled import address as _address
from attneave.stimuli.compiled import load_library
from attneave.stimuli.render.workspace import scratch

_HERE = Path(__file__).resolve().parent


_D, _L, _P, _I = ctypes.c_double, ctypes.c_long, ctypes.c_void_p, ctypes.c_int
_IMAGE = [_P, _L, _L, _L, _L, _L, _P]  # img, h, w, row_step, pix_step, channels, luts
#: The kernel's interface as Python calls it: name -> (restype, argtypes), one
#: entry per prototype of ``coverage_api.h`` (checked by tests/test_kernel_interface.py).
SIGNATURES = {
    "attneave_deposit": (_D, [_P, _P, _L, _P, _L, _L, _L, _L, _L, _L, _P]),
    "attneave_integrate": (None, [_P, _L, _L]),
    "attneave_paint_u8": (None, [_P, _L, _L, _I, _P, _L, _L, _P, _P, _P]),
    "attneave_ring_u8": (_D, [_P, _L, _I, *_IMAGE]),
    "attneave_stream_u8": (_D, [_P, _P, _L, _P, *_IMAGE]),
}


LIB = load_library(_HERE, "coverage_kernel", "ATTNEAVE_NUMPY_RENDER", SIGNATURES)
#: Which rasteriser runs: ``'c'`` (the compiled kernel) or ``'numpy'``.
KERNEL = "numpy" if LIB is None else "c"


def deposit(p, bridge, h, w, box):
    """(dep, area): the pieces of stream `p` deposited over `box`.

    `p` is a (2, n) float64 stream (x and y rows shifted by +0.5, see
    :mod:`attneave.stimuli.render.raster`), `bridge` its n - 1 flags or None, `box`
    ``(r0, r1, c0, c1)``. `dep` is the (r1 - r0 + 2, c1 - c0 + 1) float64
    array of deposits (before the column prefix sum), a scratch buffer to
    be used before the next call; `area` is the winding integral over the
    image.
    """
    r0, r1, c0, c1 = box
    bh, bw = r1 - r0 + 1, c1 - c0 + 1
    dep = scratch("kernel_deposits", (bh + 1, bw))
    x, y = np.ascontiguousarray(p[0], np.float64), np.ascontiguousarray(p[1], np.float64)
    flags = None if bridge is None else np.ascontiguousarray(bridge, np.uint8)
    area = LIB.attneave_deposit(
        _address(x), _address(y), x.size, None if flags is None else _address(flags),
        h, w, r0, c0, bh, bw, _address(dep),
    )
    return dep, area


def integrate(a):
    """Column prefix sum of the C-contiguous float64 array `a`, in place."""
    LIB.attneave_integrate(_address(a), a.shape[0], a.shape[1])
    return a


def paint_u8(a, integrated, out, lut=None):
    """``out = lut[rint(255 * min(|win|, 1))]`` with `win` the winding integral.

    `a` (C-contiguous float64) holds the winding integral if `integrated`,
    else deposits, integrated on the way (`a` is left as it is). `out` is a uint8 view of
    the same height and width (any strides, e.g. one channel of an RGB
    image), `lut` 256 uint8 levels, or None for black on white (255 - level).
    """
    if lut is not None:
        lut = np.ascontiguousarray(lut, np.uint8)
    levels = scratch("kernel_levels", out.shape[1], np.intc)
    run = scratch("kernel_run", out.shape[1])
    row_step, pix_step = out.strides[:2]
    LIB.attneave_paint_u8(
        _address(a), out.shape[0], out.shape[1], 0 if integrated else 1,
        _address(out), row_step, pix_step, None if lut is None else _address(lut),
        _address(levels), _address(run),
    )


def _image_u8(img, luts):
    """The image arguments of the 8-bit renderers: `img` (h, w) or (h, w, c)
    C-contiguous uint8, `luts` None or a C-contiguous (c, 256) uint8 array."""
    h, w = img.shape[:2]
    channels = 1 if img.ndim == 2 else img.shape[2]
    return (_address(img), h, w, img.strides[0], img.strides[1], channels,
            None if luts is None else _address(luts))


def _checked(area):
    if area != area:  # NaN: the kernel could not allocate its buffers
        raise MemoryError("the render kernel could not allocate its scratch buffers")
    return area


def ring_u8(ring, oriented, img, luts=None):
    """Paint one closed ring into the 8-bit image `img`, every pixel of it.

    `ring` is a C-contiguous (n, 2) float64 array of ``(x, y)`` points
    (image pixels, pixel centres at integers), `img` a C-contiguous (h, w)
    or (h, w, c) uint8 array, `luts` None (grey, black on white: 255 -
    level) or a C-contiguous (c, 256) uint8 array of each channel's colour
    per coverage level ``rint(255 * coverage)``. Returns the winding
    integral over the image; with `oriented`, that of the ring turned to a
    positive shoelace sum (see :func:`attneave.stimuli.render.raster.ring_area`).
    Returns NaN, `img` undefined, unless the ring is plain: finite, at least
    3 distinct points, the first not repeated at the end (the caller then
    takes its validating path), or if memory ran out.
    """
    return LIB.attneave_ring_u8(_address(ring), len(ring), oriented, *_image_u8(img, luts))


def stream_u8(p, bridge, img, luts=None):
    """Paint a stream (see :mod:`attneave.stimuli.render.raster`) into `img` as
    :func:`ring_u8` does; returns the winding integral over the image."""
    x, y = np.ascontiguousarray(p[0], np.float64), np.ascontiguousarray(p[1], np.float64)
    flags = None if bridge is None else np.ascontiguousarray(bridge, np.uint8)  # kept alive
    return _checked(LIB.attneave_stream_u8(
        _address(x), _address(y), x.size, None if flags is None else _address(flags),
        *_image_u8(img, luts),
    ))
