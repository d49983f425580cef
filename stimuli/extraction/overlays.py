"""The overlay image: a photo or silhouette with its contours coloured by surprisal.

Points are ``(x, y)`` image pixels (x = column, y = row, y down, pixel
centres at integer coordinates).
"""

from __future__ import annotations

import numpy as np

__all__ = ["overlay", "display_rgb"]


def overlay(image, contours, infos, holes=None, verdict=None):
    """The image (as 8-bit RGB) with each contour coloured by surprisal and its peaks circled.

    Parameters
    ----------
    image : ndarray
        As read by :func:`attneave.stimuli.extraction.read_image`.
    contours : list of Contour
        ``(x, y)`` image pixels (y down, pixel centres at integers).
    infos : list of attneave.stimuli.extraction.ContourInfo
        Their surprisal (from :func:`attneave.stimuli.extraction.describe`).
    holes : list of list of Contour, optional
        Drawn as black lines on a white halo (no surprisal).
    verdict : attneave.stimuli.extraction.verdict.Verdict, optional
        A ``suspect`` verdict is written below the image (``SUSPECT:
        reason``, wrapped on up to three lines) on an orange band added to
        it, and the image gets an orange frame; ``ok`` adds nothing.

    Returns
    -------
    (H', W, 3) uint8 ndarray, RGB
        ``H' = H``, or taller by the verdict's band. Surprisal is mapped
        with the turbo colour map over each contour's own range (dark blue
        lowest, dark red highest; with one contour a colour bar gives the
        values, in the corner where it hides the least of the outline), on
        a thin white halo; peaks are white circles with a black rim.
    """
    import cv2


    rgb = display_rgb(image)
    h, w = rgb.shape[:2]
    lw = max(2, int(round(min(h, w) / 200)))
    rad = max(3, int(round(min(h, w) / 100)))
    def colour_range(group):
        u = np.concatenate([i.surprisal.surprisal for i in group])
        lo, hi = float(np.min(u)), float(np.max(u))
        # a nearly constant surprisal (a circle) is shown as constant: the
        # scale spans at least the step from the mean turn to twice it (the
        # default peak prominence is 5 % of that)
        floor = max((i.params.get("prominence") or 0.0) for i in group) / 0.05
        span = max(hi - lo, floor)
        return lo, (span if span > 0 else 1.0)

    # objects of different sizes have different spacings (and the paper's
    # surprisal scales with spacing^2): each object gets its own scale
    ranges = [colour_range([i]) for i in infos]
    lut = cv2.applyColorMap(np.arange(256, dtype=np.uint8)[:, None], cv2.COLORMAP_TURBO)[:, 0, ::-1]
    shift = 4  # sub-pixel drawing: coordinates in 1/16 px
    scale = 1 << shift
    for c, info, (lo, span) in zip(contours, infos, ranges):
        res = info.surprisal
        u = res.surprisal
        # colour each stretch of the contour by the surprisal at its arc position
        t = c.t()
        tu = np.append(res.t, 1.0)
        uu = np.append(u, u[0])
        val = np.interp(t, tu, uu)
        idx = np.clip(((val - lo) / span * 255).round().astype(int), 0, 255)
        p = np.round(np.vstack([c.points, c.points[:1]]) * scale).astype(np.int32)
        # draw runs of equal colour as polylines (fast even for long contours)
        # a white halo keeps the dark end of the colour map visible on dark images
        cv2.polylines(rgb, [p.reshape(-1, 1, 2)], True, (255, 255, 255), lw + 2, cv2.LINE_AA, shift)
        brk = np.flatnonzero(np.diff(idx)) + 1
        starts = np.concatenate([[0], brk])
        ends = np.concatenate([brk, [len(idx)]])
        for a, b in zip(starts, ends):
            col = tuple(int(v) for v in lut[idx[a]])
            cv2.polylines(rgb, [p[a : b + 1].reshape(-1, 1, 2)], False, col, lw, cv2.LINE_AA, shift)
        for k in res.peaks:
            x, y = res.contour.points[k]
            centre = (int(round(x * scale)), int(round(y * scale)))
            cv2.circle(rgb, centre, (rad + lw) * scale, (0, 0, 0), lw + 1, cv2.LINE_AA, shift)
            cv2.circle(rgb, centre, rad * scale, (255, 255, 255), lw, cv2.LINE_AA, shift)
    for hole in (h for hl in (holes or []) for h in hl):
        p = np.round(hole.points * scale).astype(np.int32).reshape(-1, 1, 2)
        cv2.polylines(rgb, [p], True, (255, 255, 255), lw + 2, cv2.LINE_AA, shift)
        cv2.polylines(rgb, [p], True, (0, 0, 0), max(1, lw - 1), cv2.LINE_AA, shift)
    units = infos[0].params.get("units", "nats")
    points = np.vstack([c.points for c in contours]) if contours else np.zeros((0, 2))
    if len(infos) == 1:
        lo, span = ranges[0]
        _legend(rgb, lut, f"{lo:.4g}", f"{lo + span:.4g} {units}", points)
    else:
        _legend(rgb, lut, "low", f"high {units} (per object)", points)
    if verdict is not None and verdict.status != "ok":
        rgb = _banner(rgb, f"{verdict.status.upper()}: {verdict.reason}")
    return rgb


def _legend(rgb, lut, low, high, points=None, band=0):
    """A small colour bar with its end values, in the corner where it hides the least of the contours.

    `points` are the contours' points (x, y); `band` a height at the bottom the legend must not cover.
    """
    import cv2


    h, w = rgb.shape[:2]
    font = cv2.FONT_HERSHEY_SIMPLEX
    fs = float(np.clip(min(h, w) / 900, 0.3, 1.0))
    (tw0, th), _ = cv2.getTextSize(low, font, fs, 1)
    (tw1, _), _ = cv2.getTextSize(high, font, fs, 1)
    bar = int(np.clip(w // 5, 30, 200))
    total = tw0 + bar + tw1 + 20
    if total > w or 2 * th + 8 + band > h:
        return  # too small an image for a legend
    corners = [(4, 4), (w - total - 5, 4), (4, h - band - th - 15), (w - total - 5, h - band - th - 15)]
    if points is not None and len(points):
        # pad by a line width or two so that the bar does not touch the outline either
        pad = max(3, min(h, w) // 100)

        def hidden(corner):
            x, y = corner
            inside = ((points[:, 0] > x - pad) & (points[:, 0] < x + total + pad)
                      & (points[:, 1] > y - pad) & (points[:, 1] < y + th + 10 + pad))
            return int(inside.sum())

        corners.sort(key=hidden)  # stable: top-left when it hides nothing
    x0, y0 = corners[0]
    cv2.rectangle(rgb, (x0, y0), (x0 + total, y0 + th + 10), (255, 255, 255), -1)
    cv2.putText(rgb, low, (x0 + 4, y0 + th + 4), font, fs, (0, 0, 0), 1, cv2.LINE_AA)
    bx = x0 + tw0 + 10
    cols = lut[np.linspace(0, 255, bar).round().astype(int)]
    rgb[y0 + 3 : y0 + th + 7, bx : bx + bar] = cols[None, :, :]
    cv2.putText(rgb, high, (bx + bar + 6, y0 + th + 4), font, fs, (0, 0, 0), 1, cv2.LINE_AA)


def _banner(rgb, text, colour=(255, 140, 0), max_lines=3):
    """The image in an orange frame with a band below it holding `text`, wrapped to the image's width
    on at most `max_lines` lines (the last cut with '...'; the full text is in summary.csv).

    The band is added below the image, so that no part of the photo and its outline is hidden: the
    overlay of a suspect outline is taller than its image. Returns the new image."""
    import cv2

    h, w = rgb.shape[:2]
    t = max(2, int(round(min(h, w) / 150)))
    font = cv2.FONT_HERSHEY_SIMPLEX
    fs = float(np.clip(min(h, w) / 900, 0.3, 0.8))
    (_, th), _ = cv2.getTextSize("Ag", font, fs, 1)

    def fits(s):
        return cv2.getTextSize(s, font, fs, 1)[0][0] <= w - 8


    lines, words = [], text.split()
    while words and len(lines) < max_lines:
        line = words.pop(0)
        while words and fits(line + " " + words[0]):
            line += " " + words.pop(0)
        lines.append(line)
    if words:
        lines[-1] += " " + " ".join(words)
    for i, line in enumerate(lines):  # the last line's rest, or one word wider than the image
        while len(line) > 8 and not fits(line):
            # at least 4 characters shorter each time ("..." included), or a short text never ends
            line = line[: min(int(len(line) * 0.9), len(line) - 4) - 3].rstrip() + "..."
        lines[i] = line
    step = th + 6
    out = np.empty((h + step * len(lines) + 4, w, 3), np.uint8)
    out[:h] = rgb
    out[h:] = colour
    cv2.rectangle(out, (0, 0), (w - 1, out.shape[0] - 1), colour, t)
    for i, line in enumerate(lines):
        cv2.putText(out, line, (4, h + th + 3 + i * step), font, fs, (0, 0, 0), 1, cv2.LINE_AA)
    return out


def display_rgb(image):
    """8-bit RGB copy of an image for drawing on (alpha composited over white)."""
    img = np.asarray(image)
    if img.dtype == bool:
        img = img.astype(np.uint8) * 255
    f = img.astype(np.float64)
    if img.dtype == np.uint8:
        scale = 255.0
    elif img.dtype == np.uint16:
        scale = 65535.0
    else:
        lo, hi = float(f.min()), float(f.max())
        f = (f - lo) / (hi - lo if hi > lo else 1.0)
        scale = 1.0
    f = f / scale
    if f.ndim == 2:
        f = np.repeat(f[:, :, None], 3, axis=2)
    elif f.shape[2] == 1:
        f = np.repeat(f, 3, axis=2)
    elif f.shape[2] == 2:
        f = np.concatenate([np.repeat(f[:, :, :1], 3, axis=2), f[:, :, 1:]], axis=2)
    if f.shape[2] == 4:
        a = f[:, :, 3:4]
        f = f[:, :, :3] * a + (1.0 - a)
    return np.ascontiguousarray(np.clip(np.round(f[:, :, :3] * 255), 0, 255).astype(np.uint8))
