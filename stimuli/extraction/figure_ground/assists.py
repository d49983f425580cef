"""What a person adds to help the extraction: boxes around objects (a CSV)
and scribbles (a directory of stroke images).

Boxes file: a CSV with columns ``image, x, y, width, height``; ``image`` is
an input's file name (``horse012.jpg``) or stem (``horse012``) or path as
given; ``x, y`` is the box's top-left pixel, ``width, height`` its size, in
the image's pixels (x = column, y = row, y down). Several rows for one image
give several objects (with ``--objects all``).

Scribbles directory: for an input ``STEM.*``, the file ``STEM.png`` (RGB or
RGBA, the photo's size) with object strokes in pure red ``(255, 0, 0)`` and
background strokes in pure blue ``(0, 0, 255)``; other colours and
transparent pixels are unmarked (:func:`attneave.stimuli.extraction.figure_ground.photo.read_scribbles`).

Every mistake (an unknown image, a box outside its image, a scribble image
of the wrong size) is refused before any image is processed, with one line
naming the file, the row and what was expected.
"""

from __future__ import annotations

from pathlib import Path

from attneave.stimuli.errors import InputError

__all__ = ["read_boxes", "scribble_files"]


def _matcher(images):
    """A function from a name in a boxes file to the input image it names (or None)."""
    index = {}
    for img in images:
        p = Path(img)
        for key in {str(img), p.name, p.stem}:
            index.setdefault(key, set()).add(str(img))
    return lambda name: frozenset(index.get(name, ()))


def read_boxes(path, images, objects="largest"):
    """Boxes per input image from a CSV (see the module notes).

    Parameters
    ----------
    path : str or Path
    images : list of str
        The inputs, as given.
    objects : {'largest', 'all'}
        With 'largest', at most one box per image.

    Returns
    -------
    dict of str to list of (x, y, width, height)
        Keyed by the input as given; images without a row are absent.

    Raises
    ------
    InputError
        No rows, missing columns, a non-numeric value, an image that is no input,
        a box not inside its image, or several boxes without
        ``objects='all'``; one line naming the file and its line.
    """
    from attneave.stimuli.extraction.figure_ground.grabcut import check_box
    from attneave.stimuli.extraction.imageio import header_size
    from attneave.stimuli.tables import read_table

    df = read_table(path, required=("image", "x", "y", "width", "height"), numeric=("x", "y", "width", "height"))
    if len(df) == 0:
        raise InputError(f"{path}: no boxes (a header but no rows); expected rows image,x,y,width,height")
    match = _matcher(images)
    sizes, out = {}, {}
    for i, row in enumerate(df.itertuples(index=False)):
        line = i + 2  # the header is line 1
        name = str(row.image).strip()
        found = match(name)
        if len(found) != 1:
            what = "matches no input image" if not found else "matches several input images"
            raise InputError(f"{path}: line {line}: image {name!r} {what} (use the file name or stem of one input)")
        img = next(iter(found))  # the matcher's own set: read, never emptied
        if img not in sizes:
            sizes[img] = header_size(img)
        box = (row.x, row.y, row.width, row.height)
        if sizes[img] is not None:
            w, h = sizes[img]
            check_box(box, (h, w), f"{path}: line {line}", what=f"box for {name}")
        out.setdefault(img, []).append(tuple(int(round(v)) for v in box))
    if objects != "all":
        for img, bs in out.items():
            if len(bs) > 1:
                raise InputError(f"{path}: {len(bs)} boxes for {img}; several boxes per image need --objects all")
    return out


def scribble_files(directory, images):
    """The scribble image of each input that has one (see the module notes).

    Parameters
    ----------
    directory : str or Path
    images : list of str
        The inputs, as given.

    Returns
    -------
    dict of str to Path
        Input (as given) -> its ``STEM.png`` in `directory`.

    Raises
    ------
    InputError
        Not a directory, one without any scribble image, a PNG that belongs to no input, or one whose size
        differs from its photo's; one line naming the file.
    """
    from attneave.stimuli.extraction.imageio import header_size

    d = Path(directory)
    if not d.is_dir():
        raise InputError(f"{d}: scribbles must be a directory of STEM.png files")
    stems = {Path(img).stem: str(img) for img in images}
    out = {}
    for f in sorted(d.iterdir()):
        if f.suffix.lower() != ".png" or f.name.startswith("."):
            continue
        if f.stem not in stems:
            raise InputError(f"{f}: scribbles for no input image (expected STEM.png for an input STEM.*)")
        img = stems[f.stem]
        size, own = header_size(f), header_size(img)
        if size is None:
            raise InputError(f"{f}: not a readable PNG (scribbles: object strokes red, background blue)")
        if own is not None and size != own:
            raise InputError(f"{f}: scribbles of {size[0]}x{size[1]} pixels, but {img} is {own[0]}x{own[1]}; "
                             "expected the same size")
        out[img] = f
    if not out:
        raise InputError(f"{d}: no scribbles (no STEM.png for an input STEM.*); expected one PNG per scribbled input")
    return out
