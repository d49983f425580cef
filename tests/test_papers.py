"""The seed paper's figures as data (attneave.papers): fingerprints of every
plotted array, the readings of Figs. 2 and 4, and data apart from drawing.

The fingerprints in ``tests/data/papers_fingerprints.json`` were recorded from
the figures as reviewed; an intended change to a figure is recorded with
``python tests/test_papers.py --update`` (and said in the commit).
"""

import json
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from attneave.papers.base import fingerprint
from attneave.papers.ziatdinov import FIGURES, fig2, fig4

STORE = Path(__file__).parent / "data" / "papers_fingerprints.json"
RTOL = 1e-9
LEVEL = -np.log(0.25)  # -ln A' with the captions' A' = 1/4


def differences(stored, now, rtol=RTOL):
    """Names of the arrays whose fingerprints differ by more than `rtol` of their largest magnitude."""
    bad = []
    for key in sorted(stored.keys() | now.keys()):
        a, b = stored.get(key), now.get(key)
        if a is None or b is None or a[:2] != b[:2] or len(a) != len(b):
            bad.append(key)
            continue
        if len(a) == 2:  # no finite value
            continue
        points = a[5:]
        scale = max(abs(v) for v in points[2:])  # the larger of |min|, |max|
        tolerances = [scale, scale * scale, scale] + [scale] * 4
        if any(abs(x - y) > rtol * t for x, y, t in zip(a[2:], b[2:], tolerances)):
            bad.append(key)
    return bad


def stored():
    return json.loads(STORE.read_text())


def test_every_figure_has_a_stored_fingerprint():
    assert list(stored()) == list(FIGURES)


@pytest.mark.parametrize("name", list(FIGURES))
def test_figure_data_matches_its_fingerprint(name):
    fd = FIGURES[name]()
    assert fd.name == name
    assert differences(stored()[name], fingerprint(fd)) == []


def test_fingerprint_notices_a_small_change_to_one_curve():
    fd = fig4()
    line = fd.panels[0].lines[1]
    y = line.y.copy()
    y[1500] *= 1 + 1e-7
    changed = replace(fd, panels=(replace(fd.panels[0], lines=(fd.panels[0].lines[0], replace(line, y=y),
                                                                fd.panels[0].lines[2])),) + fd.panels[1:])
    assert differences(fingerprint(fd), fingerprint(changed)) == ["p0/1:b = 1/y"]
    # a point moved along the curve changes no sum but the first point
    x = line.x.copy()
    x[0] += 1e-6
    moved = replace(fd, panels=(replace(fd.panels[0], lines=(replace(fd.panels[0].lines[0], x=x),)
                                        + fd.panels[0].lines[1:]),) + fd.panels[1:])
    assert differences(fingerprint(fd), fingerprint(moved)) == ["p0/0:b = 0.5/x"]


def test_figure_data_needs_no_matplotlib():
    code = ("import sys\nfrom attneave.papers.ziatdinov import FIGURES\n"
            "[f() for f in FIGURES.values()]\nprint('matplotlib' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


# ---------------------------------------------------------------- Fig. 4: the caption's clothoid


def test_fig4_draws_the_clothoid_reading():
    # caption: "(clothoid) with given curvature kappa = 2 pi/ns, s in [0; 3], s = 100, n = 10"
    fd = fig4()
    (kappa,) = fd.panels[2].lines
    s, k = kappa.x, kappa.y
    assert s[0] == 0 and s[-1] == 3
    # a clothoid: curvature linear in arc length, kappa(s)/s = 2 pi/n
    np.testing.assert_allclose(np.diff(k, 2), 0, atol=1e-12)
    np.testing.assert_allclose(k[1:] / s[1:], 2 * np.pi / 10, rtol=1e-12)
    # and the u drawn is eq. 5 along it with ds = L/n = 10: u = -ln A' - b 100 cos(2 pi s - 2 pi/10)
    for b, line in zip((0.5, 1.0, 2.0), fd.panels[0].lines):
        assert line.label == f"b = {b:g}"
        np.testing.assert_array_equal(line.x, s)
        np.testing.assert_allclose(line.y, LEVEL - b * 100 * np.cos(2 * np.pi * s - 2 * np.pi / 10), atol=1e-9)
    assert "clothoid" in fd.panels[0].title and "clothoid" in fd.title and "(2 pi/n) s" in fd.panels[0].title
    assert "logarithmic spiral" in fd.panels[1].title and "clothoid" in fd.reading


def test_fig4_other_reading_is_a_logarithmic_spiral():
    fd = fig4()
    (kappa,) = fd.panels[3].lines
    np.testing.assert_allclose(kappa.y * kappa.x, 2 * np.pi / 10, rtol=1e-12)  # radius n s/(2 pi)
    for b, line in zip((0.5, 1.0, 2.0), fd.panels[1].lines):
        np.testing.assert_allclose(line.y, LEVEL - b * 100 * np.cos(2 * np.pi / line.x - 2 * np.pi / 10), atol=1e-9)


# ---------------------------------------------------------------- Fig. 2: text and caption side by side


def test_fig2_literal_reading_beside_the_text():
    fd = fig2()
    text, literal = fd.panels
    for b in (0.5, 1.0, 2.0):
        (lit,) = [line for line in literal.lines if line.label == f"b = {b:g}"]
        (txt,) = [line for line in text.lines if line.label == f"b = {b:g}"]
        s = lit.x
        assert s[0] == pytest.approx(0, abs=1e-12) and s[-1] == pytest.approx(3)
        # the caption read literally: ds = L/n = 100/10, u = -ln A' - b 100 cos(10 exp(s) - 2 pi/10)
        np.testing.assert_allclose(lit.y, LEVEL - b * 100 * np.cos(10 * np.exp(s) - 2 * np.pi / 10), atol=1e-9)
        # ~30 periods, each resolved: its range is the full 2 b ds^2 = 200 b
        assert 200 * b * (1 - 1e-3) < np.ptp(lit.y) <= 200 * b + 1e-9
        assert fd.params["u_range"]["caption ds = 10"][b] == pytest.approx(np.ptp(lit.y))
        assert fd.params["u_range"]["text ds = s/n"][b] == pytest.approx(np.ptp(txt.y))
    # the text's reading spans 0.26 for b = 2 (dense evaluation of eq. 5 with ds = s/n)
    s = np.linspace(0, 3, 300001)
    dense = LEVEL - 2 * (s / 10) ** 2 * np.cos(np.exp(s) * s / 10 - 2 * np.pi / 10)
    assert fd.params["u_range"]["text ds = s/n"][2.0] == pytest.approx(np.ptp(dense), rel=1e-6)
    assert "u spans 0.26 for b = 2" in text.title and "u spans 400 for b = 2" in literal.title


def test_draw_keeps_every_panel_and_title():
    from attneave.papers.draw import draw, png_bytes

    fd = fig4()
    fig = draw(fd)
    try:
        assert len(fig.axes) == 4
        assert [ax.get_title() for ax in fig.axes] == [p.title for p in fd.panels]
        assert len(fig.axes[0].get_lines()) == 3 + 1  # three b and the level -ln A'
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)
    assert png_bytes(fd)[:8] == b"\x89PNG\r\n\x1a\n"


if __name__ == "__main__" and sys.argv[1:] == ["--update"]:
    STORE.write_text(json.dumps({name: fingerprint(f()) for name, f in FIGURES.items()}, indent=1) + "\n")
    print(f"wrote {STORE}")
