"""The chaining of strips computed for many chains at once (runtime/voronoi/verify/curved.py,
:func:`chained_nodes_many`, :func:`strip_extensions_many`; "Chaining at the nodes" there).

One call serves chains of every kind side by side: open ones with a turn between a flat and a
steep trapezoid (either order: the flat strip's extension must hold the other's cross-section),
ones that need a flat run, closed ones whose closing node needs a flat run on the first strip
(W_a ≤ W_b) or on the last (W_a > W_b), one where that run does not fit (refused), and ends
with vertex boxes.  Each chain returned is checked exactly (every float read as a rational,
:class:`fractions.Fraction`): at every node, one strip's cross-section lies in the other strip
with the extensions returned; at the closing node likewise; the vertex box of half-width h at
an end lies in the first / last strip's range of s; the added nodes lie on the original
polyline."""
from fractions import Fraction as Fr

import numpy as np

from curvedvoronoi.runtime.voronoi.verify.curved import chained_nodes_many, strip_extensions_many
from test_strip_chaining_tiny_turns import _chains_exactly, _in_strip


def _polygon(k, side):
    """A closed regular k-gon of the given side (S[-1] = S[0])."""
    ang = 2 * np.pi / k * np.arange(k)
    S = np.vstack([[0.0, 0.0], np.cumsum(np.column_stack([side * np.cos(ang), side * np.sin(ang)]), axis=0)])
    S[-1] = S[0]
    return S


def _closes_exactly(S, T, L, e_lo, e_hi, W):
    """At the closing node P = S[0] = S[-1]: the last strip's cross-section at P lies in the first
    strip, or the first strip's in the last one (shortened by 10⁻¹² as in _chains_exactly)."""
    P = (Fr(S[0][0]), Fr(S[0][1]))
    first, last = 0, len(L) - 1
    for u, w_u, v in ((last, W[-1], first), (first, W[0], last)):
        nx, ny = -Fr(T[u][1]), Fr(T[u][0])
        w = Fr(w_u) * (1 - Fr(1, 10 ** 12))
        ends = [(P[0] + sg * w * nx, P[1] + sg * w * ny) for sg in (1, -1)]
        if all(_in_strip(S[v], T[v], L[v], W[v], W[v + 1], e_lo[v], e_hi[v], X) for X in ends):
            return True
    return False


def _box_in_range(P, h, S0, T, L, e_lo, e_hi):
    """The box of half-width h around P lies in {s ∈ [−e_lo, L + e_hi]} of the strip from S0."""
    tx, ty = Fr(T[0]), Fr(T[1])
    tt = tx * tx + ty * ty
    for sx in (1, -1):
        for sy in (1, -1):
            dx, dy = Fr(P[0]) + sx * Fr(h) - Fr(S0[0]), Fr(P[1]) + sy * Fr(h) - Fr(S0[1])
            s = (dx * tx + dy * ty) / tt
            if not -Fr(e_lo) <= s <= Fr(L) + Fr(e_hi):
                return False
    return True


def _on_polyline(x, S):
    seg = S[1:] - S[:-1]
    return any(abs(seg[j][0] * (x - S[j])[1] - seg[j][1] * (x - S[j])[0]) <= 1e-9 * (seg[j] @ seg[j])
               and -1e-12 <= (x - S[j]) @ seg[j] <= seg[j] @ seg[j] * (1 + 1e-12) for j in range(len(seg)))


def _chains():
    """(S, W, closed, h0, h1) of the chains served together."""
    th = np.radians(10)
    bend = np.array([[0.0, 0.0], [10.0, 0.0], [10 + 10 * np.cos(th), 10 * np.sin(th)]])
    th2 = np.radians(20)
    narrow = np.array([[0.0, 0.0], [10.0, 0.0], [10 + 10 * np.cos(th2), 10 * np.sin(th2)]])
    out = [(bend, np.array([1.0, 1.0, 5.0]), False, 0.0, 0.0),          # flat, then steep
           (bend, np.array([5.0, 1.0, 1.0]), False, 0.0, 0.0),          # steep, then flat
           (narrow, np.array([0.1, 2.5, 0.1]), False, 0.05, 0.03)]       # both narrowing: a flat run
    P = _polygon(18, 1.0)
    for wa, wb in ((0.49, 0.49), (0.5, 0.49), (4.0, 4.0)):              # W_a ≤ W_b, W_a > W_b, no room
        W = np.full(len(P), 0.01)
        W[0], W[-1] = wb, wa
        out.append((P, W, True, 0.0, 0.0))
    return out


def test_chains_served_together_chain_exactly():
    chains = _chains()
    jn = np.repeat(np.arange(len(chains)), [len(c[0]) for c in chains])
    closed = np.array([c[2] for c in chains])
    scale = np.full(len(chains), 20.0)
    h0, h1 = np.array([c[3] for c in chains]), np.array([c[4] for c in chains])
    S2, W2, jn2, ok = chained_nodes_many(np.concatenate([c[0] for c in chains]), np.concatenate([c[1] for c in chains]),
                                         jn, closed, scale)
    T2, _, L2, e_lo, e_hi = strip_extensions_many(S2, W2, jn2, closed, scale, h0, h1)
    sj = jn2[:-1][jn2[:-1] == jn2[1:]]                        # the chain of each strip
    assert list(ok) == [True] * 5 + [False]                  # the last closing run has no room
    for t, (S, W, cl, hs, he) in enumerate(chains[:5]):
        Sc, Wc = S2[jn2 == t], W2[jn2 == t]
        Tc, Lc, lo, hi = T2[sj == t], L2[sj == t], e_lo[sj == t], e_hi[sj == t]
        assert _chains_exactly(Sc, Tc, Lc, lo, hi, Wc), t
        assert all(_on_polyline(x, S) for x in Sc), t
        if cl:
            assert _closes_exactly(Sc, Tc, Lc, lo, hi, Wc), t
        else:
            assert _box_in_range(Sc[0], hs, Sc[0], Tc[0], Lc[0], lo[0], hi[0])
            assert _box_in_range(Sc[-1], he, Sc[-2], Tc[-1], Lc[-1], lo[-1], hi[-1])
    assert len(S2[jn2 == 2]) > 3 and len(S2[jn2 == 4]) > len(chains[4][0])     # flat runs were needed


def test_the_refused_closing_run_would_not_chain_without_it():
    """The chain refused above does not close without a flat run (so refusing it is needed), and
    one that fits in half its segment is W·sin θ long: 4·sin 20° > 1/2 here."""
    P, W, _, _, _ = _chains()[-1]
    T = (P[1:] - P[:-1]) / np.hypot(*(P[1:] - P[:-1]).T)[:, None]
    L = np.hypot(*(P[1:] - P[:-1]).T)
    sw = abs(T[-1][0] * T[0][1] - T[-1][1] * T[0][0])
    e = np.zeros(len(L))
    e[0] = e[-1] = max(W[0], W[-1]) * sw
    assert not _closes_exactly(P, T, L, e, e, W)
    assert W[0] * sw > 0.5 * L[0]


def test_an_attempt_whose_strips_cannot_chain_is_not_proved():
    """Node half-widths (0.1, 5, 0.1) over two unit segments turned by 40°: both trapezoids narrow
    away from the node by 4.9 per unit length, far more than tan 20°, so their node cross-sections
    do not hold each other (checked with the plain-coordinate test of test_strip_chaining), and a
    flat run W·sin θ = 3.2 long does not fit in half a segment: the attempt must not be proved,
    served alone or next to others."""
    import curvedvoronoi as cv
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.verify.curved import (WIDTHS, ChainEnds, ChainJob, EdgeWork, RoundGuide,
                                                             prove_widths_many, turn_sines)
    from curvedvoronoi.runtime.voronoi.verify.curved_edges import curved_scale
    from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable
    from curvedvoronoi.runtime.voronoi.verify.strips import rot90
    from test_strip_chaining import _nodes_chain

    geoms = [site_geometry(s) for s in (cv.Conic.ellipse((0, 0), (10, 4)), cv.Conic.ellipse((30, 0), (10, 4)))]
    scale = curved_scale(geoms)
    table = SiteTable(geoms, scale)
    th = np.radians(40)
    S = np.array([[15.0, -1.0], [15.0, 0.0], [15.0 + np.sin(th), np.cos(th)]])
    seg = S[1:] - S[:-1]
    L = np.hypot(*seg.T)
    T = seg / L[:, None]
    g = RoundGuide(S, L, T, rot90(T), turn_sines(T[:-1], T[1:])[1], [], np.array([0.1, 5.0, 0.1]),
                   np.full(3, 100.0), np.full(3, np.inf))
    ends = ChainEnds(None, None, None, None, 0.0, 0.0, [None, None], (None, None), [], 0.0)
    wfac, endfac = WIDTHS[0]
    assert not _nodes_chain(S, wfac * np.array([0.1, 5.0, 0.1]))
    assert 5.0 * wfac * np.sin(th) > 0.5 * L.max()
    job = ChainJob(g, ends, wfac, endfac, False, scale, (0, 1), EdgeWork())
    straight = RoundGuide(S[:2], L[:1], T[:1], rot90(T[:1]), np.zeros(0), [], np.full(2, 0.1), np.full(2, 100.0),
                          np.full(2, np.inf))
    other = ChainJob(straight, ends, wfac, endfac, False, scale, (0, 1), EdgeWork())
    assert not prove_widths_many(table, [job])[0][0]
    assert not prove_widths_many(table, [other, job, other])[1][0]
