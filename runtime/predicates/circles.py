"""Exact Delaunay-graph conflict locator for circles (thesis §3.1.3).

Sites are circles C_i = (centre c_i, radius ρ_i ≥ 0; ρ_i = 0 is a point).  The distance from q
to C_i is d(q, C_i) = | |q - c_i| - ρ_i |.  A *true Voronoi vertex* of C1, C2, C3 is a point q
with d(q, C1) = d(q, C2) = d(q, C3) = ρ > 0: the circle of centre q and radius ρ is tangent to
the three circles and none of them enters its open disc.

Selection of the true vertices.  d(q, C_i) = ρ iff |q - c_i| = ρ_i + s_i ρ with s_i = ±1 and
ρ_i + s_i ρ ≥ 0 (s_i = +1: C_i outside the empty circle, s_i = -1: C_i contains it).  So the
true vertices are exactly the real solutions of the eight Apollonius systems (I) with ρ > 0
satisfying the three sign conditions.  As in the thesis we solve the four systems (II) with
s_1 = +1 in the *signed* expansion R (R < 0 is the pattern -s) and keep the solutions with
R ≠ 0 and ρ_i + s_i R ≥ 0 (i = 1, 2, 3), decided exactly.  This replaces the four-case analysis
of §3.1.3 by a test that is correct in every configuration (intersecting, disjoint, nested
circles, points); two different patterns never give the same vertex (that would force ρ = 0).

Conflict with C4 (centre c4, radius ρ4): d(q, C4) < ρ iff
    g = |q - c4|^2 - (ρ4 + ρ)^2 < 0   and   (ρ4 - ρ < 0  or  h = |q - c4|^2 - (ρ4 - ρ)^2 > 0);
tangent (d(q, C4) = ρ, not a conflict) iff g = 0 or (ρ4 ≥ ρ and h = 0).  All signs are exact
(:mod:`runtime.algebra.quadtower`), also for non-square squared radii r2 (ρ = √r2).

Public API: :class:`Circle` (re-exported from :mod:`runtime.sites.circle`), :func:`voronoi_vertices_circles` (cached, independent of C4),
:func:`locate_conflicts_circles`; the batched float-filtered path is in
:mod:`runtime.predicates.circles_filter` (:func:`runtime.predicates.circles_filter.locate_conflicts_circles_batch`).
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from functools import lru_cache

from flint import ctx, fmpq

from .apollonius import AlgebraicSolution, normalise_den, solve_system
from ..sites.circle import Circle, Point, as_circle  # noqa: F401  (re-exported: the site records)
from ..algebra.quadtower import Elem, Frac, QuadTower, frac_to_float, rational_sqrt
from ..result import LocatorError, LocatorResult, VoronoiVertex

SIGN_SYSTEMS = ((1, 1, 1), (1, 1, -1), (1, -1, 1), (1, -1, -1))


# =====================================================================================
# Radii in a quadratic tower
# =====================================================================================


class _RadiusField:
    """Builds ρ_i = √r2_i in a tower, reusing a generator when r2_i / r2_j is a square."""

    def __init__(self):
        self.T = QuadTower()
        self.gens: list[tuple[fmpq, Elem]] = []  # (radicand, generator)

    def rho(self, r2: fmpq) -> Elem:
        r = rational_sqrt(r2)
        if r is not None:
            return r
        for rad, g in self.gens:
            k = rational_sqrt(r2 / rad)
            if k is not None:
                return self.T.mul(k, g)
        self.T, g = self.T.extend(r2)
        self.gens.append((r2, g))
        return g


def _rho_in(T: QuadTower, gens, r2: fmpq) -> tuple[QuadTower, Elem]:
    r = rational_sqrt(r2)
    if r is not None:
        return T, r
    for rad, g in gens:
        k = rational_sqrt(r2 / rad)
        if k is not None:
            return T, T.mul(k, g)
    return T.extend(r2)


# =====================================================================================
# Vertices of a triple (independent of C4, cached)
# =====================================================================================


@dataclass
class CircleVertex:
    """A true Voronoi vertex, exact: q = (X/D, Y/D), radius Rn/D > 0 (D > 0), pattern s."""

    sol: AlgebraicSolution
    pattern: tuple[int, int, int]
    x: float = 0.0  #: q rounded to double (relative accuracy ~2^-52, from arb balls)
    y: float = 0.0
    radius: float = 0.0

    def __post_init__(self):
        T, D = self.sol.tower, self.sol.D
        self.x = frac_to_float(T, Frac(self.sol.X, D))
        self.y = frac_to_float(T, Frac(self.sol.Y, D))
        self.radius = frac_to_float(T, Frac(self.sol.Rn, D))

    @property
    def tower(self) -> QuadTower:
        return self.sol.tower


@dataclass
class TripleVertices:
    circles: tuple[Circle, Circle, Circle]
    vertices: list[CircleVertex]
    gens: list  # (radicand, generator) of the base tower
    complete: bool
    notes: list[str]
    seconds: float


def _check_distinct(cs) -> None:
    for i in range(len(cs)):
        for j in range(i):
            if cs[i] == cs[j]:
                raise LocatorError(
                    f"C{j + 1} and C{i + 1} are the same circle: their bisector is the whole circle/plane, "
                    "no Voronoi vertex is defined")


def voronoi_vertices_circles(c1, c2, c3) -> TripleVertices:
    """All true Voronoi vertices of three circles, exactly (thesis §3.1.3); cached per triple.

    Raises LocatorError for coincident circles or when the equidistant set is a continuum
    (e.g. three circles tangent at one common point with collinear centres).
    """
    cs = tuple(as_circle(c) for c in (c1, c2, c3))
    _check_distinct(cs)
    return _vertices_cached(cs)


@lru_cache(maxsize=4096)
def _vertices_cached(cs: tuple[Circle, Circle, Circle]) -> TripleVertices:
    t0 = time.perf_counter()
    F = _RadiusField()
    rho = [F.rho(c.r2) for c in cs]
    T = F.T
    centres = [(c.cx, c.cy) for c in cs]
    r2 = [c.r2 for c in cs]
    verts: list[CircleVertex] = []
    notes: list[str] = []
    for s in SIGN_SYSTEMS:
        res = solve_system(T, centres, rho, r2, s)
        for fam in res.families:
            if _family_has_vertices(T, fam, rho, s):
                raise LocatorError(
                    "degenerate configuration: a continuum of points is equidistant from C1, C2, C3 "
                    f"(positive-dimensional solution set of the Apollonius system with signs {s}); "
                    "the Voronoi diagram has no isolated vertex here")
        for sol in res.solutions:
            sol = normalise_den(sol)
            Tq = sol.tower
            sR = Tq.sign(sol.Rn)
            if sR == 0:
                continue
            ok = all(Tq.sign(Tq.add(Tq.mul(rho_i, sol.D), Tq.mul(fmpq(s_i), sol.Rn))) >= 0
                     for rho_i, s_i in zip(rho, s))
            if not ok:
                continue
            if sR < 0:
                sol = AlgebraicSolution(Tq, sol.X, sol.Y, Tq.neg(sol.Rn), sol.D)
            verts.append(CircleVertex(sol, tuple(sR * si for si in s)))
    if not verts:
        notes.append("no true Voronoi vertex (e.g. nested circles): the triple is not a Delaunay triangle; "
                     "the thesis (§3.1.3) excludes this case for triples of the Delaunay graph")
    verts.sort(key=lambda v: (v.x, v.y))
    return TripleVertices(cs, verts, F.gens, True, notes, time.perf_counter() - t0)


def _family_has_vertices(T: QuadTower, fam, rho, s) -> bool:
    """Does a positive-dimensional family of solutions of system (II) contain true vertices?

    Validity along the family: R ≠ 0 and ρ_i + s_i R ≥ 0.  With R free the feasible set is
    [max(-ρ_i : s_i=+1), min(ρ_i : s_i=-1)] minus {0}, infinite unless both ends are 0.
    With R fixed the family (q on a circle of positive radius) is infinite when R is valid.
    """
    if fam.R_fixed is None:
        lo_zero = any(si == 1 and T.sign(r) == 0 for r, si in zip(rho, s))
        hi_zero = any(si == -1 and T.sign(r) == 0 for r, si in zip(rho, s))
        return not (lo_zero and hi_zero)
    R = fam.R_fixed
    sR = T.sign(R.num) * T.sign(R.den)
    if sR == 0:
        return False
    sd = T.sign(R.den)
    return all(T.sign(T.add(T.mul(r, R.den), T.mul(fmpq(si), R.num))) * sd >= 0 for r, si in zip(rho, s))


# =====================================================================================
# Conflict with C4
# =====================================================================================


@dataclass
class ConflictDecision:
    in_conflict: bool
    tangent: bool
    sign_g: int
    sign_h: int | None
    sign_rho4_minus_radius: int
    distance_to_fourth: float


def decide_conflict(tv: TripleVertices, v: CircleVertex, c4: Circle) -> ConflictDecision:
    """Exact relation of C4 to the empty circle of vertex v (see module docstring)."""
    s = v.sol
    T, gens = s.tower, tv.gens
    T, rho4 = _rho_in(T, gens, c4.r2)
    DX = T.sub(s.X, T.mul(c4.cx, s.D))
    DY = T.sub(s.Y, T.mul(c4.cy, s.D))
    D2 = T.add(T.sqr(DX), T.sqr(DY))
    P = T.mul(rho4, s.D)
    g = T.sub(D2, T.sqr(T.add(P, s.Rn)))
    sg = T.sign(g)
    sdiff = T.sign(T.sub(P, s.Rn))
    sh = None
    if sg < 0 and sdiff < 0:
        in_conflict = True
        tangent = False
    else:
        h = T.sub(D2, T.sqr(T.sub(P, s.Rn)))
        sh = T.sign(h)
        in_conflict = sg < 0 and (sdiff < 0 or sh > 0)
        tangent = sg == 0 or (sdiff >= 0 and sh == 0)
    if tangent:
        dist = v.radius
    else:
        dist = _dist_float(T, D2, s.D, rho4)
    return ConflictDecision(in_conflict, tangent, sg, sh, sdiff, dist)


def _dist_float(T: QuadTower, D2: Elem, D: Elem, rho4: Elem) -> float:
    prec = 128
    while True:
        with ctx.workprec(prec):
            v = abs(T._arb(D2, prec).sqrt() / T._arb(D, prec) - T._arb(rho4, prec))
        if v.rel_accuracy_bits() >= 60 or prec >= 4096:
            return float(v.mid())
        prec *= 2


def locate_conflicts_circles(c1, c2, c3, c4, *, strict: bool = False) -> LocatorResult:
    """Exact conflict locator for four circles (thesis §3.1.3).

    Circles are :class:`Circle` objects or (cx, cy, radius) triples.  Every vertex is decided
    exactly (certified=True) and the vertex list is complete by construction (all solutions of
    the four Apollonius systems are enumerated).  A triple without true Voronoi vertex gives an
    empty list (complete=True); with ``strict=True`` it raises LocatorError instead, since the
    thesis says such a triple is not a Delaunay triangle.
    """
    t0 = time.perf_counter()
    tv = voronoi_vertices_circles(c1, c2, c3)
    C4 = as_circle(c4)
    t1 = time.perf_counter()
    if strict and not tv.vertices:
        raise LocatorError("C1, C2, C3 have no true Voronoi vertex (" + "; ".join(tv.notes) + ")")
    out = []
    for v in tv.vertices:
        dec = decide_conflict(tv, v, C4)
        out.append(VoronoiVertex(
            x=v.x, y=v.y, radius=v.radius, distance_to_fourth=dec.distance_to_fourth,
            in_conflict=dec.in_conflict, certified=True, tangent=dec.tangent,
            info={"proof": "exact signs in a quadratic tower", "pattern": list(v.pattern),
                  "tower_depth": v.tower.depth, "sign_g": dec.sign_g, "sign_h": dec.sign_h}))
    t2 = time.perf_counter()
    return LocatorResult(conflict=any(v.in_conflict for v in out), vertices=out, method="circles-exact",
                         timings={"vertices": t1 - t0, "vertices_uncached": tv.seconds, "conflict": t2 - t1},
                         complete=tv.complete, notes=list(tv.notes))
