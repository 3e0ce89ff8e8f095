"""Local Voronoi vertices of three sites: float refinement and certification (thesis §5.2, §6.1).

A Voronoi vertex of sites S1, S2, S3 is a point q with d(q, S1) = d(q, S2) = d(q, S3) = r whose
open disc B(q, r) meets none of them (thesis Def. 5.2.1).  The diagram builds vertices locally
(a seed on an edge, then Newton) and proves them here, one at a time; the full triple solve of
:mod:`runtime.predicates.locator` is not needed.  Sites may be any mix of points, circles and conics.

* :func:`refine_vertex`: damped Newton on (d1 − d2, d1 − d3) = 0 with the float distances of
  :class:`runtime.voronoi.geometry.SiteGeometry`; the gradient of d_i at q is the unit vector
  U_i from the foot point towards q.
* :func:`certify_vertex`: **existence and uniqueness** by Krawczyk's test (Moore 1977; thesis
  §3.3.3) in ball arithmetic, on

  - three circles/points: the 3×3 system |q − c_i|² = (ρ_i + s_i r)², s_i = ±1 the side of
    circle i where q lies (points: ρ_i = 0); with r > 0 and ρ_i + s_i r > 0 in the box it
    gives d(q, S_i) = | |q − c_i| − ρ_i | = r, so the vertex is a true one;
  - otherwise the 8×8 foot-point system of thesis §6.1 / App. D.1
    (:class:`runtime.certify.krawczyk.FootSystem`), whose point-site rows are p_i = c_i.

  **True-vertex property** for a conic site (the proved foot p_i is a closest point of S_i):
  with f_i the exact conic equation and μ = σ ∇f_i(p_i)·(p_i − q) / (2 r²), σ = ±1 the sign
  that makes μ > 0, the quadratic Φ(z) = −σ f_i(z) + μ (|z − q|² − r²) vanishes at p_i with
  zero gradient there (the foot-point equations), so Φ(z) = (z − p_i)ᵀ (μ I − σ A_i)(z − p_i)
  with A_i the matrix of the quadratic part of f_i.  If μ I − σ A_i ⪰ 0 (proved in balls by
  μ − σa > 0, μ − σc > 0 and det > 0), then for every z on the conic (f_i(z) = 0) we get
  μ (|z − q|² − r²) ≥ 0, i.e. |z − q| ≥ r: no point of S_i enters the open disc.  This is the
  tangency case of the S-lemma (Pólik & Terlaky, SIAM Rev. 49 (2007)); it fails only at
  degenerate vertices (q on the evolute of S_i, a double contact), which stay uncertified.
* :func:`certify_empty`: the other sites stay outside the open disc: rigorous
  ``distance_bounds`` at the centre of the vertex box minus its half diagonal (d is 1-Lipschitz)
  exceed the upper radius bound.

Length: refinement and proof of one vertex for every mix of site kinds (points, circles, conics),
one procedure with its proof argument above.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from fractions import Fraction
from functools import lru_cache

import numpy as np
import flint
from flint import arb, arb_mat

from ..certify.foot import normalised_coefficients, to_arb, working_prec
from ..certify.interval_newton import krawczyk_inflation
from ..certify.krawczyk import FootSystem, KrawczykFailure
from ..predicates.circles import Circle
from ..sites.conic import Conic
from ..sites.rationals import to_fraction
from .conic_geometry import site_geometry

__all__ = ["VertexProof", "refine_vertex", "certify_vertex", "certify_empty", "classify_others",
           "certify_vertices_circles", "SiteFootSystem"]


# =========================================================================== float refinement

def refine_vertex(geoms, x0: float, y0: float, iters: int = 30, tol: float = 1e-13):
    """Damped Newton for the point equidistant from three sites, from the seed (x0, y0).

    F(q) = (d1(q) − d2(q), d1(q) − d3(q)), J = [U1 − U2; U1 − U3] (U_i the unit vector from the
    foot point on S_i to q, the gradient of d_i where d_i is smooth).  Steps are halved until
    |F| decreases (at most 30 halvings).  Returns (x, y, r) when |F| ≤ tol·(1 + r + |q|)
    after a step below 1e-9 of the same scale, else None (no convergence: singular
    Jacobian, medial-axis crossings, seed too far)."""
    gs = list(geoms)
    if len(gs) != 3:
        raise ValueError("refine_vertex needs three site geometries")

    def evaluate(q):
        P = q.reshape(1, 2)
        d, U = [], []
        for g in gs:
            F, Ug = g.foot_points(P)
            d.append(math.hypot(q[0] - F[0, 0], q[1] - F[0, 1]))
            U.append(Ug[0])
        return np.array([d[0] - d[1], d[0] - d[2]]), d, np.array([U[0] - U[1], U[0] - U[2]])

    q = np.array([float(x0), float(y0)])
    F, d, J = evaluate(q)
    if not np.all(np.isfinite(F)):
        return None
    for _ in range(iters):
        try:
            step = np.linalg.solve(J, -F)
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(step)):
            return None
        nF = np.linalg.norm(F)
        scale = 1.0 + abs(d[0]) + abs(q[0]) + abs(q[1])
        if nF <= tol * scale and np.linalg.norm(step) <= 1e-9 * scale:
            return float(q[0]), float(q[1]), float(sum(d) / 3)      # converged already (a refined seed)
        lam = 1.0
        for _h in range(30):
            qn = q + lam * step
            Fn, dn, Jn = evaluate(qn)
            if np.all(np.isfinite(Fn)) and (np.linalg.norm(Fn) < nF or np.linalg.norm(Fn) == 0):
                break
            lam *= 0.5
        else:
            Fn = None
        scale = 1.0 + abs(d[0]) + abs(q[0]) + abs(q[1])
        if Fn is None:
            # no decrease: at float resolution already?
            if nF <= tol * scale:
                return float(q[0]), float(q[1]), float(sum(d) / 3)
            return None
        q, F, d, J = qn, Fn, dn, Jn
        if np.linalg.norm(F) <= tol * scale and np.linalg.norm(lam * step) <= 1e-9 * scale:
            return float(q[0]), float(q[1]), float(sum(d) / 3)
    return None


# =========================================================================== proofs

@dataclass
class VertexProof:
    """Outcome of :func:`certify_vertex`.

    ``certified`` is true only when a unique vertex of the three sites is proved in ``box`` and
    it is a true vertex (no point of the three sites in the open disc).  ``x``, ``y``,
    ``radius`` are floats near the proved vertex; ``box`` = ((xlo, xhi), (ylo, yhi)) and
    ``radius_bounds`` = (lo, hi) enclose the vertex and its radius (outward-rounded floats).
    """

    x: float
    y: float
    radius: float
    box: tuple | None
    radius_bounds: tuple | None
    certified: bool
    reason: str = ""
    method: str = ""
    time: float = 0.0
    info: dict = field(default_factory=dict, repr=False)


def _fl_lo(v: arb) -> float:
    return math.nextafter(float(v.lower()), -math.inf)


def _fl_hi(v: arb) -> float:
    return math.nextafter(float(v.upper()), math.inf)


def _site_record(site):
    """('point', px, py) | ('circle', cx, cy, r2) | ('conic', coeffs) with exact Fractions."""
    if isinstance(site, Circle):
        cx, cy, r2 = to_fraction(site.cx), to_fraction(site.cy), to_fraction(site.r2)
        if r2 == 0:
            return ("point", cx, cy)
        return ("circle", cx, cy, r2)
    if isinstance(site, Conic):
        if site.kind == "circle":
            c = Circle.from_coefficients(*site.coefficients)
            return ("circle", to_fraction(c.cx), to_fraction(c.cy), to_fraction(c.r2))
        return ("conic", tuple(site.coefficients))
    raise TypeError(f"not a site: {site!r} (expected a Point, a Circle or a Conic)")


@lru_cache(maxsize=4096)
def _coeffs(rec):
    if rec[0] == "conic":
        return normalised_coefficients(rec[1])
    _, cx, cy, r2 = rec
    return normalised_coefficients((Fraction(1), Fraction(0), Fraction(1), -2 * cx, -2 * cy,
                                    cx * cx + cy * cy - r2))


class SiteFootSystem(FootSystem):
    """The 8×8 foot-point system (thesis §6.1, App. D.1) where some sites are points: for a point
    site c_i the two rows are x_i − c_x = 0, y_i − c_y = 0 (its only foot point is itself)."""

    def __init__(self, records):
        self.records = list(records)
        co = [(_coeffs(r) if r[0] != "point" else (Fraction(1), Fraction(0), Fraction(1), 0, 0, -1))
              for r in self.records]
        super().__init__(co)
        self.points = {i: (r[1], r[2]) for i, r in enumerate(self.records) if r[0] == "point"}

    def _co(self):
        key = flint.ctx.prec
        cache = self.__dict__.setdefault("_co_cache", {})
        if key not in cache:
            cache[key] = super()._co()
        return cache[key]

    def residual(self, z):
        out = super().residual(z)
        for i, (px, py) in self.points.items():
            out[2 * i] = z[2 + 2 * i] - to_arb(px)
            out[2 * i + 1] = z[3 + 2 * i] - to_arb(py)
        return out

    def jacobian(self, z):
        J = super().jacobian(z)
        for i in self.points:
            for r in (2 * i, 2 * i + 1):
                for c in range(8):
                    J[r, c] = arb(0)
            J[2 * i, 2 + 2 * i] = arb(1)
            J[2 * i + 1, 3 + 2 * i] = arb(1)
        return J


@lru_cache(maxsize=1024)
def _foot_system(recs):
    return SiteFootSystem(recs)


def _touching_certificate(coeffs, q, p, R) -> bool | None:
    """True when the quadratic Φ of the module docstring proves that no point of the conic
    ``coeffs`` is at distance < r from any q in the box (p: the foot box, R = r² ball).
    False when the foot is provably not a closest point (μ I − σ A has a negative eigenvalue,
    strictly); None when undecided."""
    a, b, c, d, e, f = (to_arb(v) for v in coeffs)
    qx, qy = q
    px, py = p
    fx = 2 * a * px + b * py + d
    fy = b * px + 2 * c * py + e
    dot = fx * (px - qx) + fy * (py - qy)
    if dot > 0:
        sg = 1
    elif dot < 0:
        sg = -1
    else:
        return None
    if not (R > 0):
        return None
    mu = sg * dot / (2 * R)
    m11, m22, m12 = mu - sg * a, mu - sg * c, -sg * b / 2
    det = m11 * m22 - m12 * m12
    if m11 > 0 and m22 > 0 and det > 0:
        return True
    if det < 0 or m11 < 0 or m22 < 0:
        return False
    return None


def _sq(v: arb) -> arb:
    """v² for a ball (``arb ** 2`` is NaN for a ball containing 0)."""
    return v * v if not v.contains(0) else abs(v) * abs(v)


def _circles_krawczyk(recs, x, y, r):
    """3×3 Krawczyk on |q − c_i|² − (ρ_i + s_i r)² = 0 (unknowns x, y, r).  Returns (box, signs)
    or raises KrawczykFailure."""
    cs = []
    for rec in recs:
        if rec[0] == "point":
            cs.append((rec[1], rec[2], Fraction(0)))
        else:
            cs.append((rec[1], rec[2], rec[3]))
    signs = []
    for cx, cy, r2 in cs:
        dd = math.hypot(x - float(cx), y - float(cy))
        signs.append(1 if (r2 == 0 or dd >= math.sqrt(float(r2))) else -1)
    C = [(to_arb(cx), to_arb(cy), to_arb(r2).sqrt() if r2 != 0 else arb(0)) for cx, cy, r2 in cs]

    def F(z):
        X, Y, Rr = z
        return [_sq(X - cx) + _sq(Y - cy) - _sq(rho + s * Rr) for (cx, cy, rho), s in zip(C, signs)]

    def Jm(z):
        X, Y, Rr = z
        return arb_mat([[2 * (X - cx), 2 * (Y - cy), -2 * s * (rho + s * Rr)] for (cx, cy, rho), s in zip(C, signs)])

    m = [arb(x), arb(y), arb(r)]
    # a few Newton steps at the working precision
    for _ in range(4):
        try:
            st = Jm(m).solve(arb_mat([[v] for v in F(m)]))
        except ZeroDivisionError:
            raise KrawczykFailure("singular Jacobian") from None
        m = [(m[i] - st[i, 0]).mid() for i in range(3)]
    box, _X = krawczyk_inflation(F, lambda z: Jm(z).tolist(), m, attempts=6, floor_bits=20)
    rr = box[2]
    if not rr > 0:
        raise KrawczykFailure("radius not provably positive")
    for (cx, cy, rho), s in zip(C, signs):
        if not (rho + s * rr > 0):
            raise KrawczykFailure("side of a circle not decided")
    return box, signs


def certify_vertex(sites, geoms, x: float, y: float, *, feet=None, max_prec: int = 256,
                   move_tol: float = 1e-6) -> VertexProof:
    """Prove that a true Voronoi vertex of the three ``sites`` lies near (x, y) (see the module
    docstring for what is proved).  ``sites``: three Point / Circle / Conic objects; ``geoms``:
    their geometries (or None: built here).  ``feet``: optional float seeds of the three foot
    points (default: the closest points given by the geometries).  Never raises on a failed proof: returns
    ``certified=False`` with a reason.  A proof that lands farther than ``move_tol``·(1 + |q| + r)
    from (x, y) is rejected (the candidate was not that vertex)."""
    t0 = time.perf_counter()
    recs = [_site_record(s) for s in sites]
    if len(recs) != 3:
        raise ValueError("certify_vertex needs exactly three sites")
    if geoms is None:
        geoms = [site_geometry(s) for s in sites]
    x, y = float(x), float(y)
    P = np.array([[x, y]])
    feet_given = feet is not None
    if feet is None:
        feet = [g.foot_points(P)[0][0] for g in geoms]
    else:
        feet = [np.asarray(F, dtype=float) for F in feet]
    dists = [math.hypot(x - float(F[0]), y - float(F[1])) for F in feet]
    r0 = sum(dists) / 3

    def fail(reason, **kw):
        return VertexProof(x, y, r0, None, None, False, reason, kw.pop("method", ""),
                           time.perf_counter() - t0, kw)

    if not all(math.isfinite(v) for v in (x, y, r0)):
        return fail("non-finite candidate")
    circular = all(r[0] in ("point", "circle") for r in recs) and feet_given is False
    reason = ""
    prec = 64
    while prec <= max_prec:
        with working_prec(prec):
            try:
                if circular:
                    box, _signs = _circles_krawczyk(recs, x, y, r0)
                    qx, qy, rb = box
                    method = "krawczyk-circles"
                else:
                    proof = _conic_proof(recs, feet, x, y)
                    if isinstance(proof, str):
                        return fail(proof, method="krawczyk-feet")
                    qx, qy, rb = proof
                    method = "krawczyk-feet"
            except KrawczykFailure as exc:
                reason = f"{prec} bits: {exc}"
                prec *= 2
                continue
            xm, ym, rm = float(qx.mid()), float(qy.mid()), float(rb.mid())
            scale = 1.0 + abs(xm) + abs(ym) + abs(rm)
            if math.hypot(xm - x, ym - y) > move_tol * scale:
                return fail(f"the proved vertex ({xm:.17g}, {ym:.17g}) is not the candidate", method=method)
            return VertexProof(xm, ym, rm, ((_fl_lo(qx), _fl_hi(qx)), (_fl_lo(qy), _fl_hi(qy))),
                               (max(_fl_lo(rb), 0.0), _fl_hi(rb)), True, "", method,
                               time.perf_counter() - t0, {"prec": prec})
    return fail(reason or "no proof")


def _conic_proof(recs, feet, x, y):
    """Krawczyk on the foot system from the float feet, then the touching certificate per conic
    site.  Returns (qx, qy, r) balls, or a reason string when the vertex is proved not to be a
    true one."""
    z = [arb(x), arb(y)]
    for F in feet:
        z += [arb(float(F[0])), arb(float(F[1]))]
    system = _foot_system(tuple(recs))
    z = system.newton(z, flint.ctx.prec, iters=6)
    box = system.krawczyk(z)
    qx, qy = box[0], box[1]
    R = None
    for i in range(3):
        Ri = _sq(qx - box[2 + 2 * i]) + _sq(qy - box[3 + 2 * i])
        R = Ri if R is None else R.intersection(Ri)
    for i, rec in enumerate(recs):
        if rec[0] == "point":
            continue
        ok = _touching_certificate(_coeffs(rec), (qx, qy), (box[2 + 2 * i], box[3 + 2 * i]), R)
        if ok is None:
            raise KrawczykFailure(f"site {i}: closest-point property undecided")
        if ok is False:
            return f"site {i} has a point strictly inside the circle: not a true vertex"
    if not R > 0:
        raise KrawczykFailure("radius not provably positive")
    return qx, qy, R.sqrt()


# =========================================================================== other sites

def classify_others(geoms_others, box, radius_bounds) -> np.ndarray:
    """For each geometry: +1 if the site provably stays outside the open disc of every centre in
    ``box`` with any radius in ``radius_bounds`` (d ≥ r: no conflict), −1 if it provably enters
    (d < r), 0 if undecided.  Uses ``distance_bounds`` at the box centre, widened by the half
    diagonal h (each d is 1-Lipschitz)."""
    (xlo, xhi), (ylo, yhi) = box
    rlo, rhi = radius_bounds
    cx, cy = 0.5 * (xlo + xhi), 0.5 * (ylo + yhi)
    h = math.hypot(xhi - xlo, yhi - ylo) * 0.5 * (1 + 1e-15) + 5e-324
    h = max(h, math.hypot(xhi - cx, yhi - cy), math.hypot(cx - xlo, cy - ylo))
    P = np.array([[cx, cy]])
    out = np.zeros(len(geoms_others), dtype=int)
    for k, g in enumerate(geoms_others):
        lo, hi = g.distance_bounds(P)
        if lo[0] - h >= rhi * (1 + 4e-16):
            out[k] = 1
        elif hi[0] + h < rlo * (1 - 4e-16):
            out[k] = -1
    return out


def certify_empty(geoms_others, x, y=None, radius_bounds=None):
    """Prove that no other site enters the open disc of a certified vertex.

    Call as ``certify_empty(geoms, proof)`` with a :class:`VertexProof`, or
    ``certify_empty(geoms, box, None, radius_bounds)`` / ``certify_empty(geoms, x, y, radius_bounds)``
    (a point: the box is degenerate).  Returns (all_outside, undecided) where ``undecided`` lists
    the indices (into ``geoms_others``) not proved outside (including any proved inside)."""
    if isinstance(x, VertexProof):
        box, rb = x.box, x.radius_bounds
    elif y is None:
        box, rb = x, radius_bounds
    else:
        box, rb = ((float(x), float(x)), (float(y), float(y))), radius_bounds
    if box is None or rb is None:
        return False, list(range(len(geoms_others)))
    cls = classify_others(geoms_others, box, rb)
    bad = [int(i) for i in np.nonzero(cls != 1)[0]]
    return (not bad), bad


# =========================================================================== batch (circles)

def certify_vertices_circles(triples, candidates):
    """Certify many vertices of circle/point triples: ``triples`` a list of three-site lists,
    ``candidates`` an (n, 2) array of float seeds.  Returns a list of VertexProof."""
    return [certify_vertex(t, None, float(c[0]), float(c[1])) for t, c in zip(triples, candidates)]
