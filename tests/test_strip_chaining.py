"""Consecutive strips of a curved-edge proof hold each other's node cross-sections
(runtime/voronoi/verify/curved.py, "Chaining at the nodes"): the arc of β in one strip crosses its
cross-section at the shared node at one point, and that point must lie in the next strip, so that
the two arcs join.  Checked here with plain coordinates: a trapezoid of half-width W_l + k·s over
s ∈ [−e, L + e] (the widths extrapolated in the extensions, e = max(W)·sin θ), and both ends of
one of the two node cross-sections inside the other strip (a segment in a convex set)."""
import math

import numpy as np
import pytest

from curvedvoronoi.runtime.voronoi.verify.curved import chained_nodes


def _cross(u, v):
    return float(u[0] * v[1] - u[1] * v[0])


def _inside(P0, t, L, w0, w1, e_lo, e_hi, X):
    n = np.array([-t[1], t[0]])
    s, lam = (X - P0) @ t, (X - P0) @ n
    w = w0 + (w1 - w0) / L * s
    return -e_lo - 1e-12 <= s <= L + e_hi + 1e-12 and abs(lam) <= w + 1e-12


def _nodes_chain(S, W):
    seg = S[1:] - S[:-1]
    L = np.hypot(*seg.T)
    T = seg / L[:, None]
    sin = [0.0] + [abs(_cross(T[j], T[j + 1])) for j in range(len(T) - 1)] + [0.0]
    wn = np.maximum(W[:-1], W[1:])
    e_lo = [wn[j - 1] * sin[j] if j else 0.0 for j in range(len(T))]
    e_hi = [wn[j + 1] * sin[j + 1] if j + 1 < len(T) else 0.0 for j in range(len(T))]
    for j in range(1, len(S) - 1):                  # node j: strips j - 1 and j
        P = S[j]
        a, b = j - 1, j
        na, nb = np.array([-T[a][1], T[a][0]]), np.array([-T[b][1], T[b][0]])
        ends_a = [P + W[j] * na, P - W[j] * na]     # strip a's cross-section at P
        ends_b = [P + W[j] * nb, P - W[j] * nb]
        in_b = all(_inside(S[b], T[b], L[b], W[b], W[b + 1], e_lo[b], e_hi[b], X) for X in ends_a)
        in_a = all(_inside(S[a], T[a], L[a], W[a], W[a + 1], e_lo[a], e_hi[a], X) for X in ends_b)
        if not (in_a or in_b):
            return False
    return True


def test_a_turn_between_two_narrowing_trapezoids_does_not_chain_without_a_flat_run():
    # node (10, 0) turned by 20°, half-width 2.5 there, both strips narrowing away from it
    th = math.radians(20)
    S = np.array([[0.0, 0.0], [10.0, 0.0], [10 + 10 * math.cos(th), 10 * math.sin(th)]])
    W = np.array([0.1, 2.5, 0.1])           # slopes ∓0.24 > tan(10°) = 0.176
    assert not _nodes_chain(S, W)
    S2, W2 = chained_nodes(S, W, False, 20.0)
    assert len(S2) > len(S) and _nodes_chain(S2, W2)


@pytest.mark.parametrize("seed", range(20))
def test_random_polylines_chain_after_chained_nodes(seed):
    rng = np.random.default_rng(seed)
    m = int(rng.integers(3, 12))
    turns = rng.uniform(-math.radians(55), math.radians(55), m)
    ang = np.cumsum(turns)
    L = rng.uniform(1, 5, m)
    S = np.vstack([[0.0, 0.0], np.cumsum(np.column_stack([L * np.cos(ang), L * np.sin(ang)]), axis=0)])
    Lmin = np.minimum(np.concatenate([[L[0]], L]), np.concatenate([L, [L[-1]]]))
    W = 0.25 * Lmin * rng.uniform(0.05, 1.0, m + 1)
    S2, W2 = chained_nodes(S, W, False, float(np.abs(S).max()) + 1)
    assert _nodes_chain(S2, W2)
    # the added nodes lie on the polyline (the guide is unchanged as a curve)
    seg = S[1:] - S[:-1]
    for x in S2:
        d = min(abs(_cross(seg[j], x - S[j])) / np.hypot(*seg[j]) +
                (0 if 0 <= (x - S[j]) @ seg[j] <= seg[j] @ seg[j] else 1) for j in range(len(seg)))
        assert d < 1e-9


def test_the_verifier_proves_strips_that_chain(monkeypatch):
    """Every chain of strips the verifier proves for a scene of ellipses satisfies the containment
    above (the chains are recorded on their way to the strips' proof)."""
    import curvedvoronoi as cv
    import curvedvoronoi.runtime.voronoi.verify.curved as curved
    import scenes

    seen = []
    original = curved.prove_strips_many

    def recording(table, jobs, **kw):
        seen.extend((np.array(jb.S), np.array(jb.W)) for jb in jobs)
        return original(table, jobs, **kw)

    monkeypatch.setattr(curved, "prove_strips_many", recording)
    d = cv.voronoi(scenes.random_ellipses(40, 1), progress=False)
    assert d.certified and seen
    assert all(_nodes_chain(S, W) for S, W in seen if not np.allclose(S[0], S[-1]))


def _wrap_chains(S, W):
    """The closing node of a closed chain: the cross-section of the side with the smaller node
    half-width lies in the other strip (extensions max(W)·sin θ at the closing node)."""
    seg = S[1:] - S[:-1]
    L = np.hypot(*seg.T)
    T = seg / L[:, None]
    sw = abs(_cross(T[-1], T[0]))
    e = max(W[0], W[-1]) * sw
    P = S[0]
    nl, nf = np.array([-T[-1][1], T[-1][0]]), np.array([-T[0][1], T[0][0]])
    if W[-1] <= W[0]:               # the last strip's cross-section (half-width W[-1]) in the first
        return all(_inside(S[0], T[0], L[0], W[0], W[1], e, 0.0, X) for X in (P + W[-1] * nl, P - W[-1] * nl))
    return all(_inside(S[-2], T[-1], L[-1], W[-2], W[-1], 0.0, e, X) for X in (P + W[0] * nf, P - W[0] * nf))


def test_the_closing_node_of_a_closed_chain_chains():
    # a regular 18-gon of side 10 (turns of 20°), half-width 2.5 at the closing node only: both
    # strips there narrow by 0.24 per unit length, more than tan(10°)
    ang = np.radians(20) * np.arange(18)
    S = np.vstack([[0.0, 0.0], np.cumsum(np.column_stack([10 * np.cos(ang), 10 * np.sin(ang)]), axis=0)])
    S[-1] = S[0]
    W = np.full(len(S), 0.1)
    W[0] = W[-1] = 2.5
    assert not _wrap_chains(S, W)
    S2, W2 = chained_nodes(S, W, True, 100.0)
    assert _wrap_chains(S2, W2) and _nodes_chain(S2, W2)
