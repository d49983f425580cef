"""Reading images: files as stored, arrays, their grey and alpha channels.

Row ``i``, column ``j`` of every array is the pixel centred at ``(x, y) = (j, i)``
(x = column, y = row, y down, pixel centres at integer coordinates).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_int

__all__ = ["IMAGE_SUFFIXES", "MAX_PIXELS", "DecoderWarning", "ImageFile", "open_image", "read_image", "header_size", "load_image", "split_channels", "full_scale",
           "MAX_INTEGER_LEVELS"]

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp")


#: Default largest image accepted, in pixels (width x height from the file's
#: header, checked before anything is decoded): 100 megapixels.
MAX_PIXELS = 100_000_000


class DecoderWarning(UserWarning):
    """The decoder reported a problem (truncated or corrupt data) but gave an image."""


@dataclass
class ImageFile:
    """An image as read from a file, with what the decoder said about it.

    Attributes
    ----------
    image : ndarray
        As returned by :func:`read_image` (EXIF orientation applied).
    warnings : list of str
        The decoder's complaints, one line each (e.g. ``Corrupt JPEG data:
        premature end of data segment``, ``image file is truncated``);
        empty for a clean file.
    path : str
    orientation : int
        The file's EXIF orientation tag (1-8; 1 = as stored, also when the
        file has none), already applied to `image`.
    """

    image: np.ndarray
    warnings: list = field(default_factory=list)
    path: str = ""
    orientation: int = 1


def open_image(path, max_pixels=MAX_PIXELS):
    """Read an image file and collect the decoder's warnings (see :func:`read_image`).

    Parameters
    ----------
    path : str or Path
    max_pixels : int
        Largest ``width * height`` accepted, read from the file's header
        before decoding (default :data:`MAX_PIXELS`, 100 Mpx), so that a
        small file that would decode to gigabytes is refused at no cost.
        A whole number >= 1 (NaN, infinity or text are refused, not taken
        as "no limit").

    Returns
    -------
    ImageFile
        The image and the decoder's warnings. A truncated file is decoded as
        far as it goes (the rest is grey or black) with the warning ``image
        file is truncated``.

    Raises
    ------
    InputError
        Not a regular file (a directory, FIFO, device: refused without
        opening it, so nothing blocks), missing, empty, larger than
        `max_pixels`, or not decodable; one line naming the file. `path`
        not a str or Path (an array is given to
        :func:`attneave.stimuli.extraction.extract` directly), `max_pixels` not a
        whole number >= 1.
    """
    import cv2

    path = _as_path(path)
    max_pixels = _max_pixels(max_pixels)
    _require_regular_file(path)
    size, orientation = _header_size(path, max_pixels)
    try:
        data = np.fromfile(path, dtype=np.uint8)
    except (IsADirectoryError, PermissionError, OSError) as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    if data.size == 0:
        raise InputError(f"{path}: empty file, expected a PNG, JPEG, TIFF or BMP image")
    with _captured_stderr() as said:
        img = _quiet_imdecode(cv2, data)
    messages = _lines(said[0]) if said else []
    if (img is None or img.size == 0) and size is not None:
        img, more = _decode_truncated(path)
        messages += more
    if img is None or img.size == 0:
        raise InputError(f"{path}: not a readable image (corrupt, or not PNG, JPEG, TIFF or BMP)")
    if img.shape[0] * img.shape[1] > max_pixels:  # a header PIL could not read
        raise InputError(f"{path}: {img.shape[1]}x{img.shape[0]} pixels exceeds the limit of {max_pixels} "
                         "pixels (max_pixels, --max-pixels)")
    if img.ndim == 3:
        if img.shape[2] == 3:
            img = cv2.cvtColor(img, cv2.COLOR_BGR2RGB)
        elif img.shape[2] == 4:
            img = cv2.cvtColor(img, cv2.COLOR_BGRA2RGBA)
        elif img.shape[2] == 1:
            img = img[:, :, 0]
    if orientation != 1:
        # a phone's photo is stored sideways with a tag that every viewer and browser obeys: the outline
        # must be in the image people see (and click on), not in the stored pixel grid
        img = np.ascontiguousarray(_ORIENT[orientation](img))
    return ImageFile(img, messages, str(path), orientation)


def read_image(path, max_pixels=MAX_PIXELS):
    """Read an image file as a viewer shows it (EXIF orientation applied; no colour management).

    Parameters
    ----------
    path : str or Path
        A PNG, JPEG, TIFF or BMP file; grey, RGB or RGBA; 8 or 16 bit
        (32-bit float TIFF also works).
    max_pixels : int
        Largest ``width * height`` accepted, checked on the header before
        decoding (default 100 Mpx); a whole number >= 1.

    Returns
    -------
    ndarray
        ``(H, W)`` for grey, ``(H, W, 3)`` RGB or ``(H, W, 4)`` RGBA
        (channels in RGB order, not OpenCV's BGR), in the file's own dtype
        (uint8, uint16 or float32). Row ``i``, column ``j`` is the pixel
        centred at ``(x, y) = (j, i)`` of the image as image viewers and
        browsers show it: a file with an EXIF orientation tag (a phone's
        JPEG stored sideways) is turned and flipped as the tag says, so
        its width and height may be the stored ones swapped.

    Raises
    ------
    InputError
        The file does not exist, is not a regular file, is empty, is larger
        than `max_pixels`, or cannot be decoded (corrupt or not an image),
        naming the file; `path` that is no str or Path, `max_pixels` that
        is no whole number >= 1.

    Warns
    -----
    DecoderWarning
        The decoder complained (corrupt or truncated data) but gave an
        image; :func:`open_image` returns these messages instead.
    """
    f = open_image(path, max_pixels)
    if f.warnings:
        import warnings

        warnings.warn(f"{path}: decoder: {'; '.join(f.warnings)}", DecoderWarning, stacklevel=2)
    return f.image


def _as_path(path):
    """`path` as a Path; anything but a str or os.PathLike is refused (one line)."""
    import os

    if isinstance(path, (str, os.PathLike)) and not isinstance(path, bytes):
        return Path(path)
    if isinstance(path, np.ndarray):
        raise InputError("path: expected an image file name (str or Path), got an array; pass arrays to "
                         "attneave.stimuli.extraction.extract or extract_contours directly")
    raise InputError(f"path: expected an image file name (str or Path), got {type(path).__name__} {path!r:.60}")


def _max_pixels(value):
    """`max_pixels` checked: a whole number >= 1 (a float such as 1e8 is taken if it is whole)."""
    try:  # the library's rule for integers (a string such as '1e8' is not one)
        return as_int(value, "max_pixels", lo=1)
    except InputError:
        raise InputError(f"max_pixels: must be a whole number of pixels >= 1, got {value!r}") from None


def _require_regular_file(path):
    """Refuse anything but a regular file before opening it (a FIFO would block)."""
    import os
    import stat

    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    if not stat.S_ISREG(mode):
        kind = "a directory" if stat.S_ISDIR(mode) else "a FIFO" if stat.S_ISFIFO(mode) else "a special file"
        raise InputError(f"{path}: is {kind}, expected a regular image file")


def header_size(path):
    """``(width, height)`` of an image file read from its header only, or None if Pillow cannot parse it.

    The size of the image as shown, as :func:`read_image` returns it: swapped
    when the file's EXIF orientation turns it by a quarter turn.
    """
    size, orientation = _pil_header(path)
    if size is not None and orientation in (5, 6, 7, 8):
        return size[1], size[0]
    return size


#: EXIF orientation (2-8) -> the steps that turn the stored pixel array (rows, columns, ...) into the
#: image a viewer shows (as PIL.ImageOps.exif_transpose; 1 = as stored).
_ORIENT = {2: lambda a: a[:, ::-1], 3: lambda a: a[::-1, ::-1], 4: lambda a: a[::-1],
           5: lambda a: a.swapaxes(0, 1), 6: lambda a: np.rot90(a, -1),
           7: lambda a: a[::-1, ::-1].swapaxes(0, 1), 8: lambda a: np.rot90(a, 1)}
#: Formats whose EXIF orientation OpenCV's decoder ignores (IMREAD_UNCHANGED) and :func:`open_image`
#: applies; OpenCV's TIFF decoder applies a TIFF's orientation tag itself (and Pillow reports the
#: turned size), so TIFF is not among them.
_ORIENTED_FORMATS = ("JPEG", "MPO", "PNG", "WEBP")


def _pil_header(path):
    """``((width, height) as stored, EXIF orientation to apply)`` from the file's header; (None, 1) if
    Pillow cannot parse it. Decodes no pixels."""
    import warnings

    from PIL import Image

    bomb = Image.MAX_IMAGE_PIXELS
    try:
        Image.MAX_IMAGE_PIXELS = None  # our own limit applies, with the size in the message
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with Image.open(path) as im:  # reads the header, decodes nothing
                size = tuple(im.size)
                orientation = 1
                # a PNG's getexif() decodes the whole image to look for an eXIf chunk after the
                # pixels; one before them (where the PNG specification puts it) is in info already
                if im.format in _ORIENTED_FORMATS and (im.format != "PNG" or "exif" in im.info):
                    try:
                        orientation = int(im.getexif().get(0x0112, 1))
                    except Exception:  # noqa: BLE001 - an unreadable EXIF block: shown as stored
                        orientation = 1
                return size, (orientation if orientation in _ORIENT else 1)
    except Exception:  # noqa: BLE001 - not a format Pillow knows: OpenCV decides
        return None, 1
    finally:
        Image.MAX_IMAGE_PIXELS = bomb


def _header_size(path, max_pixels):
    """``(size as stored or None, EXIF orientation)`` from one read of the header (:func:`_pil_header`),
    refusing more than `max_pixels` (a quarter turn does not change the count)."""
    size, orientation = _pil_header(path)
    if size is not None and size[0] * size[1] > max_pixels:
        w, h = size if orientation not in (5, 6, 7, 8) else size[::-1]  # as shown, as header_size gives it
        raise InputError(f"{path}: {w}x{h} pixels ({w * h / 1e6:.4g} Mpx) exceeds the limit of "
                         f"{max_pixels} pixels (max_pixels, --max-pixels)")
    return size, orientation


def _decode_truncated(path):
    """A truncated file decoded as far as its data go, by Pillow: (array in OpenCV's channel order, warnings)."""
    import warnings

    from PIL import Image
    from PIL import ImageFile as PilImageFile

    old = PilImageFile.LOAD_TRUNCATED_IMAGES
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with Image.open(path) as im:
                try:
                    im.load()
                    return None, []  # Pillow reads it whole: OpenCV's failure stands
                except OSError:
                    pass
            PilImageFile.LOAD_TRUNCATED_IMAGES = True
            with Image.open(path) as im:
                if im.mode not in ("L", "RGB", "RGBA", "I;16"):
                    im = im.convert("RGBA" if "A" in im.mode else "RGB")
                arr = np.asarray(im)
    except Exception:  # noqa: BLE001 - not decodable at all
        return None, []
    finally:
        PilImageFile.LOAD_TRUNCATED_IMAGES = old
    if arr.ndim == 3:  # to OpenCV's order, as imdecode gives
        arr = arr[:, :, [2, 1, 0, 3][: arr.shape[2]]]
    return np.ascontiguousarray(arr), ["image file is truncated (decoded as far as it goes)"]


class _captured_stderr:
    """Collect what C libraries (libjpeg, libpng) print on file descriptor 2 meanwhile."""

    def __enter__(self):
        import os
        import sys
        import tempfile

        self.said = []
        try:
            sys.stderr.flush()
            self._tmp = tempfile.TemporaryFile()
            self._saved = os.dup(2)
            os.dup2(self._tmp.fileno(), 2)
        except (OSError, ValueError, AttributeError):  # no real fd 2: nothing to capture
            self._saved = None
        return self.said

    def __exit__(self, *exc):
        import os

        if self._saved is None:
            return False
        os.dup2(self._saved, 2)
        os.close(self._saved)
        self._tmp.seek(0)
        self.said.append(self._tmp.read(65536).decode("utf-8", "replace"))
        self._tmp.close()
        return False


def _lines(text):
    """Distinct non-empty lines of a decoder's messages, at most five."""
    out = []
    for line in text.splitlines():
        line = " ".join(line.split())
        if line and line not in out:
            out.append(line)
    return out[:5]


def _quiet_imdecode(cv2, data):
    """cv2.imdecode without OpenCV's own log messages (libjpeg's and libpng's are captured by the caller)."""
    log = getattr(getattr(cv2, "utils", None), "logging", None)
    if log is None:  # pragma: no cover - very old OpenCV
        return cv2.imdecode(data, cv2.IMREAD_UNCHANGED)
    old = log.getLogLevel()
    log.setLogLevel(log.LOG_LEVEL_SILENT)
    try:
        return cv2.imdecode(data, cv2.IMREAD_UNCHANGED)
    finally:
        log.setLogLevel(old)


#: Integer images whose values span more grey levels than this are traced as float64 (their own
#: values): a histogram over every integer level would need memory in proportion to the span.
MAX_INTEGER_LEVELS = 65536


def load_image(image_or_path):
    """``(array, name)`` from a path (read with :func:`read_image`) or an array.

    An integer array (other than uint8 and uint16) whose values span more
    than :data:`MAX_INTEGER_LEVELS` levels is returned as float64 with the
    same values (so a threshold stays in its units) when it is grey or RGB;
    with an alpha channel it is refused (its full scale, and so the default
    alpha level, would be lost).
    """
    import os

    if isinstance(image_or_path, (str, os.PathLike)) and not isinstance(image_or_path, bytes):
        return read_image(image_or_path), str(image_or_path)
    try:
        img = np.asarray(image_or_path)
    except Exception:  # noqa: BLE001 - anything that is not an array
        raise InputError("image: expected a path or an array") from None
    if img.dtype == object and img.ndim == 0:
        raise InputError(f"image: expected a path (str or Path) or an image array, got {type(image_or_path).__name__}")
    return _wide_integers(img, "image"), "image"


def _wide_integers(img, name):
    """An integer image of more than MAX_INTEGER_LEVELS levels as float64 (see :func:`load_image`)."""
    if not np.issubdtype(img.dtype, np.integer) or img.dtype in (np.uint8, np.uint16) or img.size == 0:
        return img
    lo, hi = int(img.min()), int(img.max())
    if hi - lo < MAX_INTEGER_LEVELS:
        return img
    if img.ndim == 3 and img.shape[2] in (2, 4):
        raise InputError(f"{name}: {img.dtype} image with an alpha channel and values from {lo} to {hi} "
                         f"(more than {MAX_INTEGER_LEVELS} levels): give it as uint8, uint16 or float "
                         "(alpha 0 to 1)")
    return img.astype(np.float64)


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
