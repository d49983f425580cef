"""Outlines of objects in photographs and silhouettes, to sub-pixel accuracy.

Points are ``(x, y)`` floats in image pixels: x = column, y = row, y points
down, pixel centres at integer coordinates (OpenCV's convention), in the
input image's own pixel grid. Every contour returned is closed (the first
point is not repeated), stored counter-clockwise as seen on the screen.

The pipeline
------------
1. **Read** (:func:`read_image`): PNG, JPEG, TIFF, BMP; grey, RGB or RGBA;
   8 or 16 bit (or float TIFF), turned and flipped as the file's EXIF
   orientation says (as viewers show it). Colour is reduced to luminance
   ``0.299 R + 0.587 G + 0.114 B`` in the image's own units; the alpha
   channel is used only by ``method='alpha'``.
2. **Segment** (``method``), giving a boolean object mask and, where the
   image has grey levels, an iso-level for the sub-pixel step:

   ``'otsu'`` (default)
       Photographs and antialiased renders of one object on a plain
       background. Otsu's threshold splits the grey levels in two classes;
       the contour level is then the midpoint of the two classes' medians
       (robust to the few edge pixels, so an antialiased edge is found at
       its 50 % coverage line, not at wherever Otsu's split fell). The
       object is the class that touches the image border less
       (``polarity='auto'``), or the ``'dark'`` / ``'light'`` one.
   ``'threshold'``
       When you know the level (e.g. a calibrated grey value or a render
       with known ground and figure); ``threshold`` is in the image's units
       (0-255 for 8 bit, 0-65535 for 16 bit) and is the contour level.
   ``'mask'``
       A binary silhouette of either polarity (MPEG-7 style, a
       segmentation exported from another tool). Pixels above the midpoint
       of the image's range are "on"; the object is the class touching the
       border less, or given by ``polarity``.
   ``'alpha'``
       Cut-outs with transparency (PNG with an alpha channel): the object
       is where alpha exceeds ``threshold`` (default half of full opacity);
       an antialiased alpha edge gives a sub-pixel contour.
   ``'grabcut'``
       Objects on cluttered or textured backgrounds that a single threshold
       cannot separate. OpenCV's GrabCut (Rother et al. 2004), initialised
       with ``rect=(x, y, width, height)`` or, by default, with the image
       inset by 5 % on every side. Slow (seconds per megapixel) and not
       deterministic across OpenCV versions; check the overlay.

3. **Clean up**: 8-connected objects; the largest one
   (``objects='largest'``) or every object of at least ``min_area``
   pixels (``objects='all'``, largest first). Holes are traced apart and
   returned only when asked (``holes=True``); the outer contour is the
   boundary of the object with its holes filled, so a hole is never taken
   for it. An object that touches the image border is closed along the
   border (at the image edge, ``x = -0.5`` or ``x = width - 0.5``, ...).
4. **Sub-pixel contour**: marching squares
   (:func:`skimage.measure.find_contours`) on the grey image, run only on
   a crop around the chosen object in which every pixel more than a pixel
   from its edge keeps its side of the level, so that nothing but this
   object's boundary is traced and its shape cannot change. Three
   refinements make it accurate on antialiased edges: each edge is traced
   at the local midpoint of the object's and the background's grey levels
   (``local_level``; under a graded background a single level moves the
   edge), after a 3x3 average that makes the edge profile linear between
   pixel centres (``presmooth``), whose known curvature-dependent shift is
   then removed. On exact-coverage renders the contour is accurate to
   about 0.004 px RMS. A two-valued image (a binary mask, whatever the
   method) has no grey levels to interpolate: its marching-squares outline
   (a staircase) is smoothed lightly along the arc (``mask_sigma`` px,
   default 1) instead. A photograph's figure-ground mask (``'photo'``,
   boxes, scribbles, ``'grabcut'``) is traced the same way on the photo's colour edge
   (:mod:`attneave.stimuli.extraction.figure_ground.colour_edge`: each pixel's colour projected
   on the line from the local background colour to the local object
   colour), so that the outline lies on the edge where the edge is sharp
   (an exact-coverage disk, noise 0-10 levels: 0.005-0.07 px RMS, against 0.3 px
   for the mask's staircase) and is the mask's own where it is faint; it
   moves at most onto the pixels next to the mask's boundary.
5. **Curvature and surprisal** (:func:`describe`): the contour is
   smoothed along its arc with a periodic Gaussian whose scale is tied to
   the shape, ``sigma = SIGMA_FRACTION * perimeter`` (1 %) unless given, at
   least ``MIN_SIGMA`` px; curvature is the Gaussian-derivative curvature
   at that scale (:func:`attneave.stimuli.geometry.polyline.gaussian_curvature`); surprisal
   (:func:`attneave.stimuli.geometry.information.surprisal`) is computed on the smoothed
   contour resampled at ``n`` points (or a spacing in px).

References
----------
.. [1] Otsu, N. (1979). A threshold selection method from gray-level
       histograms. IEEE Trans. SMC 9(1), 62-66.
.. [2] Lorensen, W. E., & Cline, H. E. (1987). Marching cubes: a high
       resolution 3D surface construction algorithm. SIGGRAPH 21(4).
.. [3] Rother, C., Kolmogorov, V., & Blake, A. (2004). "GrabCut":
       interactive foreground extraction using iterated graph cuts.
       ACM Trans. Graphics 23(3), 309-314.
.. [4] Mokhtarian, F., & Mackworth, A. K. (1992). A theory of multiscale,
       curvature-based shape representation for planar curves. IEEE PAMI
       14(8), 789-805.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.extraction.imageio import load_image
from attneave.stimuli.extraction.segment import METHODS, POLARITIES, NoObject, check_method_options, segment
from attneave.stimuli.extraction.trace import Extraction, trace_objects  # Extraction: re-exported (its public home)
from attneave.stimuli.validate import as_int, as_number

__all__ = ["MASK_SIGMA", "GRABCUT_ITERATIONS", "MAX_GRABCUT_ITERATIONS", "Extraction", "extract", "extract_contours"]

#: Default smoothing (px of arc length) of a binary mask's staircase outline.
MASK_SIGMA = 1.0
#: Default GrabCut iterations, and the most accepted (it converges within about ten; each
#: iteration costs about a second per megapixel).
GRABCUT_ITERATIONS = 5
MAX_GRABCUT_ITERATIONS = 1000


def extract(
    image_or_path,
    method="otsu",
    threshold=None,
    polarity="auto",
    objects="largest",
    min_area=None,
    holes=False,
    min_hole_area=None,
    mask_sigma=MASK_SIGMA,
    presmooth=True,
    local_level=True,
    rect=None,
    grabcut_iterations=None,
    name=None,
    boxes=None,
    scribbles=None,
    model=None,
):
    """Extract the sub-pixel outer contour(s) of the object(s) in an image.

    Parameters
    ----------
    image_or_path : str, Path or ndarray
        An image file (see :func:`read_image`) or an array: ``(H, W)`` grey
        or bool, ``(H, W, 3)`` RGB, ``(H, W, 4)`` RGBA (RGB order).
    method : {'otsu', 'auto', 'threshold', 'mask', 'alpha', 'grabcut', 'photo', 'model', 'rembg'}
        How the object is separated from the background; see the module
        notes for when to use each. Default 'otsu'. 'auto' takes a
        two-valued image or one on a plain background by 'otsu', a cut-out
        by 'alpha' and anything else by 'photo'
        (:func:`attneave.stimuli.extraction.segment.image_kind`); 'photo' is the
        automatic (or, with `boxes` / `scribbles`, assisted) figure-ground
        of :mod:`attneave.stimuli.extraction.figure_ground.photo`; 'rembg' a learned network
        through rembg (:mod:`attneave.stimuli.extraction.figure_ground.learned`); 'model' a
        raw ONNX network rembg does not know (`model`).
    threshold : float, optional
        'threshold': the grey level of the object's edge (required), in the
        image's units. 'alpha': the alpha level (default half of opaque).
    polarity : {'auto', 'dark', 'light'}
        Which class is the object for 'otsu', 'threshold' and 'mask'.
        'auto' (default): the class that touches the image border less.
    objects : {'largest', 'all'}
        The largest object only (default) or every object of at least
        `min_area` pixels, largest first.
    min_area : float, optional
        Smallest object, in pixels counted with its holes filled; default
        ``max(9, 1e-4 * H * W)``.
    holes : bool
        Also trace the holes of each object (returned apart, in
        ``Extraction.holes``).
    min_hole_area : float, optional
        Smallest hole kept, in pixels (default `min_area`); smaller ones
        are counted in ``params['holes_dropped']``.
    mask_sigma : float
        Smoothing along the arc (px) of the staircase outline of a
        two-valued (binary) image. Default 1.
    presmooth : bool
        Average the grey field over 3x3 pixels before marching squares
        (default True). Linear interpolation between pixel centres is exact
        only where the edge profile is linear; on an exact-coverage render
        the raw profile is linear over one pixel only, and the traced edge
        wobbles by 0.05 px RMS. The 3x3 average makes the profile linear
        over three pixels (0.004 px RMS about the mean on a disk of radius
        90). It also moves the level line towards the centre of curvature
        by ``PRESMOOTH_SHIFT * k`` (0.49 px^2 times the curvature k); each
        point is moved back along its normal by that amount, with k taken
        at a 2 px scale. If the average would cut the object (a neck
        thinner than about 1.5 px), the raw field is traced instead;
        ``params['presmooth']`` records which, per object.
    local_level : bool
        With `presmooth`, trace each edge at the midpoint of the object's
        and the background's grey levels measured within about
        ``LOCAL_RADIUS`` (10) px of it, rather than at one level for the whole image (default
        True). Under uneven lighting or a graded background a global level
        sits off the local midpoint, which moves a sharp edge by up to the
        width of its transition (three pixels after the 3x3 average); the
        local midpoint keeps it on the 50 % line. Pixels more than a pixel
        from the edge keep their side of the level, so the object's shape
        cannot change; ``params['local_level']`` records, per object,
        whether it was used (it is not if it would cut the object).
    rect : (x, y, width, height), optional
        'grabcut' initial rectangle; default the image inset by 5 %.
    boxes : list of (x, y, width, height), optional
        Boxes around the object(s) (image pixels): one outline per box, in
        box order ('photo', 'model' and 'rembg' methods; several need
        ``objects='all'``). With a network the box is seen widened
        by :data:`~attneave.stimuli.extraction.figure_ground.model.BOX_CONTEXT` on every side.
    scribbles : (H, W) uint8 ndarray, optional
        0 unmarked, 1 object, 2 background
        (:func:`attneave.stimuli.extraction.figure_ground.photo.read_scribbles`); 'photo' method.
    model : dict, optional
        ``model_file`` and optionally ``size``, ``mean``, ``std`` for
        ``method='model'`` (:func:`attneave.stimuli.extraction.figure_ground.model.object_probability`);
        optionally ``network`` (a rembg session name) and ``model_file`` for
        ``method='rembg'`` (:func:`attneave.stimuli.extraction.figure_ground.learned.network_probability`).
    grabcut_iterations : int, optional
        Iterations of GrabCut, a whole number from 1 to
        :data:`MAX_GRABCUT_ITERATIONS` ('grabcut', 'photo' and 'auto'
        methods; default 5).
    name : str, optional
        Names the image in messages and the contours (default: the path,
        or 'image' for an array).

    Returns
    -------
    Extraction
        Contours (``(x, y)`` image pixels, y down, pixel centres at
        integers, closed, counter-clockwise on the screen), holes, the
        object mask and every resolved parameter.

    Raises
    ------
    InputError
        Unreadable file, bad parameter, or an image without a usable object
        (uniform, no object, everything object), with one line naming the
        image and the reason. An option that does not apply to `method`
        (`threshold` but for 'threshold' and 'alpha', `rect` but for
        'grabcut', `grabcut_iterations` but for 'grabcut', 'photo' and
        'auto', `boxes` but for 'auto', 'photo', 'model' and 'rembg', `scribbles`
        but for 'auto' and 'photo', `model` but for 'model' and 'rembg') is refused,
        not ignored (the rule of ``attneave extract``,
        :func:`attneave.stimuli.extraction.segment.check_method_options`).

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:64, :64]
    >>> img = ((xx - 30.0) ** 2 + (yy - 32.0) ** 2 <= 20.0 ** 2).astype(np.uint8) * 255
    >>> ex = extract(img)
    >>> ex.params["method"], ex.params["polarity"], len(ex.contours)
    ('otsu', 'light', 1)
    >>> bool(abs(ex.contour.area - img.astype(bool).sum()) < 0.01 * img.astype(bool).sum())
    True
    """
    if not isinstance(method, str) or method not in METHODS:
        raise InputError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    if not isinstance(polarity, str) or polarity not in POLARITIES:
        raise InputError(f"unknown polarity {polarity!r}; expected one of {', '.join(POLARITIES)}")
    if not isinstance(objects, str) or objects not in ("largest", "all"):
        raise InputError(f"objects must be 'largest' or 'all', got {objects!r}")
    check_method_options(method, dict(threshold=threshold, rect=rect, grabcut_iterations=grabcut_iterations,
                                      boxes=boxes, scribbles=scribbles, model_file=model),
                         names={"model_file": "model"})
    if threshold is not None:
        threshold = as_number(threshold, "threshold")
    mask_sigma = as_number(mask_sigma, "mask_sigma", ge=0)
    if min_area is not None:
        min_area = as_number(min_area, "min_area", ge=0)
    if min_hole_area is not None:
        min_hole_area = as_number(min_hole_area, "min_hole_area", ge=0)
    if grabcut_iterations is None:
        grabcut_iterations = GRABCUT_ITERATIONS
    else:
        grabcut_iterations = as_int(grabcut_iterations, "grabcut_iterations", lo=1, hi=MAX_GRABCUT_ITERATIONS)
    img, default_name = load_image(image_or_path)
    name = default_name if name is None else str(name)
    if boxes is not None and len(boxes) > 1 and objects != "all":
        raise InputError(f"{name}: {len(boxes)} boxes for one image need objects='all' (--objects all)")
    opts = (objects, min_area, holes, min_hole_area, mask_sigma, presmooth, local_level)
    try:
        if not boxes:
            seg = segment(img, method, threshold, polarity, name, rect, grabcut_iterations, None, scribbles, model)
            return trace_objects(seg, name, *opts)
        # one outline per box, in box order
        parts = []
        for b in boxes:
            seg = segment(img, method, threshold, polarity, name, rect, grabcut_iterations, b, scribbles, model)
            parts.append(trace_objects(seg, name, "largest", *opts[1:]))
    except NoObject as exc:
        raise NoObject(f"{name}: {exc}") from None
    first = parts[0]
    params = dict(first.params, objects=objects, boxes=[p.params.get("box") for p in parts],
                  object_areas=[a for p in parts for a in p.params["object_areas"]],
                  agreement=min(p.params.get("agreement", 1.0) for p in parts), candidate_areas=None)
    mask = np.logical_or.reduce([p.mask for p in parts])
    return Extraction([p.contour for p in parts], [p.holes[0] for p in parts], mask, params)


def extract_contours(image_or_path, method="otsu", threshold=None, polarity="auto", objects="largest",
                     min_area=None, holes=False, **kwargs):
    """Sub-pixel outer contours of the object(s) in an image (stable entry point).

    The same as ``extract(...).contours``. This signature is what recipes
    (``from_image``) call; it will stay compatible.

    Parameters
    ----------
    image_or_path : str, Path or ndarray
        An image file or an array (see :func:`extract`).
    method : {'otsu', 'auto', 'threshold', 'mask', 'alpha', 'grabcut', 'photo', 'model', 'rembg'}
        How the object is separated from the background (default 'otsu').
    threshold : float, optional
        The edge's grey level ('threshold', required) or alpha level
        ('alpha'); refused with other methods.
    polarity : {'auto', 'dark', 'light'}
        Which class is the object.
    objects : {'largest', 'all'}
        The largest object, or every object of at least `min_area` pixels.
    min_area : float, optional
        Smallest object in pixels (default ``max(9, 1e-4 * H * W)``).
    holes : bool
        Trace holes too (they are not returned here; see :func:`extract`).
    **kwargs
        Any other parameter of :func:`extract` (``rect``,
        ``grabcut_iterations``, ``boxes``, ``scribbles``, ``model``,
        ``mask_sigma``, ...). One that does not apply to `method` is
        refused, not ignored.

    Returns
    -------
    list of Contour
        Outer contours, largest first; ``(x, y)`` in the image's pixels (x =
        column, y = row, y down, pixel centres at integers), closed, first
        point not repeated, counter-clockwise on the screen.

    Raises
    ------
    InputError
        As :func:`extract`: an unreadable image, a bad parameter, an option
        for another method, or no usable object.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 50), np.uint8); img[10:30, 5:25] = 200
    >>> [c] = extract_contours(img)
    >>> [round(float(v), 1) for v in c.bbox]
    [4.5, 9.5, 24.5, 29.5]
    """
    return extract(image_or_path, method=method, threshold=threshold, polarity=polarity, objects=objects,
                   min_area=min_area, holes=holes, **kwargs).contours
