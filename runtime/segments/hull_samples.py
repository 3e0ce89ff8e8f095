"""Samples of the arcs where they touch the convex hull of the sites (thesis §1.2: the unbounded
regions are those of the sites on the convex hull, their infinite edges follow the hull's sides).

Samples of an arc lie on the arc, hence inside the convex hull of the sites, a sagitta ρ(1 −
cos δ) inside it near the arc's point of contact with the hull (δ the angle to the nearest
sample).  A point site, or a segment's end, closer than that to a side of the hull between two
arcs is then a corner of the samples' hull: the sample diagram gives it an unbounded region,
while its true region is closed by a vertex of the two arcs far out (at about ℓ²/(8ε) for a
point ε inside a side of length ℓ: 10⁸ for ε = 0.004 and ℓ = 1800), beyond any far point the
construction checks.  No refinement of the triangle's own sites removes it: the arcs whose
contact points matter are not among them.

:func:`hull_samples` adds the contact points themselves.  Starting from the ends of all curves
and the point sites (the hull of segments is that of their ends), each side of the current hull
with outward unit normal n, except a chord of one arc, is compared with every arc whose circle
crosses it: the arc's extreme point c + ρn in the direction n (when n lies in the arc's angular
range; otherwise the arc's extreme point is an end, already there) beyond the side becomes a
sample, and the hull is recomputed (only the newest point near a contact point is kept as a
sample, none next to an arc's end).  The hull only grows, so an arc once inside stays inside.
At a bridge between two arcs the normal's error shrinks quadratically (the chord of points at
angle errors φ turns the normal by about ρφ²/ℓ), so a few rounds reach the contact points to
rounding.  These points are samples only: the combinatorics they suggest are proved afterwards.
They are kept only on the sides with a point site (a curve's end among them) within a sagitta
band (0.1 ρ) inside: elsewhere the samples' hull has the true hull's corner sites already (and
more co-circular samples of an arc next to its smooth joint upset the sample walks of a
circle's two halves).

Public API: :func:`hull_samples`.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from .distance import in_arc
from .elementary import ARC, ElementarySites

__all__ = ["hull_samples"]

#: most rounds of contact points (the normal's error shrinks quadratically per round)
MAX_ROUNDS = 40
#: contact points closer than this times the radius to a newer one or to an end are dropped
NEAR = 1e-3
#: a contact point is a sample only where a point lies within BAND times the radius inside its side
BAND = 0.1
#: hull sides times candidate arcs per block of the comparison (bounds its memory)
BLOCK = 4_000_000


def hull_samples(E: ElementarySites) -> dict:
    """{arc site: [(x, y), ...]}: points of the arcs on the convex hull of the sites (floats, on
    the arcs' circles to rounding; module docstring)."""
    arcs = np.nonzero(E.kind == ARC)[0]
    if not len(arcs):
        return {}
    C, rho = E.C[arcs], E.rho[arcs]
    P = np.vstack([E.A, E.B])
    scale = 1.0 + float(np.max(np.abs(P))) + float(np.max(rho))
    eps = 1e-13 * scale
    out: dict = {}
    cand = np.arange(len(arcs))
    for _ in range(MAX_ROUNDS):
        try:
            hull = ConvexHull(P)
        except (QhullError, ValueError):
            return out                 # collinear ends: the arcs' samples themselves close it
        V = P[hull.vertices]           # counter-clockwise
        V1 = np.roll(V, -1, axis=0)
        W = V1 - V
        L = np.hypot(W[:, 0], W[:, 1])
        N = np.column_stack([W[:, 1], -W[:, 0]]) / L[:, None]          # outward unit normals
        off = np.einsum("ij,ij->i", N, V)
        new = []
        still = np.zeros(len(cand), dtype=bool)
        rows = max(1, BLOCK // max(len(N), 1))
        for b0 in range(0, len(cand), rows):
            idx = cand[b0:b0 + rows]
            H = C[idx] @ N.T + rho[idx][:, None] - off[None, :]        # circle beyond each side
            a_, s_ = np.nonzero(H > eps)
            if not len(a_):
                continue
            still[b0 + np.unique(a_)] = True
            U = N[s_]
            s = arcs[idx[a_]]
            # a chord of the arc itself (both ends on its circle) is not a bridge: skipped
            near = 1e-9 * (E.rho[s] + np.abs(E.C[s]).max(axis=1))
            on0 = np.abs(np.hypot(*(V[s_] - E.C[s]).T) - E.rho[s]) <= near
            on1 = np.abs(np.hypot(*(V1[s_] - E.C[s]).T) - E.rho[s]) <= near
            inside = in_arc(E.C[s], E.A[s], E.B[s], U) & ~(on0 & on1)
            a_, s_, U, s = a_[inside], s_[inside], U[inside], s[inside]
            if not len(a_):
                continue
            X = E.C[s] + E.rho[s][:, None] * U
            beyond = np.einsum("ij,ij->i", U, X) - off[s_] > eps
            for site, x in zip(s[beyond].tolist(), X[beyond]):
                new.append((site, x))
        cand = cand[still]
        if not new:
            break
        for site, x in new:
            # the newest iterate of a contact point replaces the older ones near it, and none is
            # kept next to the arc's ends (samples themselves): nearly coincident co-circular
            # samples are a degenerate input for the sample triangulation
            site = int(site)
            near = NEAR * float(E.rho[site])
            if min(np.hypot(*(x - E.A[site])), np.hypot(*(x - E.B[site]))) <= near:
                continue
            out[site] = [y for y in out.get(site, []) if np.hypot(*(x - y)) > near] + [x]
        P = np.vstack([P, np.array([x for _, x in new])])
    return _needed(E, P, out)


def _needed(E: ElementarySites, P, out: dict) -> dict:
    """The contact points of the hull sides that have a point site (an isolated point or a
    curve's end, not a smooth joint) strictly inside, within a sagitta band of BAND times the
    arcs' radius: only there do the samples' hull and the true hull disagree on corners."""
    where = {(float(x[0]), float(x[1])): site for site, xs in out.items() for x in xs}
    if not where:
        return {}
    try:
        V = P[ConvexHull(P).vertices]
    except (QhullError, ValueError):
        return {}
    Q = E.A[:E.n_points]                  # the point sites (segments' and arcs' ends among them)
    keep: dict = {}
    X = np.array(list(where), float)
    X_site = list(where.values())
    tol = 1e-9 * (1.0 + float(np.max(np.abs(P))))
    for a, b in zip(V, np.roll(V, -1, axis=0)):
        sites = [where.get((float(x[0]), float(x[1]))) for x in (a, b)]
        if sites == [None, None]:
            continue
        _keep_collinear(E, a, b, X, X_site, tol, keep)
        band = BAND * max(float(E.rho[s]) for s in sites if s is not None)
        w = b - a
        L = float(np.hypot(*w))
        if L == 0:
            continue
        n = np.array([w[1], -w[0]]) / L                      # outward
        depth = (a - Q) @ n
        along = (Q - a) @ (w / L)
        if np.any((depth > 0) & (depth <= band) & (along > 0) & (along < L)):
            for x, site in zip((a, b), sites):
                if site is not None:
                    keep.setdefault(site, []).append(x)
    return keep


def _keep_collinear(E: ElementarySites, a, b, X, X_site, tol: float, keep: dict) -> None:
    """Arcs tangent to one side of the hull (three circles of integer data touching a common line
    at integer points is common): their contact points inside the side are on the true hull but
    not vertices of the samples' hull; without them the middle arc's samples stay strictly inside
    it (their chords sag by the sagitta), the samples give the outer two arcs a common unbounded
    edge and the middle arc none.  The contact point c + ρn of every other arc whose circle
    touches the side's line within ``tol`` (n the outward normal, in the arc's range, inside the
    side; not the arcs of the side's own ends, whose short sides between iterates of one contact
    are nearly tangent chords) is kept, with the side's two ends, so that the sample triangulation sees the contacts (nearly)
    collinear on its hull."""
    w = b - a
    L = float(np.hypot(*w))
    if L == 0:
        return
    u = w / L
    n = np.array([u[1], -u[0]])                                  # outward (counter-clockwise hull)
    ends = {X_site[i] for x in (a, b) for i in np.nonzero(np.all(X == x, axis=1))[0].tolist()}
    arcs = np.nonzero(E.kind == ARC)[0]
    H = E.C[arcs] @ n + E.rho[arcs] - float(n @ a)
    cand = arcs[(np.abs(H) <= tol) & ~np.isin(arcs, list(ends))]    # a third arc (not a chord's own)
    if not len(cand):
        return
    Xc = E.C[cand] + E.rho[cand][:, None] * n
    along = (Xc - a) @ u
    ok = (along > tol) & (along < L - tol) & in_arc(E.C[cand], E.A[cand], E.B[cand], np.repeat(n[None, :], len(cand), 0))
    found = False
    for site, x in zip(cand[ok].tolist(), Xc[ok]):
        near = NEAR * float(E.rho[site])
        if min(np.hypot(*(x - E.A[site])), np.hypot(*(x - E.B[site]))) <= near:
            continue
        keep.setdefault(int(site), []).append(x)
        found = True
    if found:
        for x in (a, b):
            for i in np.nonzero(np.all(X == x, axis=1))[0].tolist():
                keep.setdefault(X_site[i], []).append(X[i])
