"""Vertex proofs of the point/segment/arc certificate (step 2 of
:mod:`runtime.segments.certificate`), independent of the construction's vertex code.

A reported vertex v (sites s_0 … s_{k−1}, position, radius) is proved as follows.

* **Corner** (the closures of all listed sites share a point site) and **arc centre** (a listed
  arc whose centre is the reported position): decided exactly in rationals
  (:mod:`runtime.segments.certificate_corners`).
* **k = 3**: each listed site contributes a *touching-type* distance: |v − p| for a point, the
  signed distance σ·ℓ(v) to the line of a segment touched in its interior (σ: the side of the
  reported position), σ (|v − c| − ρ) for an arc touched in its interior (σ = +1 outside its
  circle, −1 inside), and for a curve s whose end e is also listed (or whose smooth-joint partner
  is listed, e the joint) the circle touches s at e, so v lies on the normal line of s at e: the
  equation t·(v − e) = 0, t the tangent of s at e (a circle through e tangent to s elsewhere would
  meet it twice); of the two curves of a joint one carries the distance |v − e|, the other the
  normal line.  The k − 1 = 2 equations (normal lines, and d_{D0} − d_{Dj} over the
  distance-carrying sites) in (x, y) are solved by float Newton from the reported position and
  proved by Krawczyk (:func:`runtime.certify.interval_newton.krawczyk_inflation`) at 128 bits: one
  zero in a small box K, r = d_{D0}(K).  It is a vertex of the sites when r > 0, the foot of every
  segment touched inside is in (0, 1), the direction from the centre of every arc touched inside is
  in its open range (then the circle's distance is the arc's), and v lies on the ray from an arc's
  centre through its end e when the arc is touched at e ((e − c)·(v − c) > 0).
* **k > 3**: three sites whose equations (|v − p|² = r², a x + b y + c = σ r √(a² + b²),
  |v − c|² = (ρ + σ r)², the normal lines) have a regular Jacobian at the report are solved in
  closed form by sympy; the solution near the report is enclosed in arb from its radicals, and
  every other listed site's equation is proved to vanish exactly
  (:mod:`runtime.segments.certificate_exact`); the same contact conditions follow.
* The reported position and radius are within :data:`VERTEX_TOL`·(1 + |x| + |y| + r) of the proved
  ones, the contacts turn counter-clockwise in the listed order and the circle is empty
  (:mod:`runtime.segments.certificate_contacts`).  When the box of k = 3 leaves a site's
  emptiness undecided (a tie the floats break by 10⁻¹⁷, mirror images in a regular star), the same
  zero is enclosed again at :data:`TIGHT_PREC` bits (Krawczyk, its box inside the first one, which
  holds one zero only) and the emptiness decided on that box.

* **Elliptic pieces** (:mod:`runtime.segments.certificate_ellipses`): touched inside, the
  touching-type distance |v − e(φ(v))| with the foot φ(v) enclosed by a parametric Krawczyk test
  inside the piece's open parameter range (also beyond the centre of curvature at a listed end,
  the end then tied); touched at an end, the normal line; the contact proved the piece's nearest
  point.  Corners and vertices of more than three sites with an elliptic piece are not proved (no
  exact decision for elliptic pieces).

Public API: :class:`VertexProof`, :func:`prove_vertices`, :data:`VERTEX_TOL`.

Length: one proof (the touching-type terms, their system, its Krawczyk test and the contact
conditions read the same term tuples); splitting it would pass them between modules.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from flint import arb, arb_mat, fmpq

from ..certify.foot import working_prec
from ..certify.interval_newton import KrawczykFailure, krawczyk_inflation
from ..voronoi.verify.problems import Problem, fault
from .certificate_contacts import ccw, empty
from .certificate_corners import prove_arc_centre, prove_corner
from .certificate_exact import exact_vertex
from .certificate_ellipses import (end_contact_valid, interior_contact_valid, normal_residual,
                                   past_centre_of_curvature, term_grad, term_value, touches_inside)
from .certificate_sites import ARC, ELLIPSE, POINT, SEGMENT, SiteTable, hypot

__all__ = ["VertexProof", "prove_vertices", "VERTEX_TOL"]

#: reported vertex positions and radii must be this close (relative) to the proved ones
VERTEX_TOL = 1e-10
#: the vertex equations of a tie at an elliptic piece the proof does not handle (not a fault)
LIMIT = "limit"
#: the start of a contact message that is a limit of the proof (undecided), not a fault
UNDECIDED = "not proved (undecided): "
#: bits of the second enclosure of a vertex whose emptiness the first leaves undecided
TIGHT_PREC = 384


@dataclass
class VertexProof:
    """``ok``: the vertex is proved; ``x``, ``y``, ``r``: arb enclosures of the exact vertex;
    ``corner``: the point site at a radius-0 vertex; ``listed``: its sites; ``centre_of``: the arc
    whose centre it is."""

    ok: bool
    x: arb | None = None
    y: arb | None = None
    r: arb | None = None
    corner: int | None = None
    listed: frozenset = frozenset()
    centre_of: int | None = None


def prove_vertices(D, T: SiteTable, problems: list) -> list[VertexProof]:
    out = []
    for v in D.vertices:
        try:
            out.append(_prove(T, v, problems))
        except (ValueError, ZeroDivisionError, ArithmeticError) as exc:      # pragma: no cover - defensive
            problems.append(Problem(f"vertex {v.id}: not proved ({exc.__class__.__name__}: {exc})", kind="vertex",
                                    vertex=v.id, sites=_valid(T, v.sites), fault=False))
            out.append(VertexProof(False))
    return out


def _valid(T, sites):
    return tuple(int(s) for s in sites if 0 <= int(s) < T.n)


def _name(v) -> str:
    return f"vertex {v.id} (sites {', '.join(map(str, v.sites))})"


def _tol(v) -> float:
    return VERTEX_TOL * (1 + abs(float(v.x)) + abs(float(v.y)) + abs(float(v.radius)))


def _prove(T: SiteTable, v, problems) -> VertexProof:
    sites = tuple(int(s) for s in v.sites)
    k = len(sites)
    name = _name(v)
    if k < 3 or len(set(sites)) != k or not all(0 <= s < T.n for s in sites):
        problems.append(fault(f"{name}: a vertex needs 3 or more distinct valid sites", kind="vertex",
                              vertex=v.id, sites=_valid(T, sites)))
        return VertexProof(False)
    if not all(math.isfinite(float(t)) for t in (v.x, v.y, v.radius)):
        return VertexProof(False)
    if any(T.kind[s] is None or (T.is_curve(s) and T.ends[s] is None) for s in sites):
        return VertexProof(False)
    elliptic = [s for s in sites if T.kind[s] == ELLIPSE]
    common = None
    for s in sites:
        pts = {s} if T.kind[s] == POINT else {e for e in T.ends[s] if e >= 0}
        common = pts if common is None else common & pts
    if elliptic and (common or k > 3):
        problems.append(Problem(f"{name}: a corner or a vertex of more than three sites with an elliptic piece "
                                "(no exact decision for elliptic pieces): not proved", kind="vertex", vertex=v.id,
                                sites=sites, fault=False))
        return VertexProof(False)
    if common:
        return prove_corner(T, v, sites, next(iter(common)), problems, _tol(v), name, VertexProof)
    scale = 1.0 + abs(float(v.x)) + abs(float(v.y)) + abs(float(v.radius))
    for s in sites:
        if T.kind[s] == ARC:
            c = T.C[s]
            if abs(float(v.x) - c[0]) + abs(float(v.y) - c[1]) <= 1e-6 * scale and not elliptic:
                pr = prove_arc_centre(T, v, sites, s, problems, _tol(v), name, VertexProof)
                if pr.ok:
                    pr.centre_of = s
                return pr
    return _general(T, v, sites, problems)


# ------------------------------------------------------------------------------------ terms
def _terms(T: SiteTable, sites, xr, yr, rr=0.0):
    """Per listed site: ("pt", px, py, joint) | ("ln", nx, ny, c, σ) | ("arc", cx, cy, ρ, σ) |
    ("pp", tx, ty, ex, ey, e, s) with exact Fractions (joint: (code, curve) when the point is a
    smooth joint carrying curve's distance); None when a curve lists both its ends or a side is
    undecided."""
    listed = set(sites)
    partner: dict = {}
    for s in sites:
        if T.is_curve(s):
            for code in T.ends[s]:
                if code <= -2 and any(o in listed and o != s for o in T.joint_curves(code)):
                    partner.setdefault(s, []).append(code)
            if len(partner.get(s, ())) == 2 and len({o for c_ in partner[s] for o in T.joint_curves(c_)}) == 2:
                # two curves joined at both ends (a closed pair): the joint nearer the report
                partner[s] = [min(partner[s], key=lambda c_: (float(T.pt(c_)[0]) - xr) ** 2 +
                                  (float(T.pt(c_)[1]) - yr) ** 2)]
    out = []
    for s in sites:
        if T.kind[s] == POINT:
            out.append(("pt",) + T.a[s] + (None,))
            continue
        ends = [e for e in T.ends[s] if e >= 0 and e in listed] + partner.get(s, [])
        if T.kind[s] == ELLIPSE:
            # a joint of two elliptic pieces beyond its centre of curvature is no contact (mirror
            # feet inside both); a listed end and yet a contact inside: the end ties
            ends = [e for e in ends if not (e <= -2 and _past_joint(T, e, xr, yr))]
            if not ends or touches_inside(T.piece[s], xr, yr, rr):
                if any(e <= -2 for e in ends):
                    return LIMIT
                out.append(("el", T.piece[s], tuple(T.which_end(s, e) for e in ends)))
                continue
            if len(ends) == 2:
                # a short piece touched at one end (on its normal line), its other end tied
                ends.sort(key=lambda e: normal_residual(T.piece[s], T.which_end(s, e), xr, yr))
                if ends[1] <= -2:
                    return LIMIT
        tie = (T.which_end(s, ends[1]),) if T.kind[s] == ELLIPSE and len(ends) == 2 else ()
        if len(ends) == 2 and not tie:
            return None
        if ends:
            e = ends[0]
            if e <= -2 and s == min(T.joint_curves(e)):
                out.append(("pt",) + T.pt(e) + ((e, s), tie))
            else:
                t = T.leaving(s, e)
                out.append(("pp", t[0], t[1]) + T.pt(e) + (e, s, tie))
            continue
        if T.kind[s] == ELLIPSE:
            out.append(("el", T.piece[s], ()))
            continue
        if T.kind[s] == SEGMENT:
            (ax, ay), (bx, by) = T.a[s], T.b[s]
            nx, ny = -(by - ay), bx - ax
            c = -(nx * ax + ny * ay)
            side = float(nx) * xr + float(ny) * yr + float(c)
            if side == 0:
                return None
            out.append(("ln", nx, ny, c, 1 if side > 0 else -1))
        else:
            (cx, cy), rho = T.cen[s], T.rad[s]
            d = math.hypot(xr - float(cx), yr - float(cy)) - float(rho)
            if d == 0:
                return None
            out.append(("arc", cx, cy, rho, 1 if d > 0 else -1))
    return out


def _past_joint(T: SiteTable, e: int, xr: float, yr: float) -> bool:
    """Joint e joins two elliptic pieces and (xr, yr) lies beyond its centre of curvature (floats,
    decided once for both pieces by the first: it only chooses the equations)."""
    curves = T.joint_curves(e)
    if any(T.kind[o] != ELLIPSE for o in curves):
        return False
    s = min(curves)
    return past_centre_of_curvature(T.piece[s], T.which_end(s, e), xr, yr)


def _value(term, x, y, num):
    """The touching-type distance (or the normal line's residual) at (x, y); ``num`` converts
    exact coefficients (float or arb)."""
    fl = num is float
    if term[0] == "el":
        return term_value(term[1], x, y, fl)
    if term[0] == "pt":
        return math.hypot(x - num(term[1]), y - num(term[2])) if fl else hypot(x - num(term[1]), y - num(term[2]))
    if term[0] == "ln":
        nx, ny, c, sg = num(term[1]), num(term[2]), num(term[3]), term[4]
        nn = (nx * nx + ny * ny) ** 0.5 if fl else (nx * nx + ny * ny).sqrt()
        return sg * (nx * x + ny * y + c) / nn
    if term[0] == "arc":
        dx, dy = x - num(term[1]), y - num(term[2])
        d = math.hypot(dx, dy) if fl else hypot(dx, dy)
        return term[4] * (d - num(term[3]))
    return num(term[1]) * (x - num(term[3])) + num(term[2]) * (y - num(term[4]))


def _grad(term, x, y, num):
    fl = num is float
    if term[0] == "el":
        return term_grad(term[1], x, y, fl)
    if term[0] in ("pt", "arc"):
        dx, dy = x - num(term[1]), y - num(term[2])
        d = math.hypot(dx, dy) if fl else hypot(dx, dy)
        sg = term[4] if term[0] == "arc" else 1
        return sg * dx / d, sg * dy / d
    if term[0] == "ln":
        nx, ny, sg = num(term[1]), num(term[2]), term[4]
        nn = (nx * nx + ny * ny) ** 0.5 if fl else (nx * nx + ny * ny).sqrt()
        return sg * nx / nn, sg * ny / nn
    return num(term[1]), num(term[2])


def _arbq(q):
    return arb(fmpq(q.numerator, q.denominator))


#: the exact (Fraction) fields of each kind of term
_NUMERIC = {"pt": (1, 2), "ln": (1, 2, 3), "arc": (1, 2, 3), "pp": (1, 2, 3, 4)}


def _same(v):
    return v


def _converted(terms, num):
    """The terms with their exact coefficients converted once by ``num`` (float, or arb at the
    working precision): :func:`_system` on them with ``num`` = float or :func:`_same` evaluates the
    same expressions on the same converted values as on the exact terms, without converting the
    coefficients at every evaluation."""
    out = []
    for t in terms:
        idx = _NUMERIC.get(t[0], ())
        out.append(tuple(num(v) if m in idx else v for m, v in enumerate(t)))
    return out


def _system(terms, num):
    """F, J of the k − 1 equations: normal lines, then d_{D0} − d_{Dj}."""
    perps = [t for t in terms if t[0] == "pp"]
    dist = [t for t in terms if t[0] != "pp"]

    def F(z):
        x, y = z
        out = [_value(t, x, y, num) for t in perps]
        d0 = _value(dist[0], x, y, num)
        return out + [d0 - _value(t, x, y, num) for t in dist[1:]]

    def J(z):
        x, y = z
        rows = [list(_grad(t, x, y, num)) for t in perps]
        g0 = _grad(dist[0], x, y, num)
        for t in dist[1:]:
            g = _grad(t, x, y, num)
            rows.append([g0[0] - g[0], g0[1] - g[1]])
        return rows
    return F, J, dist[0]


# ------------------------------------------------------------------------------------ general
def _general(T: SiteTable, v, sites, problems) -> VertexProof:
    name = _name(v)
    xr, yr = float(v.x), float(v.y)
    terms = _terms(T, sites, xr, yr, float(v.radius))
    if terms is LIMIT:
        problems.append(Problem(f"{name}: an elliptic piece touched at a joint and elsewhere too (a tie the "
                                "certificate does not handle): not proved", kind="vertex", vertex=v.id, sites=sites,
                                fault=False))
        return VertexProof(False)
    if terms is None or not any(t[0] != "pp" for t in terms):
        problems.append(fault(f"{name}: no circle of positive radius touches these sites there (a curve and "
                              "both its ends, or a site through the reported centre)", kind="vertex",
                              vertex=v.id, sites=sites))
        return VertexProof(False)
    if len(sites) == 3:
        box = _krawczyk(terms, xr, yr)
        if box is None:
            problems.append(Problem(f"{name}: no proved equidistant point near the reported position (Krawczyk "
                                    "failed)", kind="vertex", vertex=v.id, sites=sites))
            return VertexProof(False)
        X, Y = box
        F, J, d0 = _system(terms, _arbq)
        R = _value(d0, X, Y, _arbq)
    else:
        sol = exact_vertex(terms, v, sites, _tol(v))
        if isinstance(sol, str):
            problems.append(Problem(f"{name}: {sol}", kind="vertex", vertex=v.id, sites=sites,
                                    fault=sol.startswith("site")))
            return VertexProof(False)
        X, Y, R = sol
    if not R > 0:
        problems.append(fault(f"{name}: the equidistant point has no positive radius", kind="vertex", vertex=v.id,
                              sites=sites))
        return VertexProof(False)
    msg = _contacts_valid(T, sites, terms, X, Y, R)
    if msg is not None:
        problems.append(Problem(f"{name}: {msg}", kind="vertex", vertex=v.id, sites=sites,
                                fault=not msg.startswith(UNDECIDED)))
        return VertexProof(False)
    tol = _tol(v)
    if not ((X - xr).abs_upper() <= tol and (Y - yr).abs_upper() <= tol and (R - float(v.radius)).abs_upper() <= tol):
        problems.append(fault(f"{name}: the proved vertex is at ({float(X.mid())!r}, {float(Y.mid())!r}) radius "
                              f"{float(R.mid())!r}, reported at ({xr!r}, {yr!r}) radius {float(v.radius)!r}",
                              kind="vertex", vertex=v.id, sites=sites))
        return VertexProof(False)
    if not ccw(T, sites, terms, X, Y):
        problems.append(fault(f"{name}: the sites are not listed counter-clockwise by their contact points",
                              kind="vertex", vertex=v.id, sites=sites))
        return VertexProof(False)
    found: list = []
    ok = empty(T, v, sites, X, Y, R, found, name)
    if not ok and len(sites) == 3:
        # a site within the box's width of the circle (mirror images that floats leave nearly
        # tied): the same zero enclosed at TIGHT_PREC bits decides it unless the tie is exact
        tight = _tighten(terms, X, Y)
        if tight is not None:
            again: list = []
            with working_prec(TIGHT_PREC):
                X2, Y2 = tight
                R2 = _value(_system(terms, _arbq)[2], X2, Y2, _arbq)
                ok = bool(R2 > 0) and empty(T, v, sites, X2, Y2, R2, again, name)
            if ok:
                X, Y, R = X2, Y2, R2
            found = again
    problems.extend(found)
    if not ok:
        return VertexProof(False)
    return VertexProof(True, X, Y, R, None, frozenset(sites))


def _tighten(terms, X, Y):
    """The zero of the vertex system in the proved box (X, Y), enclosed again at
    :data:`TIGHT_PREC` bits (float-start Newton steps with balls, then Krawczyk with a floor of
    2^(40 − TIGHT_PREC) of the scale); None unless the new box lies inside (X, Y), which holds one
    zero only, so that both enclose the same zero."""
    scale = 1 + max(abs(float(X.mid())), abs(float(Y.mid())))
    with working_prec(TIGHT_PREC):
        Fa, Ja, _ = _system(terms, _arbq)
        m = [arb(X.mid()), arb(Y.mid())]
        try:
            for _ in range(6):
                Yi = arb_mat(Ja(m)).mid().inv().mid()
                step = Yi * arb_mat([[v] for v in Fa(m)])
                m = [(m[i] - step[i, 0]).mid() for i in range(2)]
            K, _X = krawczyk_inflation(Fa, Ja, m, floor=arb(scale) * arb(2) ** (40 - TIGHT_PREC))
        except (KrawczykFailure, ZeroDivisionError, ValueError):
            return None
        if not (X.contains(K[0]) and Y.contains(K[1])):
            return None
        return K[0], K[1]


def _contacts_valid(T: SiteTable, sites, terms, X, Y, R):
    """None when every contact is where its equation says (module docstring), else a message."""
    for s, t in zip(sites, terms):
        if t[0] == "el":
            ok = interior_contact_valid(t[1], X, Y, R, t[2])
            if ok is not True:
                return _undecided(ok) + f"the circle's contact with elliptic piece {s} is not its nearest point inside it"
        if T.kind[s] == ELLIPSE and (t[0] == "pp" or (t[0] == "pt" and t[3] is not None)):
            e, tie = (t[5], t[7]) if t[0] == "pp" else (t[3][0], t[4])
            ok = end_contact_valid(T.piece[s], T.which_end(s, e), X, Y, R, tie)
            if ok is not True:
                return _undecided(ok) + f"the end {e} of elliptic piece {s} is not its nearest point"
        if t[0] == "pt" and t[3] is not None:
            other = [o for o in T.joint_curves(t[3][0]) if o != s][0]
            if T.kind[other] == ELLIPSE:
                ok = end_contact_valid(T.piece[other], T.which_end(other, t[3][0]), X, Y, R)
                if ok is not True:
                    return _undecided(ok) + f"the joint {t[3][0]} of elliptic piece {other} is not its nearest point"
        if t[0] == "ln":
            u = T.foot(s, X, Y)
            if not (u > 0 and u < 1):
                what = "outside" if (u < 0 or u > 1) else "at an end of"
                return f"the circle touches the line of segment {s} {what} the segment"
        elif t[0] == "arc":
            cx, cy, rho = T.arb_arc(s)
            inr = T.in_range(s, X - cx, Y - cy)
            if inr is not True or not (rho + t[4] * R > 0):
                what = "outside" if inr is False else "at an end of"
                return f"the circle touches the circle of arc {s} {what} the arc"
        if T.kind[s] == ARC and (t[0] == "pp" or (t[0] == "pt" and t[3] is not None)):
            e = t[5] if t[0] == "pp" else t[3][0]
            cx, cy, _ = T.arb_arc(s)
            ex, ey = T.pt_arb(e)
            if not ((ex - cx) * (X - cx) + (ey - cy) * (Y - cy) > 0):
                return f"the vertex is not on the ray from the centre of arc {s} through its end {e}"
        if t[0] == "pt" and t[3] is not None:
            other = [o for o in T.joint_curves(t[3][0]) if o != s][0]
            if T.kind[other] == ARC:
                cx, cy, _ = T.arb_arc(other)
                ex, ey = T.pt_arb(t[3][0])
                if not ((ex - cx) * (X - cx) + (ey - cy) * (Y - cy) > 0):
                    return f"the vertex is not on the ray from the centre of arc {other} through its joint"
    return None


def _undecided(verdict) -> str:
    return UNDECIDED if verdict is None else ""


def _narrow(Fa, Ja, K, scale: float):
    """A proved box K of a far vertex (an ill-conditioned system: the float start is off along
    its bisector) can be wider than the reported position's tolerance although that position is
    right: from K's midpoint, Newton steps with balls at the working precision (a numerical start
    only) and a new Krawczyk test, whose box — proved on its own — is kept when it succeeds."""
    if max(float(K[0].rad()), float(K[1].rad())) <= VERTEX_TOL * (1 + scale) / 64:
        return K[0], K[1]
    m = [K[0].mid(), K[1].mid()]
    try:
        for _ in range(3):
            Y = arb_mat(Ja(m)).mid().inv().mid()
            step = Y * arb_mat([[v] for v in Fa(m)])
            m = [(m[i] - step[i, 0]).mid() for i in range(2)]
        K2, _X = krawczyk_inflation(Fa, Ja, m, floor=arb(1 + scale) * arb(2) ** -100)
        return K2[0], K2[1]
    except (KrawczykFailure, ZeroDivisionError, ValueError):
        return K[0], K[1]


def _solve2(J, f):
    """J⁻¹ f for a float 2 × 2 matrix (Gaussian elimination with partial pivoting, as LAPACK's
    dgesv); ZeroDivisionError when a pivot is 0 (a numerical step only: the proof follows)."""
    (a, b), (c, d) = J
    f0, f1 = f
    if abs(c) > abs(a):
        a, b, c, d, f0, f1 = c, d, a, b, f1, f0
    m = c / a
    u = d - m * b
    x1 = (f1 - m * f0) / u
    return (f0 - b * x1) / a, x1


def _float_newton(terms, xr, yr):
    """Float Newton steps from the reported position on the vertex system (a numerical start for
    Krawczyk's test, which alone proves anything); None when they fail."""
    Ff, Jf, _ = _system(_converted(terms, float), float)
    z0, z1 = xr, yr
    for _ in range(30):
        try:
            s0, s1 = _solve2(Jf((z0, z1)), Ff((z0, z1)))
        except (ValueError, ZeroDivisionError, OverflowError):
            return None
        z0, z1 = z0 - s0, z1 - s1
        if not (math.isfinite(z0) and math.isfinite(z1)):
            return None
        if max(abs(s0), abs(s1)) <= 1e-16 * (1 + max(abs(z0), abs(z1))):
            break
    return np.array([z0, z1])


def _krawczyk(terms, xr, yr):
    z = _float_newton(terms, xr, yr)
    if z is None:
        return None
    Fa, Ja, _ = _system(_converted(terms, _arbq), _same)
    # a floor of 2^-80 of the scale: a coordinate that is exact in floats (YF_i = 0) must not
    # start at a radius below the second-order coupling of the other one; an ill-conditioned
    # system (a far vertex sliding along its bisector) needs a wider first box
    m = [arb(float(z[0])), arb(float(z[1]))]
    for e in (80, 60, 44):
        try:
            floor = arb(1 + float(np.max(np.abs(z)))) * arb(2) ** -e
            K, _X = krawczyk_inflation(Fa, Ja, m, floor=floor)
            return _narrow(Fa, Ja, K, float(np.max(np.abs(z))))
        except (KrawczykFailure, ZeroDivisionError, ValueError):
            continue
    # three nearly collinear contacts (a vertex 10³ times farther than the sites' spread): the
    # float zero is off by more than any box the test accepts.  Newton steps with balls at the
    # working precision (midpoints only: a numerical start, proved by the test that follows)
    try:
        for _ in range(4):
            Y = arb_mat(Ja(m)).mid().inv().mid()
            step = Y * arb_mat([[v] for v in Fa(m)])
            m = [(m[i] - step[i, 0]).mid() for i in range(2)]
        floor = arb(1 + float(np.max(np.abs(z)))) * arb(2) ** -100
        K, _X = krawczyk_inflation(Fa, Ja, m, floor=floor)
        return K[0], K[1]
    except (KrawczykFailure, ZeroDivisionError, ValueError):
        return None
