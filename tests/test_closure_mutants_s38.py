"""Mutants of :mod:`curvedvoronoi.runtime.voronoi.verify.closure` (mutation sample seed 38).

Far from disjoint circles c_k (centre C_k, radius ρ_k) in the direction u(θ), d_k(m + t·u) =
t − (C_k·u + ρ_k) + O(1/t) after the same shift for every k, so the site owning the far
direction θ maximises h_k(θ) = C_k·u(θ) + ρ_k (Anton's thesis, ch. 4, unbounded edges), and an
unbounded edge of the pair (i, j) runs to infinity only in a direction where h_i = h_j is the
maximum.  The accounting at infinity must refuse ends placed anywhere else: between two
consecutive ends the shared site must own the whole arc, not only its first direction."""
import math
from fractions import Fraction as F

from curvedvoronoi.runtime.predicates.circles import Circle
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.verify.closure import verify_accounting
from curvedvoronoi.runtime.voronoi.verify.edge_checks import check_edges
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable
from curvedvoronoi.runtime.voronoi.verify.vertices import prove_vertices

CIRCLES = [(0.0, 0.0, 1.0), (10.0, 0.0, 2.0), (4.0, 8.0, 0.5)]


def _h(k, th):
    x, y, r = CIRCLES[k]
    return x * math.cos(th) + y * math.sin(th) + r


def _proved_ends():
    D = voronoi([Circle.from_radius(x, y, F(r)) for x, y, r in CIRCLES], certify=False)
    geoms = [site_geometry(s) for s in D.sites]
    T = CircleTable(geoms)
    problems: list = []
    vinfo, vok = prove_vertices(D, list(D.sites), geoms, T, problems)
    eok, ends, _ = check_edges(D, geoms, T, vinfo, vok, problems, {})
    assert all(eok) and not problems and len(ends) == 3, problems
    return T, ends


def test_an_unbounded_end_moved_into_the_next_sector_is_refused():
    T, ends = _proved_ends()
    assert verify_accounting(3, T, ends, [])
    k = next(n for n, e in enumerate(ends) if tuple(sorted(e[1])) == (0, 2))
    th = ends[k][0]
    # the true end direction of (0, 2) is where h_0 = h_2 = max (closed form: C_2 - C_0 = (4, 8),
    # ρ_2 - ρ_0 = -1/2, so 4 cos θ + 8 sin θ = 1/2 there)
    assert abs(4 * math.cos(th) + 8 * math.sin(th) - 0.5) < 1e-9
    moved = th + 0.5
    # on (th, th + 0.5] site 0 strictly beats 2 (and 1): no end of the pair (0, 2) can lie at th + 0.5,
    # and the arc from the (1, 2) end to it is not all owned by site 2
    for t in (th + 0.01 * s for s in range(1, 51)):
        assert _h(0, t) > _h(2, t) and _h(0, t) > _h(1, t)
    bad = list(ends)
    bad[k] = (moved % (2 * math.pi),) + tuple(ends[k][1:])
    probs: list = []
    assert not verify_accounting(3, T, bad, probs)
