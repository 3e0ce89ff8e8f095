"""Vertex proofs for :mod:`runtime.voronoi.verify.certificate`: existence, uniqueness, emptiness.

Circle and point triples (thesis §3.1.2–3.1.3).  A vertex outside the three discs solves

    F_l(x, y, r) = (x − cx_l)² + (y − cy_l)² − (r + ρ_l)² = 0,   l = 0, 1, 2,   r > 0,

and then d(q, S_l) = |q − c_l| − ρ_l = r.  Subtracting F_0 makes two equations linear in q, so
q = q0 − r·q1 when the centres are not collinear, and F_0 becomes a quadratic in r: the system
has at most **two** solutions.  Both are proved, in a batch over all vertices, by **Krawczyk's
test in floating point with error bounds** (Krawczyk 1969; Moore, Kearfott & Cloud,
*Introduction to Interval Analysis*, SIAM 2009, §8.2), decided by the kernel's
:func:`runtime.certify.interval_newton.float_krawczyk_test` on a cube z̃ + [−ρ, ρ]³ from the
enclosures of F(z̃) (its rounding and the rounding of the float data of the exact sites) and of
the Jacobian over the cube (:func:`_krawczyk`): a unique zero in the cube.  Two
disjoint boxes then hold *all* solutions of the system, which the edge proofs use (the zeros of
d_k − d_i on the bisector of i, j are the solutions with r > 0).  Triples that are not pairwise
exterior, collinear centres and failed tests go to the exact route of thesis §3.1.3
(:func:`runtime.predicates.circles.voronoi_vertices_circles`, exact in quadratic towers).

Triples with a conic: first, for convex sites, a float Krawczyk test on the distance
differences, all vertices at once (:mod:`runtime.voronoi.verify.conic_vertices`); where it does
not decide, :func:`runtime.voronoi.vertex.certify_vertex` (Krawczyk on the exact foot-point
system, thesis §6.1 / App. D.1, and the touching certificate).

Emptiness: every other site k must satisfy lo_k(q̃) − h > r_hi, with h the half diagonal of the
vertex box (distances are 1-Lipschitz) and lo_k the rigorous ``distance_bounds``; candidates come
from a k-d tree on the centres (circles and points: d(q, S) ≥ |q − c| − ρ; conics: the distance
to the bounding box, a lower bound of the distance to the site,
:meth:`runtime.voronoi.verify.site_table.SiteTable.near_pairs`).
"""
from __future__ import annotations

import math

import numpy as np

from ...certify.interval_newton import (float_contraction_bound, float_inverse, float_krawczyk_test,
                                        float_residual_bound, round_up)
from ...predicates.circles import voronoi_vertices_circles
from ...result import LocatorError
from .problems import fault
from .exact_vertices import cocircular_vertex, exact_emptiness

__all__ = ["VertexInfo", "prove_vertices", "vname", "local_reach", "local_default", "LOCAL_REACH"]

EPS = 2.0 ** -53
VERTEX_TOL = 1e-10      # relative distance between a reported vertex and the proved one
#: a local proof (an insertion, a chunk of the chunked certificate) lists the sites that come
#: within r_v + LOCAL_REACH·VERTEX_TOL·(1 + |x| + |y| + |r_v|) of each reported vertex v
LOCAL_REACH = 5.0


class VertexInfo:
    """What the verifier knows of one reported vertex: the proved position (x, y), radius r, a
    half-width ``h`` of its box, and ``others``: the positions of the other solutions of the
    triple's system (exact route: every Voronoi vertex of the triple; fast route: the second
    root with r > −h), for the edges' exact-zero argument; ``others=None`` when unknown."""

    def __init__(self, vid, sites, x, y, r, h=0.0, others=(), key=None):
        self.id, self.sites = vid, sites
        self.x, self.y, self.r, self.h = float(x), float(y), float(r), float(h)
        self.others = others
        self.key = key
        self.tol = VERTEX_TOL * (1 + abs(x) + abs(y) + abs(r))


def local_reach(v, info) -> float:
    """A radius about the reported vertex v (position, radius) whose disc holds the true empty
    circle, once v is proved (``info``): v is within tol + 2h of the proved centre (the check of
    :func:`prove_vertices`), the true vertex within √2·h of that centre and its radius within h of
    the proved one, so the true circle lies in the disc of centre v and radius r_v + 2·tol + 7h
    (widened for rounding).  A local proof (an insertion, a chunk of the chunked certificate)
    lists the sites within r_v + LOCAL_REACH·VERTEX_TOL·(1 + |x| + |y| + |r_v|) before proving;
    where this radius is larger (a coarse proof box: about 1.5 % of the vertices of random circles
    have h > tol/4) it must check the sites out to this radius as well.  The whole verifier lists
    the sites around the proved box itself and needs neither."""
    r = v.radius + 2 * info.tol + 7 * info.h
    return r * (1 + 1e-12) + 1e-12 * (abs(v.x) + abs(v.y) + 1)


def local_default(v) -> float:
    """The radius about the reported vertex v within which a local proof lists the sites first."""
    return v.radius + LOCAL_REACH * VERTEX_TOL * (1 + abs(v.x) + abs(v.y) + abs(v.radius))


def vname(v) -> str:
    return f"vertex {v.id} (sites {', '.join(str(int(s)) for s in v.sites)})"


# ============================================================================ fast circle route

def _krawczyk(C, Rho, Z, scale):
    """Batch float Krawczyk for F_l = |q − c_l|² − (r + ρ_l)².  C (n,3,2), Rho (n,3), Z (n,3).
    Returns (ok mask, refined Z, box half-width).

    The test is the kernel's :func:`runtime.certify.interval_newton.float_krawczyk_test`
    (Krawczyk 1969; Moore, Kearfott & Cloud §8.2; its proof and rounding model, Higham §3.1,
    there) on the cube Z̃ + [−ρ, ρ]³.  The enclosures handed to it, with u = 2^-53 and
    m_l = |x| + |y| + |c_l| + |r| + ρ_l (floats of the exact centres and radii, each within a
    few ulps of the exact data):

    * F(Z̃) for the exact data within 32u·m_l² (the float evaluation of F, about 16
      operations) + 8u·m_l·(|c_l| + ρ_l) (the data's rounding: ∂F/∂c = −2(q − c),
      ∂F/∂ρ = −2(r + ρ)) of the float F̃;
    * every Jacobian on the cube within 2ρ (the rows 2(q − c_l), −2(r + ρ_l) move by at most 2ρ
      per entry) + 8u·(m_l + |c_l|) (the rounding of the float row and the data's) of the
      float J̃ at Z̃, entrywise.
    """
    u = EPS
    with np.errstate(all="ignore"):
        for _ in range(3):                               # Newton polish
            q, r = Z[:, None, :2], Z[:, 2:3]
            V = q - C
            F = (V ** 2).sum(-1) - (r + Rho) ** 2
            J = np.concatenate([2 * V, -2 * (r + Rho)[..., None]], axis=-1)
            det = np.linalg.det(J)
            good = np.isfinite(det) & (np.abs(det) > 1e-300)
            Jg = np.where(good[:, None, None], J, np.eye(3))
            step = np.where(good[:, None], np.linalg.solve(Jg, F[..., None])[..., 0], 0.0)
            Z = Z - step
            if not (np.abs(step) > 4 * u * np.abs(Z)).any():
                break                                    # converged to rounding: more steps change nothing
        q, r = Z[:, None, :2], Z[:, 2:3]
        V = q - C
        F = (V ** 2).sum(-1) - (r + Rho) ** 2
        J = np.concatenate([2 * V, -2 * (r + Rho)[..., None]], axis=-1)
        Y, invertible = float_inverse(J)  # rows with a singular J are refused (exact route)
        mag = (np.abs(q) + np.abs(C)).sum(-1) + np.abs(r) + Rho            # (n,3)
        F_rad = round_up(32 * u * (mag ** 2) + 8 * u * mag * (np.abs(C).sum(-1) + Rho))
        dataJ = round_up(8 * u * (mag + np.abs(C).sum(-1)))[..., None]     # (n,3,1): per row
        b = float_residual_bound(Y, F, F_rad)                              # ≥ |Y F(Z̃)|
    ok = np.zeros(len(Z), bool)
    ok_rows = invertible & np.isfinite(Z).all(-1)
    H = np.zeros(len(Z))
    bmax = b.max(-1)
    for mult in (4.0, 64.0, 4096.0):
        with np.errstate(all="ignore"):
            rho = np.maximum(mult * bmax, 1e-15 * scale)
            J_rad = np.broadcast_to(round_up(2 * rho[:, None, None] + dataJ), J.shape)
            test, _ = float_krawczyk_test(b, float_contraction_bound(Y, J, J_rad), np.broadcast_to(rho[:, None], b.shape))
        test &= ok_rows
        new = test & ~ok
        H = np.where(new, rho, H)
        ok |= test
        if ok[ok_rows].all():
            break               # the larger cubes would only try the rows not yet proved
    return ok, Z, H


def _fast_circle_vertices(items, table):
    """items: list of (index, triple, x, y, r).  Returns {index: (x, y, r, h, others)} for the
    vertices proved on the fast route; the rest go to the exact route."""
    if not items:
        return {}
    idx = np.array([it[0] for it in items])
    T = np.array([it[1] for it in items], int)
    C = table.C[T]                    # (n,3,2)
    Rho = table.R[T]
    Z0 = np.array([[it[2], it[3], it[4]] for it in items], float)
    scale = table.scale
    # the second root of the quadratic in r (q = q0 − r q1), shifted to c_0, seeded from the
    # reported root; both roots are then refined and tested in one batch
    c1, c2 = C[:, 1] - C[:, 0], C[:, 2] - C[:, 0]
    A = 2 * np.stack([c1, c2], axis=1)                                  # (n,2,2)
    b = np.stack([(c1 ** 2).sum(-1) - Rho[:, 1] ** 2 + Rho[:, 0] ** 2,
                  (c2 ** 2).sum(-1) - Rho[:, 2] ** 2 + Rho[:, 0] ** 2], axis=1)
    d = 2 * np.stack([Rho[:, 1] - Rho[:, 0], Rho[:, 2] - Rho[:, 0]], axis=1)
    detA = A[:, 0, 0] * A[:, 1, 1] - A[:, 0, 1] * A[:, 1, 0]
    nA = np.abs(A).max(axis=(1, 2))
    regular = np.abs(detA) > 1e-9 * nA * nA
    Ag = np.where(regular[:, None, None], A, np.eye(2))
    q0, q1 = np.moveaxis(np.linalg.solve(Ag, np.stack([b, d], axis=-1)), -1, 0)
    qa = (q1 ** 2).sum(-1) - 1
    qb = -2 * ((q0 * q1).sum(-1) + Rho[:, 0])
    with np.errstate(all="ignore"):
        r_sum = -qb / qa                                               # r1 + r2
        r_other = r_sum - Z0[:, 2]
    quad = regular & (np.abs(qa) > 1e-9 * (np.abs(q1) ** 2).sum(-1).clip(1.0)) & np.isfinite(r_other)
    with np.errstate(all="ignore"):                                    # rows without a second root: NaN, zeroed
        Zo = np.column_stack([q0 - r_other[:, None] * q1 + C[:, 0], r_other])
    Zo = np.where(np.isfinite(Zo), Zo, 0.0)
    nv = len(Z0)
    ok, Z, H = _krawczyk(np.concatenate([C, C]), np.concatenate([Rho, Rho]), np.concatenate([Z0, Zo]), scale)
    ok1, Z1, H1, ok2, Z2, H2 = ok[:nv], Z[:nv], H[:nv], ok[nv:], Z[nv:], H[nv:]
    apart = (np.abs(Z1 - Z2) > (H1 + H2)[:, None]).any(-1)
    # true vertex: r > 0 and r + ρ_l > 0 on the box
    pos = (Z1[:, 2] - H1 > 0)
    good = ok1 & ok2 & quad & apart & pos
    out = {}
    for m in np.nonzero(good)[0]:
        others = () if Z2[m, 2] + H2[m] <= 0 else ((float(Z2[m, 0]), float(Z2[m, 1])),)
        out[int(idx[m])] = (float(Z1[m, 0]), float(Z1[m, 1]), float(Z1[m, 2]), float(H1[m]), others)
    return out


# ============================================================================ all vertices

def prove_vertices(D, sites, geoms, table, problems, offset=(0.0, 0.0)):
    """Prove every reported vertex (position, radius, emptiness).  Returns ({id: VertexInfo},
    list of flags in diagram order).  Steps: the well-formed vertices (:func:`_screen`); the fast
    circle route and the float conic route on all of them at once; the route of each vertex
    (:func:`_vertex_info`); the reported position and radius against the proved ones, and one
    reported vertex per proved one (:func:`_matches_report`); emptiness (:func:`_emptiness_batch`)."""
    verts = list(D.vertices)
    flags = [False] * len(verts)
    infos: dict = {}
    todo, fast_items = _screen(verts, len(sites), table, problems)
    fast = _fast_circle_vertices(fast_items, table) if table is not None else {}
    ctable = None
    if table is None and todo:      # a conic site: the conic table, for the float route and emptiness
        from .curved_edges import curved_scale
        from .site_table import SiteTable

        ctable = SiteTable(geoms, curved_scale(geoms))
    quick = _conic_quick(verts, todo, fast, geoms, ctable)
    seen_keys: dict = {}
    for m in todo:
        v = verts[m]
        info = _vertex_info(v, sites, geoms, fast.get(m), quick.get(m), problems)
        if info is None or not _matches_report(v, info, offset, seen_keys, problems):
            continue
        infos[v.id] = info
        flags[m] = True
    _emptiness_batch(verts, flags, infos, geoms, (table, ctable), problems)
    return infos, flags


def _screen(verts, n, table, problems):
    """(todo, fast_items): the vertices with a unique id, k ≥ 3 distinct valid sites and a finite
    position and radius (the others are problems), and those of three pairwise exterior circles
    or points (the fast circle route)."""
    seen_ids: set = set()
    todo, trips3 = [], []
    for m, v in enumerate(verts):
        trip = tuple(int(s) for s in v.sites)
        if v.id in seen_ids:
            problems.append(f"{vname(v)}: duplicate vertex id {v.id}")
            continue
        seen_ids.add(v.id)
        if len(trip) < 3 or len(set(trip)) != len(trip) or not all(0 <= s < n for s in trip):
            problems.append(f"{vname(v)}: invalid site list (need k >= 3 distinct sites)")
            continue
        if not (math.isfinite(v.x) and math.isfinite(v.y) and math.isfinite(v.radius)):
            problems.append(f"{vname(v)}: non-finite position or radius")
            continue
        todo.append(m)
        if len(trip) == 3 and table is not None:
            trips3.append((m, trip))
    if not trips3:
        return todo, []
    ext = _pairwise_exterior(table, np.array([t for _, t in trips3], int))
    return todo, [(m, trip, float(verts[m].x), float(verts[m].y), float(verts[m].radius))
                  for (m, trip), e in zip(trips3, ext.tolist()) if e]


def _conic_quick(verts, todo, fast, geoms, ctable) -> dict:
    """Triples with a conic: the float Krawczyk test on the distance differences, all at once
    (:func:`runtime.voronoi.verify.conic_vertices.prove_conic_vertices`, on the conic table
    ``ctable``); {m: (x, y, h, r_lo, r_hi)} where it decides."""
    conic = [m for m in todo if m not in fast and len(verts[m].sites) == 3
             and not all(geoms[int(s)].kind in ("point", "circle") for s in verts[m].sites)]
    if not conic:
        return {}
    from .conic_vertices import prove_conic_vertices

    res = prove_conic_vertices(geoms, [tuple(int(s) for s in verts[m].sites) for m in conic],
                               [(verts[m].x, verts[m].y) for m in conic], ctable.scale, table=ctable)
    return {m: r for m, r in zip(conic, res) if r is not None}


def _near_key(trip, x, y):
    """The key of a proved vertex: its sites and its position rounded to 1e-9 (relative)."""
    return (tuple(sorted(trip)), round(x / (1e-9 * (1 + abs(x)))), round(y / (1e-9 * (1 + abs(y)))))


def _vertex_info(v, sites, geoms, fast, quick, problems):
    """The proved vertex of v's sites nearest to v, by its route: the fast circle route
    (``fast``), k > 3 co-circular sites (:func:`runtime.voronoi.verify.exact_vertices.
    cocircular_vertex`), circles and points exactly (thesis §3.1.3), the float conic route
    (``quick``), else the exact foot-point system (:func:`runtime.voronoi.vertex.certify_vertex`);
    None (with a problem) when no route proves it."""
    trip = tuple(int(s) for s in v.sites)
    if fast is not None:
        x, y, r, h, others = fast
        return VertexInfo(v.id, trip, x, y, r, h, others, key=_near_key(trip, x, y))
    name = vname(v)
    g3 = [geoms[s] for s in trip]
    if len(trip) > 3:
        return cocircular_vertex(v, trip, geoms, problems, VertexInfo)
    if all(g.kind in ("point", "circle") for g in g3):
        try:
            tv = voronoi_vertices_circles(*[g.exact for g in g3])
        except LocatorError as exc:
            problems.append(f"{name}: degenerate triple ({exc})")
            return None
        if not tv.vertices:
            problems.append(f"{name}: the three sites have no Voronoi vertex")
            return None
        best = min(tv.vertices, key=lambda w: math.hypot(w.x - v.x, w.y - v.y))
        h = 2e-16 * (abs(best.x) + abs(best.y)) + 1e-300
        others = tuple((w.x, w.y) for w in tv.vertices if w is not best)
        return VertexInfo(v.id, trip, best.x, best.y, best.radius, h, others, key=(tuple(sorted(trip)), id(best)))
    if quick is not None:
        x, y, h, r_lo, r_hi = quick
        info = VertexInfo(v.id, trip, x, y, 0.5 * (r_lo + r_hi), h, None, key=_near_key(trip, x, y))
        info.r_hi = r_hi
        return info
    from ..vertex import certify_vertex
    proof = certify_vertex([sites[s] for s in trip], g3, v.x, v.y)
    if not proof.certified:
        problems.append(f"{name}: not proved ({proof.reason})")
        return None
    (xl, xh), (yl, yh) = proof.box
    h = max(xh - xl, yh - yl) / 2
    info = VertexInfo(v.id, trip, proof.x, proof.y, proof.radius, h, None, key=_near_key(trip, proof.x, proof.y))
    info.r_hi = proof.radius_bounds[1]
    return info


def _matches_report(v, info, offset, seen_keys, problems) -> bool:
    """Whether the reported position and radius of v are within the tolerance (plus twice the
    box) of the proved ones, and no earlier reported vertex is the same proved vertex."""
    name = vname(v)
    # in a local frame (``offset``: the translation from the user's frame) the reported
    # position was the user's float: add a few ulps of the user's coordinates
    info.tol += 8 * EPS * (abs(info.x + offset[0]) + abs(info.y + offset[1]))
    dpos = math.hypot(info.x - v.x, info.y - v.y)
    if dpos > info.tol + 2 * info.h:
        problems.append(f"{name}: reported position ({v.x:.17g}, {v.y:.17g}) is {dpos:.3g} from the "
                        f"proved vertex of its sites ({info.x:.17g}, {info.y:.17g})")
        return False
    if abs(info.r - v.radius) > info.tol + 2 * info.h:
        problems.append(f"{name}: reported radius {v.radius:.17g}, proved {info.r:.17g}")
        return False
    if info.key in seen_keys:
        problems.append(f"{name}: the same vertex as vertex {seen_keys[info.key]}")
        return False
    seen_keys[info.key] = v.id
    return True


def _pairwise_exterior(table, T):
    """For each row of the (m, 3) site triples T: whether its three discs are pairwise exterior
    with a margin (|c_i − c_j| > (ρ_i + ρ_j)(1 + 10⁻⁹) + 10⁻¹²·scale); the others take the exact
    route (module docstring)."""
    out = np.ones(len(T), bool)
    for a, b in ((0, 1), (0, 2), (1, 2)):
        i, j = T[:, a], T[:, b]
        V = table.C[i] - table.C[j]
        dd = np.hypot(V[:, 0], V[:, 1])
        out &= dd > (table.R[i] + table.R[j]) * (1 + 1e-9) + 1e-12 * table.scale
    return out


def _emptiness_batch(verts, flags, infos, geoms, tables, problems):
    """Every other site strictly outside the disc of each proved vertex (module docstring).
    ``tables``: the circle table (circles and points) or None, and the conic table or None."""
    table, ctable = tables
    ms = [m for m, f in enumerate(flags) if f]
    if not ms:
        return
    X = np.array([[infos[verts[m].id].x, infos[verts[m].id].y] for m in ms])
    info_l = [infos[verts[m].id] for m in ms]
    H = np.array([inf.h * math.sqrt(2) + 4 * EPS * (abs(inf.x) + abs(inf.y)) for inf in info_l])
    Rhi = np.array([getattr(inf, "r_hi", inf.r + inf.h) + 4 * EPS * abs(inf.r) for inf in info_l])
    Rlo = np.array([inf.r - inf.h - 4 * EPS * abs(inf.r) for inf in info_l])
    if table is not None:           # circles and points
        rows, ks = table.near(X, Rhi + H + 1e-9 * table.scale)
    else:   # a conic: every site whose bounding box comes within the reach (the conic table)
        rows, ks = ctable.near_pairs(X, Rhi + 2 * H, (-1, -1))
    width = max(len(inf.sites) for inf in info_l)
    trips = np.full((len(info_l), width), -1, int)
    for t, inf in enumerate(info_l):
        trips[t, :len(inf.sites)] = inf.sites
    keep = ~(trips[rows] == ks[:, None]).any(-1)        # the vertex's own sites
    rows, ks = rows[keep], ks[keep]
    if table is not None:
        lo, hi = table.bounds(X[rows], ks)
    else:
        lo, hi = np.empty(len(rows)), np.empty(len(rows))
        order = np.argsort(ks, kind="stable")
        cuts = np.flatnonzero(np.diff(ks[order])) + 1
        for grp in np.split(order, cuts) if len(order) else ():
            lo[grp], hi[grp] = geoms[int(ks[grp[0]])].distance_bounds(X[rows[grp]])
    if not len(rows):
        return
    inside = hi + H[rows] < Rlo[rows]
    und = ~inside & (lo - H[rows] <= Rhi[rows])
    if und.any() and table is not None:
        # circle/point vertices: the floats cannot separate the site from the circle (nearly
        # co-circular input); decide exactly in the quadratic tower (thesis §3.1.3)
        for t in np.nonzero(und)[0].tolist():
            inf = info_l[int(rows[t])]
            verdict = exact_emptiness(inf, int(ks[t]), geoms)
            if verdict == "outside":
                und[t] = False
            elif verdict == "inside":
                und[t], inside[t] = False, True
    done = set()
    for mask, why in ((inside, "is closer than the three sites: not a Voronoi vertex"), (und, "too close to decide")):
        for t in np.nonzero(mask)[0]:
            r_ = int(rows[t])
            if r_ in done:
                continue
            done.add(r_)
            m = ms[r_]
            flags[m] = False
            infos.pop(verts[m].id, None)
            problems.append(fault(f"{vname(verts[m])}: site {int(ks[t])} {why}", kind="vertex", vertex=verts[m].id,
                                  sites=(*verts[m].sites, int(ks[t]))))
