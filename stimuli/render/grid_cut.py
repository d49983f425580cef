"""Cutting a stream of ring points at the pixel grid, for the exact rasteriser of
:mod:`attneave.stimuli.render.raster`: the points where the stream crosses a
grid line are inserted (shared by the two pieces that meet there, so there are
no cracks and nothing is counted twice), and each piece's deposits into the
winding-number accumulation are computed.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.geometry.polyline import shoelace
from attneave.stimuli.render.workspace import ramp, scratch

__all__ = ["cut_pieces", "stream_box", "ring_area"]


def _refine(p, axis, lo, hi, bridge, out):
    """Insert the points where a stream crosses ``p[axis] = integer`` in [lo, hi].

    Crossing points carry exactly integral coordinates on `axis`; the other
    coordinate is interpolated from the start of the piece, so original
    vertices are kept bit for bit. Returns ``(q, bridge)``: `q` is `p` when
    nothing crosses, else a view of the scratch buffer named `out` (see
    :func:`scratch`).
    """
    m = p.shape[1] - 1
    a0, a1 = p[axis, :-1], p[axis, 1:]
    # rows: 0-1 floor of each piece's least and greatest `a`, 2 its count of
    # new points, 3 their running total; 4-6 what every new point of the
    # piece needs besides its start point (offset, step, slope); 7-8 scratch
    w = scratch("refine", (9, m))
    np.minimum(a0, a1, out=w[0])
    np.maximum(a0, a1, out=w[1])
    ext = np.floor(w[:2], out=w[:2])
    # The crossings of a piece are the integers in (w0, w1] within [lo, hi];
    # an end point on a grid line gives a zero-length piece, which adds 0.
    np.clip(ext, lo - 1.0, hi, out=ext)
    cnt = np.subtract(w[1], w[0], out=w[2])
    cnt += 1.0  # the piece's start and its crossings
    if bridge is not None:
        cnt[bridge] = 1.0  # a piece between rings is never cut
    pos = np.cumsum(cnt, out=w[3])
    total = int(pos[-1])
    if total == m:
        return p, bridge
    counts = scratch("refine_n", m, np.intp)
    np.copyto(counts, cnt, casting="unsafe")
    d = np.subtract(p[:, 1:], p[:, :-1], out=w[7:9])
    step = np.sign(d[axis], out=w[5])
    # A piece with constant `a` has no crossing: its slope (inf or nan; the
    # caller silences the warnings) is only used at its start, which is
    # overwritten below.
    np.divide(d[1 - axis], d[axis], out=w[6])
    pos -= cnt  # each piece's start in the new stream
    starts = scratch("refine_s", m, np.intp)
    np.copyto(starts, pos, casting="unsafe")
    # Crossing j = 1, 2, ... of a piece lies at mid + step * (j - cnt / 2),
    # mid = w0 + cnt / 2: w0 + 1, w0 + 2, ... where `a` grows, w1, w1 - 1,
    # ... where it falls. With j = k - start for the new point k, that is
    # offset + step * k, offset = mid - step * (start + cnt / 2); every term
    # is an integer or a half, exact in float64.
    half = np.multiply(cnt, 0.5, out=cnt)
    np.add(w[0], half, out=w[0])
    pos += half
    pos *= step
    np.subtract(w[0], pos, out=w[4])
    # every new point's piece (np.repeat of an arange), then its piece's
    # data; mode="wrap" (the indices are valid) makes take 2.5x cheaper
    k = np.repeat(ramp(m, np.intp), counts)
    per = scratch("refine_per", (5, total))
    for row, src in enumerate((w[4], w[5], w[6], p[0, :-1], p[1, :-1])):
        src.take(k, out=per[row], mode="wrap")
    start = per[3:]
    q = scratch(out, (2, total + 1))
    qa, qb = q[axis, :-1], q[1 - axis, :-1]
    np.multiply(per[1], ramp(total), out=qa)
    qa += per[0]
    np.subtract(qa, start[axis], out=qb)
    qb *= per[2]
    qb += start[1 - axis]
    # 2-D fancy assignment is several times slower than two 1-D ones
    q[0, starts] = p[0, :-1]
    q[1, starts] = p[1, :-1]
    q[:, -1] = p[:, -1]
    if bridge is not None:
        flags = np.zeros(total, bool)
        flags[starts[bridge]] = True
        bridge = flags
    return q, bridge


def stream_box(p, h, w):
    """``((r0, r1, c0, c1), clip_x, clip_y)`` or None: the pixels a stream's
    pieces can reach, from its extent (rows floor(y), y clipped to [0, h],
    row h lying outside the image; columns floor(x), x in [0, w)), and
    whether it crosses the image's side or top/bottom edges."""
    (xlo, ylo), (xhi, yhi) = np.minimum.reduce(p, axis=1).tolist(), np.maximum.reduce(p, axis=1).tolist()
    # A shape wholly above the image is flattened onto its top edge, where
    # the pieces of every column cancel: it adds nothing either.
    if ylo >= h or yhi <= 0.0 or xhi <= 0.0 or xlo >= w:
        return None
    box = int(max(ylo, 0.0)), int(min(yhi, float(h))), int(max(xlo, 0.0)), int(min(xhi, w - 1.0))
    return box, xlo < 0.0 or xhi >= w, ylo < 0.0 or yhi > h


def ring_area(area, ring, clipped):
    """The winding integral `area` of a stream, for its one `ring` (or None)
    oriented to a positive shoelace sum (see :func:`cut_pieces`)."""
    if ring is None:
        return area
    # whole inside the image, |area| is the shoelace sum
    return abs(area) if not clipped else (area if shoelace(ring) >= 0.0 else -area)


def cut_pieces(p, bridge, h, w, ring=None):
    """Cut a stream at the pixel grid into pieces, each inside one pixel.

    `p` is a (2, n) stream from :func:`attneave.stimuli.render.raster.ring_stream` (x and y rows). Returns None
    when nothing reaches the image, else ``(pc, box, clipped, area)``: `pc`
    a (5, m) scratch array whose rows are each piece's dx, its deposits
    (the signed area between the piece and its pixel's bottom side, and the
    rest of its cover, which goes to the pixel below) and its pixel (column,
    row; floats holding integers, the column in [0, w], the row in [0, h]);
    `box` = (r0, r1, c0, c1), the pixels the pieces can reach; `clipped`
    whether the shape crosses the image's border; `area` the winding
    integral over the image. Given the stream's one `ring`, the area is that
    of the ring oriented to a positive shoelace sum (so that the ring need
    not be reversed: the coverage is ``|win|`` either way).
    """
    ext = stream_box(p, h, w)
    if ext is None:
        return None
    (r0, r1, c0, c1), clip_x, clip_y = ext
    # Columns first, then rows, whose grid lines then cut the new pieces too.
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        p, bridge = _refine(p, 0, 0.0, float(w), bridge, "cols")
        p, bridge = _refine(p, 1, 0.0, float(h), bridge, "rows")
    if clip_x:
        # Pieces left or right of the image affect no image column: moved
        # onto its edge they keep their place in the stream but add nothing.
        np.clip(p[0], 0.0, float(w), out=p[0])
    if clip_y:
        # Pieces above the image are flattened onto its top edge (their
        # cover reaches every row below), pieces below it onto its bottom
        # edge (row h, outside the image: they add nothing inside).
        np.clip(p[1], 0.0, float(h), out=p[1])
    m = p.shape[1] - 1
    # rows: 0 dx, 1-2 the deposits (top, bottom), 3-4 the midpoint (x, y),
    # then the pixel. The refinement's buffers are dead by now and were just
    # written: reusing them keeps the working set in cache (a spiky shape
    # moves megabytes through its scratch buffers).
    pc = scratch("refine_per", (5, m))
    dx, dep, mid = pc[0], pc[1:3], pc[3:5]
    np.subtract(p[:, 1:], p[:, :-1], out=pc[:2])
    np.add(p[:, 1:], p[:, :-1], out=mid)
    mid *= 0.5
    if bridge is not None:
        dx[bridge] = 0.0  # pieces between rings add nothing
    # The winding integral over the image, sum(dx * (h - ym)) over the
    # pieces, is -sum(dx * ym) since the dx of each column sum to 0.
    area = ring_area(-float(np.add.reduce(np.multiply(dx, mid[1], out=pc[1]))), ring, clip_x or clip_y)
    # A piece adds the signed area between itself and its pixel's bottom
    # side to its pixel (top), and the rest of its cover, dx * (ym - row),
    # to the pixel below (bottom); summing down each column gives the
    # winding integral.
    row = np.floor(mid[1], out=dep[0])
    bottom = np.subtract(mid[1], row, out=dep[1])
    np.copyto(mid[1], row)
    np.floor(mid[0], out=mid[0])
    bottom *= dx
    np.subtract(dx, bottom, out=dep[0])
    return pc, (r0, r1, c0, c1), clip_x or clip_y, area
