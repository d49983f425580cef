"""Log-aesthetic arcs' integrals (attneave.stimuli.curves.lac.arc, lac_quadrature):
the derivatives Newton uses against finite differences of the integrals,
the graded rule's depth per alpha against the deepest rule and against the
arc's natural equation, the one-sided rule against the two-sided one, and
the dense Newton step against SuperLU's."""

import numpy as np
import pytest
from scipy.sparse.linalg import spsolve

from attneave.stimuli.curves.lac.arc import (
    arc_integrals,
    arc_turn,
    grading_levels,
    graph_inverse,
    graph_value,
    piece_chords,
)
from attneave.stimuli.curves.lac.newton import LACSystem
from attneave.stimuli.curves.lac.quadrature import LEVELS, graded_rule, quadrature_groups

# arcs through an inflection, of one sign with a large curvature ratio, nearly circular
K0 = np.array([-1.0, 5.0, 0.8, 2.0, 1.0])
K1 = np.array([2.0, 0.05, -3.0, 2.0 + 1e-9, 1.7])
TH0 = np.array([0.4, -1.0, 2.0, 0.1, 0.0])
L = np.array([1.3, 3.0, 0.7, 1.0, 1.1])


@pytest.mark.parametrize("alpha", [-2.0, -1.0, -0.3, 0.5])
def test_derivatives_against_finite_differences(alpha):
    # the closed-form derivatives (sums of kappa e, t kappa e, Theta e over the
    # nodes) against central differences of the integrals themselves, in the
    # graph variables u = g(kappa) and the length
    keep = slice(None) if alpha < 0 else [1, 3, 4]  # alpha >= 0: arcs of one sign only
    k0, k1, th0, L_ = K0[keep], K1[keep], TH0[keep], L[keep]
    arc = arc_integrals(th0, k0, k1, L_, alpha)
    u0, u1 = graph_value(k0, alpha), graph_value(k1, alpha)
    for name, fn in (("u0", lambda h: arc_integrals(th0, graph_inverse(u0 + h, alpha), k1, L_, alpha)),
                     ("u1", lambda h: arc_integrals(th0, k0, graph_inverse(u1 + h, alpha), L_, alpha)),
                     ("L", lambda h: arc_integrals(th0, k0, k1, L_ + h, alpha))):
        h = 1e-6
        plus, minus = fn(h), fn(-h)
        dz = (plus["z"] - minus["z"]) / (2 * h)
        np.testing.assert_allclose(arc["z_" + name], dz, rtol=0, atol=2e-6 * np.abs(dz).max())
        if name != "L":
            dturn = (plus["turn"] - minus["turn"]) / (2 * h)
            np.testing.assert_allclose(arc["turn_" + name], dturn, rtol=0, atol=2e-6 * np.abs(dturn).max())


def test_derivatives_are_computed_once_and_lazily():
    arc = arc_integrals(TH0, K0, K1, L, -0.3)
    assert "z_L" not in arc.values                     # values only, until a derivative is asked for
    eager = arc_integrals(TH0, K0, K1, L, -0.3, derivatives=True)
    for key in ("z", "turn", "Theta1", "z_L", "z_u0", "z_u1", "turn_u0", "turn_u1"):
        np.testing.assert_array_equal(arc[key], eager[key])
    assert sorted(arc) == sorted(eager) and len(arc) == 8


def test_shallower_grading_agrees_with_the_deepest():
    # the depth grading_levels gives alpha = -0.3 (4 levels, 160 nodes on an
    # inflected arc instead of 240) changes the chord by rounding only
    rng = np.random.default_rng(3)
    alpha = -0.3
    levels = grading_levels(alpha)
    assert levels < LEVELS
    worst = 0.0
    for _ in range(100):
        k0 = rng.uniform(-30, 30)
        k1 = -np.sign(k0) * 10 ** rng.uniform(-2, 2)
        Lk = 10 ** rng.uniform(-1, 0.5)
        v0, v1 = graph_value(k0, alpha), graph_value(k1, alpha)
        ts = np.array([v0 / (v0 - v1)])
        z = []
        for lev in (levels, LEVELS):
            x, w = graded_rule(np.zeros(1), np.ones(1), ts, levels=lev)
            z.append(Lk * np.sum(np.exp(1j * (0.3 + Lk * arc_turn(x, k0, k1, alpha))) * w))
        worst = max(worst, abs(z[0] - z[1]) / Lk)
    assert worst < 2e-15


def test_one_sided_rule_drops_only_weightless_nodes():
    # t* beyond an interval's end: the two-sided rule's panels on the far side
    # of t* have no length; the one-sided rule integrates the same (a kink
    # |t - t*|**1.5 just beyond 1)
    f = lambda t: np.abs(t - 1.2) ** 1.5  # noqa: E731
    exact = (1.2 ** 2.5 - 0.2 ** 2.5) / 2.5
    for one_side in (False, True):
        x, w = graded_rule(np.zeros(1), np.ones(1), np.array([1.2]), one_side=one_side)
        assert abs(np.sum(w * f(x)) - exact) < 1e-14
        assert x.shape == (1, 120 if one_side else 240)
    groups = quadrature_groups(0.0, 1.0, np.array([0.5, 1.2, 5.0]))
    assert [(g[0].tolist(), g[1].shape[1]) for g in groups] == [([2], 24), ([0], 240), ([1], 120)]


def test_piece_chords_add_up_to_the_arc():
    # the chords of an arc's pieces add up to its chord (one rule per piece;
    # both agree with the natural equation to ~1e-13 of the length at alpha = -2)
    t = np.linspace(0, 1, 8)
    for alpha in (-0.3, -2.0):
        whole = arc_integrals(TH0, K0, K1, L, alpha)["z"]
        arcs = np.repeat(np.arange(K0.size), 7)
        lo, hi = np.tile(t[:-1], K0.size), np.tile(t[1:], K0.size)
        parts = piece_chords(TH0, K0, K1, L, alpha, lo, hi, arcs).reshape(K0.size, 7).sum(axis=1)
        np.testing.assert_allclose(parts, whole, rtol=0, atol=1e-12)


def test_dense_step_is_superlus():
    # small systems take numpy's dense LU: the same Newton step as SuperLU's
    t = np.linspace(0, 2 * np.pi, 9, endpoint=False)
    P = np.c_[100 + 40 * np.cos(t) + 6 * np.cos(3 * t), 100 - 25 * np.sin(t)]
    system = LACSystem(P, closed=True, wind=-1)
    rng = np.random.default_rng(0)
    x = np.concatenate((rng.uniform(0, 6, system.nt), rng.uniform(-2, 2, system.nu), rng.uniform(0.5, 1.5, system.M)))
    F, arc = system.residual(x, -0.3)
    dense = system.step(arc, -0.3, F)
    sparse = spsolve(system.jacobian(arc, -0.3), -F)
    assert x.size <= 96
    np.testing.assert_allclose(dense, sparse, rtol=0, atol=1e-10 * np.abs(sparse).max())
