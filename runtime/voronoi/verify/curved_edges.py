"""Step 2 of the certificate (:mod:`runtime.voronoi.verify.certificate`) for the edges with a conic
site: their chains of strips (:mod:`runtime.voronoi.verify.curved`, all edges side by side), and
their unbounded ends, proved to infinity in a sector of directions
(:func:`runtime.voronoi.verify.tail.prove_tail`) or, for mirror-image sites tied at infinity,
along their mirror line (:func:`runtime.voronoi.verify.mirror_tail.prove_mirror_tail`).

Public API: :func:`curved_edges`, :func:`curved_job`, :func:`curved_scale`, :func:`past`,
:func:`drawn_points`, :func:`shape_key`, :func:`may_mirror`, :func:`ends_at_vertices`; the steps of
:func:`curved_edges`: :func:`near_bisector`, :func:`mirror_edges`, :class:`FarEnds`.
"""
from __future__ import annotations

import math
import time

import numpy as np

from ...predicates.symmetry import mirror_line
from .mirror_tail import prove_mirror_edge, prove_mirror_tail
from .tied_tail import prove_tied_tail

__all__ = ["curved_edges", "curved_job", "curved_scale", "past", "drawn_points", "shape_key", "may_mirror",
           "ends_at_vertices"]


def past(deadline) -> bool:
    """Is the deadline (a :func:`time.perf_counter` value) passed?"""
    return deadline is not None and time.perf_counter() > deadline


def curved_scale(geoms) -> float:
    """1 + the largest finite coordinate of the sites' bounding boxes."""
    fin = [b for g in geoms for b in g.bounding_box() if math.isfinite(b)]
    return 1.0 + (max(abs(b) for b in fin) if fin else 0.0)


def curved_job(e, name, pair, P, endv, scale, problems):
    """The checks of an edge with a conic site that need no search (ends at its vertices); returns
    the job for :func:`runtime.voronoi.verify.curved.prove_curved_edges`, or None (problem
    recorded)."""
    v0, v1 = endv
    if e.closed and (v0 is not None or v1 is not None):
        problems.append(f"{name}: a closed edge cannot end at a vertex")
        return None
    if not ends_at_vertices(name, P, endv, scale, problems):
        return None
    return (scale, pair, P, v0, v1, float(e.tolerance), bool(e.closed))


def ends_at_vertices(name, P, endv, scale, problems) -> bool:
    """Does the polyline start and end at its end vertices?  Each end within tol + 2h of the
    vertex's proved centre (plus 10⁻¹² of the scene): the test by which
    :func:`runtime.voronoi.verify.vertices.prove_vertices` accepts the reported vertex, so a
    polyline drawn from the reported position always passes; its end is then within
    tol + (2 + √2)·h of the true vertex.  False: problem recorded."""
    for t, (w, Q) in enumerate(((endv[0], P[0]), (endv[1], P[-1]))):
        if w is not None and math.hypot(Q[0] - w.x, Q[1] - w.y) > w.tol + 2 * w.h + 1e-12 * scale:
            problems.append(f"{name}: polyline {'starts' if t == 0 else 'ends'} at ({Q[0]:.17g}, {Q[1]:.17g}), "
                            f"not at vertex {w.id} ({w.x:.17g}, {w.y:.17g})")
            return False
    return True


def curved_edges(curved, geoms, problems, eok, ends_inf, deadline=None, late=None):
    """Edges with a conic site (:mod:`runtime.voronoi.verify.curved`), all chains side by side;
    an unbounded end is proved to infinity by :func:`runtime.voronoi.verify.tail.prove_tail` and
    recorded in ``ends_inf`` as (θ_mid, pair, (θa, θb), edge id) with [θa, θb] its asymptotic
    sector.  ``curved``: (position, edge, name, job).  ``late``: a one-element list counting
    the edges left undone at ``deadline``."""
    from .curved import TIME_LIMIT, prove_curved_edges
    from .site_table import SiteTable
    from .support import SupportTable

    if not curved:
        return
    late = [0] if late is None else late
    scale = curved[0][3][0]
    table = SiteTable(geoms, scale)
    jobs = near_bisector(curved, table, scale, problems, eok)
    # edges between mirror-image sites are their mirror lines: proved without strips
    sup = SupportTable(geoms) if sup_ok(geoms) else None
    jobs = mirror_edges(jobs, geoms, table, sup, eok, ends_inf)
    results = prove_curved_edges(table, [job for _, _, _, job in jobs], deadline=deadline,
                                 sup=sup if sup is not None and sup.ok else None)
    tails = FarEnds(geoms, table, scale, sup)
    for (p_e, e, name, job), (ok, msg, beyond) in zip(jobs, results):
        if msg == TIME_LIMIT or (beyond and past(deadline)):
            late[0] += 1           # stopped, or its tails would start after the deadline
            eok[p_e] = False
            continue
        if not ok:
            problems.append(f"{name}: {msg}")
            eok[p_e] = False
            continue
        ok, ends = tails.prove(e, name, job[1], beyond, problems)
        eok[p_e] = ok
        if ok:
            ends_inf.extend(ends)


def near_bisector(curved, table, scale, problems, eok):
    """The jobs of ``curved`` whose drawn points (:func:`drawn_points`) lie within the stated
    tolerance of the bisector: |d_i − d_j|/2 is a lower bound of a point's distance to it
    (d_i − d_j is 2-Lipschitz), from the enclosures of d_i, d_j (one call for all edges); an edge
    with a point farther (lower bound > tol) is recorded in ``problems`` and not proved."""
    rows, ks, owner = [], [], []
    for t, (_, e, _, (_, pair, P, _, _, _, _)) in enumerate(curved):
        inner = P[drawn_points(e, P)]
        rows += [inner, inner]
        ks += [np.full(len(inner), pair[0]), np.full(len(inner), pair[1])]
        owner.append(len(inner))
    V = table.evaluate(np.concatenate(rows), np.concatenate(ks)) if sum(owner) else None
    jobs, pos = [], 0
    for (p_e, e, name, job), cnt in zip(curved, owner):
        Vi, Vj = (V.part(pos, pos + cnt), V.part(pos + cnt, pos + 2 * cnt)) if cnt else (None, None)
        pos += 2 * cnt
        if cnt:
            inner = job[2][drawn_points(e, job[2])]
            lb = np.maximum(Vi.lo - Vj.hi, Vj.lo - Vi.hi) / 2
            tol = float(e.tolerance) if math.isfinite(e.tolerance) else math.inf
            far = np.nonzero(lb > tol * (1 + 1e-9) + 1e-12 * scale)[0]
            if len(far):
                p = int(far[0])
                problems.append(f"{name}: polyline point {p + drawn_points(e, job[2]).start} ({inner[p, 0]:.9g}, "
                                f"{inner[p, 1]:.9g}) is at least {lb[p]:.3g} from the bisector (stated tolerance {tol:.3g})")
                eok[p_e] = False
                continue
        jobs.append((p_e, e, name, job))
    return jobs


def mirror_edges(jobs, geoms, table, sup, eok, ends_inf):
    """Prove the edges of ``jobs`` between mirror-image sites as their mirror lines
    (:func:`runtime.voronoi.verify.mirror_tail.prove_mirror_edge`, no strips; sites proved not
    mirror images by :func:`may_mirror` skipped), with their unbounded ends in ``ends_inf``;
    returns the other jobs (those whose mirror proof fails among them)."""
    exact = [g.exact for g in geoms]
    rest = []
    for p_e, e, name, job in jobs:
        _, pair, P, v0, v1, _, closed = job
        if (sup is not None and may_mirror(geoms, pair)
                and mirror_line(exact[pair[0]], exact[pair[1]]) is not None):
            ok, _, mends = prove_mirror_edge(exact, geoms, table, sup, pair, v0, v1, P, closed)
            if ok:
                eok[p_e] = True
                ends_inf.extend((math.atan2(float(u[1]), float(u[0])) % (2 * math.pi), pair,
                                 ("mirror", u, lat), e.id) for u, lat in mends)
                continue
        rest.append((p_e, e, name, job))
    return rest


class FarEnds:
    """The proofs beyond the chains' cuts of the unbounded ends of one call's edges: the support
    table ``sup`` (made at the first end if not given), and ``more``, the tails undecided within
    TAIL_WORK still to be tried again with TAIL_WORK_MORE (at most MORE_TAILS of
    :mod:`runtime.voronoi.verify.tail` per call)."""

    def __init__(self, geoms, table, scale, sup):
        from .tail import MORE_TAILS

        self.geoms, self.table, self.scale, self.sup = geoms, table, scale, sup
        self.more = MORE_TAILS

    def prove(self, e, name, pair, beyond, problems):
        """Prove each unbounded end of edge ``e`` beyond its cut (``beyond``, from
        :func:`runtime.voronoi.verify.curved.prove_curved_edge`): a tie in rationals first
        (:meth:`tied`), else the sector prover; at the first end not proved, its problem is
        recorded and the others are left.  Returns (ok, ends), ``ends`` the entries of
        ``ends_inf`` (θ, pair, sector or mirror tie, edge id)."""
        from .support import SupportTable
        from .tail import TAIL_WORK_MORE, prove_tail

        ok, ends = True, []
        for far in beyond:
            if self.sup is None:
                self.sup = SupportTable(self.geoms)
            sup = self.sup
            q = far["point"]
            tie = self.tied(pair, far)
            if tie is not None:
                th = math.atan2(float(tie[0][1]), float(tie[0][0])) % (2 * math.pi)
                ends.append((th, pair, ("mirror",) + tie, e.id))
                continue
            ok, msg, sector = prove_tail(sup, self.table, pair, far["link"], self.scale)
            if not ok and "undecided" in msg and self.more > 0:
                self.more -= 1
                ok, msg, sector = prove_tail(sup, self.table, pair, far["link"], self.scale, max_work=TAIL_WORK_MORE)
            if not ok:
                problems.append(f"{name}: proved up to ({q[0]:.9g}, {q[1]:.9g}), not proved beyond it: {msg}")
                break
            tha, thb, _ = sector
            ends.append((0.5 * (tha + thb) % (2 * math.pi), pair, (tha, thb), e.id))
        return ok, ends

    def tied(self, pair, far):
        """The tie of a tail in a direction where its sites tie exactly with others (rows of
        identical shapes: mirror lines, :func:`runtime.voronoi.verify.mirror_tail.prove_mirror_tail`;
        translates or different shapes resting on one line: tied tails,
        :func:`runtime.voronoi.verify.tied_tail.prove_tied_tail`), proved in rationals at once, or
        None (also without support functions: a site not bounded convex).  The sector prover
        cannot separate a tie and would spend its whole work limit first."""
        sup, geoms = self.sup, self.geoms
        ok2, tie = False, None
        if sup.ok:       # bounded convex sites: support functions exist
            ok2, msg2, tie = prove_mirror_tail([g.exact for g in geoms], geoms, sup, pair, far["link"])
        if sup.ok and not ok2:      # different shapes resting on one line
            ok2, msg2, tie = prove_tied_tail([g.exact for g in geoms], geoms, sup, pair, far["link"],
                                             np.asarray(far["point"], float) - sup.m)
        return tie if ok2 else None


def shape_key(g):
    """The float isometry invariants of a site geometry: its kind and its semi-axes (ellipse a ≥ b,
    hyperbola), radius (circle) or parameter (parabola); None for another kind.  A rigid motion
    keeps the canonical form of a conic, hence these (the classical invariants of a conic under
    rigid motions; e.g. Salmon, *Conic Sections*, §§ 370-371); the floats of two congruent sites
    differ by rounding only."""
    if g.kind == "point":
        return ("point",)
    if g.kind == "circle":
        return ("circle", float(g.rho))
    if g.kind in ("ellipse", "hyperbola"):
        return (g.kind, float(g.a), float(g.b))
    if g.kind == "parabola":
        return ("parabola", float(g.p))
    return None


def may_mirror(geoms, pair) -> bool:
    """False when the sites of ``pair`` are not congruent (their :func:`shape_key` differ by more
    than 10⁻⁹ of the values, far above rounding), so no reflection maps one onto the other and
    :func:`runtime.predicates.symmetry.mirror_line` would return None; True otherwise (then it
    decides exactly).  Only a shortcut: an edge skipped here is proved by the strips."""
    ka, kb = (shape_key(geoms[k]) for k in pair)
    if ka is None or kb is None:
        return True
    return ka[0] == kb[0] and all(abs(x - y) <= 1e-9 * max(abs(x), abs(y)) for x, y in zip(ka[1:], kb[1:]))


def sup_ok(geoms) -> bool:
    """Do the sites have support functions (points, circles, ellipses)?"""
    return all(g.kind in ("point", "circle", "ellipse") for g in geoms)


def drawn_points(e, P) -> slice:
    """The polyline points that are not end vertices: all but the first and last, plus an end at
    infinity (a far point, which must lie within the stated tolerance of the bisector too); every
    point of a closed edge."""
    if e.closed:
        return slice(0, len(P))
    return slice(0 if e.ends[0] is None else 1, len(P) if e.ends[1] is None else len(P) - 1)
