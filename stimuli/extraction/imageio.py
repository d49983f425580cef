"""Reading images: files as stored, arrays, their grey and alpha channels.

Row ``i``, column ``j`` of every array is the pixel centred at ``(x, y) = (j, i)``
(x = column, y = row, y down, pixel centres at integer coordinates).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from stimuli.errors import InputError

__all__ = ["IMAGE_SUFFIXES", "read_image", "load_image", "split_channels", "full_scale"]

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp")


def read_image(path):
    """Read an image file as it is stored (no colour management, no EXIF rotation).

    Parameters
    ----------
    path : str or Path
        A PNG, JPEG, TIFF or BMP file; grey, RGB or RGBA; 8 or 16 bit
        (32-bit float TIFF also works).

    Returns
    -------
    ndarray
        ``(H, W)`` for grey, ``(H, W, 3)`` RGB or ``(H, W, 4)`` RGBA
        (channels in RGB order, not OpenCV's BGR), in the file's own dtype
        (uint8, uint16 or float32). Row ``i``, column ``j`` is the pixel
        centred at ``(x, y) = (j, i)``.

    Raises
    ------
    InputError
        The file does not exist, is empty, or cannot be decoded (corrupt or
        not an image), naming the file.
    """
    import cv2

    path = Path(path)
    try:
        data = np.fromfile(path, dtype=np.uint8)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except (IsADirectoryError, PermissionError, OSError) as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    if data.size == 0:
        raise InputError(f"{path}: empty file, expected a PNG, JPEG, TIFF or BMP image")
    img = _quiet_imdecode(cv2, data)
    if img is None or img.size == 0:
        raise InputError(f"{path}: not a readable image (corrupt, or not PNG, JPEG, TIFF or BMP)")
    if img.ndim == 3:
        if img.shape[2] == 3:
            img = cv2.cvtColor(img, cv2.COLOR_BGR2RGB)
        elif img.shape[2] == 4:
            img = cv2.cvtColor(img, cv2.COLOR_BGRA2RGBA)
        elif img.shape[2] == 1:
            img = img[:, :, 0]
    return img


def _quiet_imdecode(cv2, data):
    """cv2.imdecode without OpenCV's own warnings on stderr (we raise instead)."""
    log = getattr(getattr(cv2, "utils", None), "logging", None)
    if log is None:  # pragma: no cover - very old OpenCV
        return cv2.imdecode(data, cv2.IMREAD_UNCHANGED)
    old = log.getLogLevel()
    log.setLogLevel(log.LOG_LEVEL_SILENT)
    try:
        return cv2.imdecode(data, cv2.IMREAD_UNCHANGED)
    finally:
        log.setLogLevel(old)


def load_image(image_or_path):
    """``(array, name)`` from a path (read with :func:`read_image`) or an array."""
    if isinstance(image_or_path, (str, Path)):
        return read_image(image_or_path), str(image_or_path)
    try:
        img = np.asarray(image_or_path)
    except Exception:  # noqa: BLE001 - anything that is not an array
        raise InputError("image: expected a path or an array") from None
    return img, "image"


def split_channels(img, name):
    """Grey (float, image units) and alpha (or None) of an image array."""
    if img.dtype == bool:
        img = img.astype(np.uint8)
    if not (np.issubdtype(img.dtype, np.integer) or np.issubdtype(img.dtype, np.floating)):
        raise InputError(f"{name}: pixel type {img.dtype} is not numeric")
    if img.ndim == 2:
        grey, alpha = img, None
    elif img.ndim == 3 and img.shape[2] in (1, 2, 3, 4):
        c = img.shape[2]
        alpha = img[:, :, c - 1] if c in (2, 4) else None
        if c <= 2:
            grey = img[:, :, 0]
        else:
            rgb = img[:, :, :3].astype(np.float32)
            grey = rgb[:, :, 0] * np.float32(0.299) + rgb[:, :, 1] * np.float32(0.587) + rgb[:, :, 2] * np.float32(0.114)
    else:
        raise InputError(f"{name}: expected a grey (H, W), RGB or RGBA (H, W, 3|4) image, got shape {img.shape}")
    if min(grey.shape) < 2:
        raise InputError(f"{name}: image of {grey.shape[1]}x{grey.shape[0]} pixels is too small")
    if np.issubdtype(grey.dtype, np.floating) and not np.isfinite(grey).all():
        raise InputError(f"{name}: image has NaN or infinite pixels")
    return grey, alpha


def full_scale(dtype):
    """The full-scale value of an image dtype (its maximum for integers, 1 for floats)."""
    if np.issubdtype(dtype, np.integer):
        return float(np.iinfo(dtype).max)
    return 1.0
