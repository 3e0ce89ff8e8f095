"""Directions at infinity owned by unbounded sites (parabolas, hyperbolas): the accounting of ends.

**Asymptotic functions.**  For a closed set S, d(t·u, S)/t → c_S(u) = dist(u, S^∞) uniformly in
u as t → ∞, S^∞ the horizon (asymptotic) cone of S (Rockafellar & Wets, *Variational Analysis*,
§3.B and Thm. 4.10: S/t → S^∞ in the Painlevé–Kuratowski sense, and 1-Lipschitz distance
functions then converge locally uniformly).  A bounded site has S^∞ = {0}, c ≡ 1; a parabola
the ray of its axis; a hyperbola its four asymptote rays (the curve, not its convex sides): c(θ)
= sin(min(π/2, angular distance from θ to the rays)) (:func:`c_range`, an enclosure on a cell
of directions: the angular distance is 1-Lipschitz and sin increases on [0, π/2]).

**Accounting** (:func:`accounting_unbounded`, replacing support functions, which do not exist for
unbounded sites, in :func:`runtime.voronoi.verify.closure.verify_accounting_conics`).  Along an
unbounded edge of the diagram with sites i', j', at every accumulation direction θ' of q/|q|,
d_i' = d_j' ≤ d_k divided by t gives c_i'(θ') = c_j'(θ') = min_k c_k(θ'); these directions form a
connected set A (a decreasing intersection of connected compact sets).  Each proved tail (pair
i, j, :func:`runtime.voronoi.verify.conic_tail.prove_conic_tail`) comes with an interval J of
directions inside the open sector where β_ij is its tail, on which only i and j can attain
min_k c_k (:func:`lead_interval`).  Here the intervals J of one pair are proved disjoint, and on
every closed arc that no J covers one site strictly minimises c_k.  Then A lies in the intervals
J of the pair {i', j'}, so in one of them (connected), so the edge eventually runs in that
sector, where β_i'j' is the proved tail: every unbounded edge of the diagram is a proved one.
(b) No component without points at infinity (thesis Prop. 1.2.1): the bounded sites as in
:func:`runtime.voronoi.verify.hull_nesting.hulls_disjoint`; each bounded site's disc and each
unbounded site's convex side (each branch of a hyperbola) strictly separated by a tangent
half-plane (:func:`runtime.voronoi.verify.far_conics.FarConic.lower` at the disc's centre above
its radius); two unbounded convex sides by a direction v with h_A(v) + h_B(−v) < 0, h the
support function of a parabola's convex side, v·vertex + p·v₂²/(2|v₁|) for v₁ < 0 (canonical
components), or of a hyperbola branch, v·centre − √(a²v₁² − b²v₂²) for ∓v₁ > 0, a|v₁| > b|v₂|.

Public API: :func:`c_range`, :func:`lead_interval`, :func:`asymptotic_direction`,
:func:`accounting_unbounded`, :func:`far_centre`.
"""
from __future__ import annotations

import math

import numpy as np

from ...certify.cell_cover import CellTest, walk_cells
from .far_conics import UNBOUNDED, FarConic
from .hull_nesting import gap_note, hulls_disjoint
from .problems import fault

__all__ = ["c_range", "c_float", "lead_interval", "asymptotic_direction", "accounting_unbounded", "far_centre"]

TWO_PI = 2.0 * math.pi


def far_centre(geoms):
    """A centre for the far field: the middle of the unbounded sites' vertices / centres (of every
    site's box when there is no unbounded site); any fixed point serves the proofs."""
    pts = []
    for g in geoms:
        if g.kind in UNBOUNDED:
            fr = g.exact.frame
            pts.append((float(fr.tx), float(fr.ty), float(fr.tx), float(fr.ty)))
    if not pts:
        pts = [tuple(g.bounding_box()) for g in geoms]
    b = np.array(pts, float)
    return 0.5 * (b[:, :2].min(0) + b[:, 2:].max(0))


def _rays(fars, k):
    return None if fars.get(k) is None else np.array(fars[k].rays(), float)


def _ang_dist(th, rays):
    """Angular distance (in [0, π]) from the angles th to the nearest of the rays."""
    d = np.abs((np.asarray(th, float)[..., None] - rays + math.pi) % TWO_PI - math.pi)
    return d.min(-1)


def c_float(fars, k, th):
    """Float c_k(θ) (module docstring)."""
    rays = _rays(fars, k)
    th = np.asarray(th, float)
    if rays is None:
        return np.ones_like(th)
    return np.sin(np.minimum(_ang_dist(th, rays), 0.5 * math.pi))


def c_range(fars, k, thc, half):
    """Enclosure (lo, hi) of c_k on [θc − half, θc + half]."""
    rays = _rays(fars, k)
    thc = np.asarray(thc, float)
    if rays is None:
        return np.ones_like(thc), np.ones_like(thc)
    d = _ang_dist(thc, rays)
    pad = 1e-12 + 1e-15 * np.abs(thc)
    dlo = np.clip(d - half - pad, 0.0, 0.5 * math.pi)
    dhi = np.clip(d + half + pad, 0.0, 0.5 * math.pi)
    return np.sin(dlo) * (1 - 1e-15) - 1e-16, np.sin(dhi) * (1 + 1e-15) + 1e-16


def asymptotic_direction(fars, n, i, j, thX):
    """A float zero of c_i − c_j where i, j attain min_k c_k (float), nearest to thX, or None."""
    oth = [k for k in range(n) if k not in (i, j)]
    grid = thX + np.linspace(-math.pi, math.pi, 8193)
    g = c_float(fars, i, grid) - c_float(fars, j, grid)
    top = np.minimum(c_float(fars, i, grid), c_float(fars, j, grid))
    if oth:
        low = np.min([c_float(fars, k, grid) for k in oth if fars.get(k) is not None] + [np.ones_like(grid)], 0)
    else:
        low = np.full_like(grid, np.inf)
    ch = np.nonzero((np.sign(g[:-1]) != np.sign(g[1:])) & (top[:-1] < low[:-1]) & (top[1:] < low[1:]))[0]
    if not len(ch):
        return None
    c0 = int(ch[np.argmin(np.abs(grid[ch] - thX))])
    a_, b_ = grid[c0], grid[c0 + 1]
    ga = g[c0]
    for _ in range(60):
        mid = 0.5 * (a_ + b_)
        gm = float(c_float(fars, i, mid) - c_float(fars, j, mid))
        a_, b_, ga = (mid, b_, gm) if np.sign(gm) == np.sign(ga) else (a_, mid, ga)
    return 0.5 * (a_ + b_)


def _min_strict(fars, n, s, g0, g1, max_work, allowed=()):
    """Is c_s < c_k on [g0, g1] for every k ≠ s outside ``allowed`` (cells halved until decided)?
    With ``allowed`` = (i, j): is min(c_i, c_j) < c_k for the others (s = i)?"""
    ks = [k for k in range(n) if k != s and k not in allowed]
    if not ks:
        return True
    unb = [k for k in ks if fars.get(k) is not None]
    a = np.linspace(g0, g1, 17)

    def test(thc, half):
        hi = c_range(fars, s, thc, half)[1]
        for k in allowed:
            if k != s:
                hi = np.minimum(hi, c_range(fars, k, thc, half)[1])
        lo = np.ones_like(thc) if len(unb) < len(ks) else np.full_like(thc, np.inf)
        for k in unb:
            lo = np.minimum(lo, c_range(fars, k, thc, half)[0])
        return CellTest(fault=None, undecided=~(hi < lo))

    return walk_cells(a[:-1], a[1:], test, max_work, smallest=1e-13).proved


def lead_interval(fars, n, i, j, ths, tha, thb, max_work=20000):
    """J = (α, β, σ) ⊂ (θa, θb) around the float direction ths on which only i and j can attain
    min_k c_k and c_i − c_j has strict opposite signs at α and β (σ = 1 when c_i > c_j at β), or
    None."""
    for eta in (1e-2, 1e-3, 1e-5):
        a, b = ths - eta, ths + eta
        if not (tha < a and b < thb):
            continue
        lo_a, hi_a = c_range(fars, i, a, 0.0)
        lo_a2, hi_a2 = c_range(fars, j, a, 0.0)
        lo_b, hi_b = c_range(fars, i, b, 0.0)
        lo_b2, hi_b2 = c_range(fars, j, b, 0.0)
        if hi_a < lo_a2 and lo_b > hi_b2:
            sigma = 1.0
        elif lo_a > hi_a2 and hi_b < lo_b2:
            sigma = -1.0
        else:
            continue
        if _min_strict(fars, n, i, a, b, max_work, allowed=(i, j)):
            return (a, b, sigma)
    return None


# ============================================================================ separation
def _h_region(fc, branch, th):
    """Support function of a convex side of an unbounded site in the world directions th (inf where
    unbounded), with a rounding margin (module docstring)."""
    vx, vy = np.cos(th), np.sin(th)
    v1 = fc.cs * vx + fc.sn * vy
    v2 = -fc.sn * vx + fc.cs * vy
    base = vx * fc.tx + vy * fc.ty
    mag = abs(fc.tx) + abs(fc.ty)
    with np.errstate(divide="ignore", invalid="ignore"):
        if fc.kind == "parabola":
            val = np.where(v1 < 0, fc.p * v2 * v2 / (2 * np.abs(v1)), np.inf)
            mag = mag + np.where(v1 < 0, val, 0.0)
        else:
            s1 = -branch * v1
            rad = fc.a * fc.a * v1 * v1 - fc.b * fc.b * v2 * v2
            val = np.where((s1 > 0) & (rad > 0), -np.sqrt(np.maximum(rad, 0.0)), np.inf)
            mag = mag + fc.a + fc.b
    return base + val + 1e-11 * (mag + 1.0)


def _separated_unbounded(fa, ba, fb, bb):
    """A direction v with h_A(v) + h_B(−v) < 0 on a grid (module docstring)."""
    th = np.linspace(0.0, TWO_PI, 7201)[:-1]
    s = _h_region(fa, ba, th) + _h_region(fb, bb, th + math.pi)
    return bool(np.any(s < 0))


def _disc_margin(fc, branch, centre, radius):
    """Lower bound of d(centre, convex side) − radius through tangent half-planes at the float foot
    of the centre (and at the vertex)."""
    X0, Y0 = fc.cs * (centre[0] - fc.tx) + fc.sn * (centre[1] - fc.ty), -fc.sn * (centre[0] - fc.tx) + fc.cs * (centre[1] - fc.ty)
    err = 1e-12 * (abs(centre[0]) + abs(centre[1]) + abs(fc.tx) + abs(fc.ty) + 1.0)
    best = -math.inf
    if fc.kind == "parabola":
        from .far_conics import parabola_foot_guess
        sy = -1.0 if Y0 > 0 else 1.0                  # reflect Y so that Y0 ≤ 0
        S0 = float(parabola_foot_guess(X0, sy * Y0 if sy * Y0 < 0 else -1e-300, fc.p))
        for S in (0.0, S0, 1.1 * S0, 0.9 * S0):
            v = (-fc.p * X0 + S * sy * Y0 - 0.5 * S * S) / math.hypot(fc.p, S)
            best = max(best, v - err * (1 + fc.p + abs(S)) - 1e-12 * abs(v))
    else:
        from .far_conics import hyperbola_foot_guess
        x, y = branch * X0, abs(Y0)                   # the right branch after reflections
        ws = [0.0]
        if x > 0 and y > 0:
            w0 = float(hyperbola_foot_guess(x, y, fc.a, fc.b))
            ws += [w0, 1.1 * w0, 0.9 * w0]
        for w in ws:
            nx, ny = -fc.b * math.cosh(w), fc.a * math.sinh(w)
            nn = math.hypot(nx, ny)
            v = ((x - fc.a * math.cosh(w)) * nx + (y - fc.b * math.sinh(w)) * ny) / nn
            best = max(best, v - err * (1 + fc.a + fc.b) * math.cosh(w) - 1e-12 * abs(v))
    return best - radius * (1 + 1e-12)


def _separation(geoms, fars, problems, max_work) -> bool:
    """Step (b) of the module docstring."""
    from .support import SupportTable

    n = len(geoms)
    bnd = [k for k in range(n) if fars.get(k) is None]
    if len(bnd) > 1 and not hulls_disjoint(SupportTable([geoms[k] for k in bnd]), problems, max_work, names=bnd):
        return False
    sides = [(k, br) for k in range(n) if fars.get(k) is not None
             for br in ((1.0,) if fars[k].kind == "parabola" else (1.0, -1.0))]
    sup_b = SupportTable([geoms[k] for k in bnd]) if bnd else None
    for k, br in sides:
        for t, kb in enumerate(bnd):
            if not _disc_margin(fars[k], br, sup_b.cen[t], sup_b.rho[t]) > 0:
                problems.append(f"sites {min(k, kb)} and {max(k, kb)}: site {kb} is not proved outside the "
                                f"convex side of the unbounded site {k}")
                return False
    for x in range(len(sides)):
        for y in range(x + 1, len(sides)):
            (ka, ba), (kb, bb) = sides[x], sides[y]
            if ka != kb and not _separated_unbounded(fars[ka], ba, fars[kb], bb):
                problems.append(f"sites {ka} and {kb}: the convex sides of these unbounded sites are not "
                                "proved disjoint")
                return False
    return True


# ============================================================================ accounting
def accounting_unbounded(geoms, ends_inf, problems, max_work=400000, unproved_ends=()) -> bool:
    """Steps (a) and (b) of the module docstring.  ``ends_inf``: (θ, pair, (α, β), edge id) with J =
    [α, β] from :func:`runtime.voronoi.verify.conic_tail.prove_conic_tail`."""
    n = len(geoms)
    if n < 2:
        return True
    m = far_centre(geoms)
    fars = {k: FarConic(g, m) for k, g in enumerate(geoms) if g.kind in UNBOUNDED}
    if not _separation(geoms, fars, problems, max_work):
        return False
    if unproved_ends:
        ids = sorted(unproved_ends)
        problems.append(fault("completeness not proved: the ends at infinity of unbounded edge"
                              f"{'s' if len(ids) > 1 else ''} {', '.join(map(str, ids[:6]))}"
                              f"{', ...' if len(ids) > 6 else ''} are not proved", kind="infinity"))
        return False
    if any(t[2][0] == "mirror" for t in ends_inf):
        problems.append("ties at infinity between mirror-image sites next to unbounded sites are not handled")
        return False
    if not ends_inf:
        # a component without points at infinity is then not excluded (Prop. 1.2.1 needs one)
        problems.append("completeness not proved: no unbounded edge is proved (with unbounded sites "
                        "the diagram may have none, and then the argument of Prop. 1.2.1 does not apply)")
        return False
    ends = sorted(((tha % TWO_PI, tha % TWO_PI + (thb - tha), pair, eid) for _, pair, (tha, thb), eid in ends_inf),
                  key=lambda t: t[0])
    mm = len(ends)
    if mm < 2:
        problems.append(fault("a single unbounded edge end: the ends at infinity do not close up", kind="infinity"))
        return False
    ok = True
    for a in range(mm):
        for b in range(a + 1, mm):
            ea, eb = ends[a], ends[b]
            if set(ea[2]) == set(eb[2]) and not (eb[0] - ea[0] > ea[1] - ea[0] and eb[1] - ea[0] < TWO_PI):
                problems.append(fault(f"unbounded edges {ea[3]} and {eb[3]} of sites {ea[2][0]}, {ea[2][1]} have "
                                      "overlapping asymptotic intervals", kind="infinity", sites=ea[2]))
                ok = False
    for t in range(mm):
        cur, nxt = ends[t], ends[(t + 1) % mm]
        a_next = nxt[0] + (TWO_PI if t == mm - 1 else 0.0)
        if not a_next > cur[1]:
            problems.append(fault(f"the asymptotic intervals of unbounded edges {cur[3]} and {nxt[3]} overlap",
                                  kind="infinity", sites=(*cur[2], *nxt[2])))
            ok = False
            continue
        shared = set(cur[2]) & set(nxt[2])
        if not shared:
            problems.append(fault(f"unbounded edges {cur[3]} and {nxt[3]} are consecutive at infinity but share "
                                  "no site: " + gap_note(unproved_ends), kind="infinity", sites=(*cur[2], *nxt[2])))
            ok = False
        elif not any(_min_strict(fars, n, s, cur[1], a_next, max_work) for s in shared):
            problems.append(fault(f"between the unbounded edges {cur[3]} and {nxt[3]} no single site owns all far "
                                  "directions: an unbounded edge is missing or misplaced", kind="infinity",
                                  sites=(*cur[2], *nxt[2])))
            ok = False
    return ok
