"""The Delaunay triangulation of the labelled samples and the walks along its bichromatic sides.

The Voronoi diagram of the samples, restricted to the boundaries between different labels,
approximates the diagram of the sites (the sites' regions are the unions of their samples' cells
in the limit of dense sampling).  A triangle with three labels (i, j, k) is a candidate vertex
(its circumcentre is the seed); triangles with two labels {i, j} chain into the edge (i, j).
Walking the dual graph across the bichromatic sides gives every edge: from a 3-label triangle to
another (an edge between two vertices), to the hull (an unbounded edge) or back to the start (a
closed, vertex-less edge around a nested site, thesis Prop. 1.2.1).

qhull is called on the samples moved so that their bounding box is centred at the origin, with
a *fixed* perturbation of :data:`PERTURBATION` of the extent (Barber, Dobkin, Huhdanpaa 1996, §4
call this joggling): the lifted points (x, y, x² + y²) of samples near (10⁶, 10⁶) lose 12 of
their 16 digits in the paraboloid coordinate, and qhull then drops nearly coincident samples as
"coplanar" (they are in no triangle; :attr:`scipy.spatial.Delaunay.vertex_to_simplex` points them
at facets that are not triangles); dense samples on circles are nearly co-circular, and qhull's
facet merging on them costs time quadratic in their number (45 000 samples of four circles:
127 s unperturbed, 1.3 s perturbed).  qhull's own joggle (``QJ``) is not used first: after a
precision error it retries with a joggle ten times larger, up to 10⁻² of the extent, and on
2.4·10⁵ samples of 17 577 circles (radii 0.02 to 283, extent 1 400) it returned 14 723 triangles
whose circumdisks hold another sample (one 10⁻³ of its radius from the centre), whose 3-label
triangles the refinement rounds then chased without end.  The perturbed triangulation is the
Delaunay triangulation of points moved by about 10⁻¹¹ of the extent -- the sample triangulation is
an approximation whatever its precision (the diagram's proof is the verifier's), so this costs
nothing in rigour.  Every input sample is a corner.

The batch update (:meth:`SampleTriangulation.update`) keeps the triangulation local across the
refinement rounds, collinear samples on the hull included (the samples of a segment on the
convex hull of a scene): its result is checked to be a Delaunay triangulation of the convex hull
(Delaunay's lemma on the new sides, the hull, Euler's count) before it is used.
:meth:`SampleTriangulation.legalized` flips (Lawson) the edges that exact incircle tests find illegal.

Length: the triangulation, its batch update with the update's checks, and the walks read the
same arrays (corners, neighbours, labels, circumcentres); apart they would pass all of them.

Public API: :class:`SampleTriangulation`, :func:`circumcentres`, :func:`delaunay`, :func:`perturbed`,
:func:`side_neighbours`.
"""
from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import ConvexHull, Delaunay, QhullError, cKDTree

from .exact_delaunay import lawson_flips
from .sample_walks import chain_walks, index_type

__all__ = ["SampleTriangulation", "circumcentres", "delaunay", "perturbed", "side_neighbours"]

#: qhull options: the paraboloid coordinate scaled to the box of the others, coplanar points kept
#: apart (``Qc``), a point at infinity (``Qz``), wide facets allowed (``Q12``)
QHULL_PLAIN = "Qbb Qc Qz Q12"
#: qhull options of the last resort: qhull's own (escalating) joggle
QHULL_OPTIONS = "QJ Qbb"
#: below this many samples qhull runs on the unperturbed samples first (exact degeneracies kept)
JOGGLE_ABOVE = 20000
#: the fixed perturbation of qhull's input, relative to the largest coordinate (qhull's own first
#: joggle is 30 000 machine epsilons ≈ 6.7·10⁻¹²)
PERTURBATION = 1e-11
#: the batch update declines a cavity of more samples than this: qhull on the cavity holds ~1 kB
#: per sample at once, while a full triangulation of many samples goes strip by strip
#: (:func:`runtime.voronoi.strip_delaunay.strip_delaunay`, one strip's facets at a time)
CAVITY_MAX = 46000


def delaunay(P):
    """qhull's Delaunay triangulation of the points ``P`` (n × 2) in a frame centred on their
    bounding box (see the module docstring): unperturbed below :data:`JOGGLE_ABOVE` points when
    qhull keeps every point, else perturbed by :data:`PERTURBATION` of the extent, with qhull's
    joggle (:data:`QHULL_OPTIONS`) as the last resort.  Returns (triangulation, centre); point
    queries (``find_simplex``) take points minus the centre.  Raises scipy's ``QhullError``
    on fewer than three points."""
    P = np.asarray(P, float)
    c = (P.min(axis=0) + P.max(axis=0)) / 2 if len(P) else np.zeros(2)
    # exact grids and collinear points (point sites are single samples) must keep qhull's merged,
    # unperturbed triangulation: a perturbation splits their flat hull sides into slivers whose
    # circumcentres are at infinity.  Perturb only when qhull drops samples as coplanar, or for
    # many samples (dense co-circular samples make facet merging quadratic).
    # joggling needs four points for its initial simplex; three are triangulated as they are
    if len(P) <= 3:
        return Delaunay(P - c), c
    if len(P) < JOGGLE_ABOVE:
        tri = Delaunay(P - c, qhull_options=QHULL_PLAIN)
        if not len(tri.coplanar):
            return tri, c
    Q = P - c
    try:
        tri = Delaunay(perturbed(Q), qhull_options=QHULL_PLAIN)
        if not len(tri.coplanar):
            return tri, c
    except QhullError:
        pass
    return Delaunay(Q, qhull_options=QHULL_OPTIONS), c


def perturbed(Q):
    """The points ``Q`` (centred on their bounding box) moved by the fixed, reproducible
    perturbation of :func:`delaunay` (the same points give the same moved points)."""
    wobble = np.random.default_rng(len(Q)).uniform(-1.0, 1.0, Q.shape)
    wobble *= PERTURBATION * float(np.abs(Q).max())
    wobble += Q
    return wobble


class SampleTriangulation:
    """The Delaunay triangulation (qhull) of the samples ``P`` labelled by their sites ``lab``.

    ``simp`` / ``nb``: triangles and their neighbours (``nb[t, k]`` across the side opposite
    vertex k, −1 on the hull; int32 when the indices fit); ``L``: labels of the corners; ``bich``:
    the sides with two labels; ``nlab``: 1, 2 or 3 labels (int8); ``cc``: circumcentres;
    ``seed``: per triangle, the refined vertex point of a 3-label triangle once known (NaN
    before), kept by :meth:`update` for unchanged triangles.

    ``L``, ``bich``, ``nlab`` and ``cc`` are functions of ``P``, ``lab`` and ``simp`` (``cc``
    elementwise in IEEE arithmetic: the same corners give the same bits, whichever triangulation
    computed them first), made on first use; :meth:`compact` drops them and keeps the seeds of
    the triangles that have one, for a triangulation kept after the construction (its size is
    then P, lab, simp and nb: 10⁴ random circles, 3·10⁵ triangles, 37 MB before, 11 MB after)."""

    def __init__(self, P, lab, simp=None, nb=None, cc=None, seed=None):
        self.P = P
        self.lab = lab
        if simp is None:
            tri, _ = delaunay(P)
            simp, nb = tri.simplices, tri.neighbors
        it = index_type(max(len(P), len(simp)) + 1)
        self.simp = np.asarray(simp, dtype=it)
        self.nb = np.asarray(nb, dtype=it)
        self._L = self._bich = self._nlab = None
        self._cc = cc
        self._seed = np.full((len(simp), 2), np.nan) if seed is None else seed
        self._seed_rows = None          # after compact(): (rows, values) of the seeds that are set
        self.walk_list = None
        #: edge polylines computed on this triangulation / on the previous one (reused when equal)
        self.edge_memo = None
        self.prior_edge_memo = None

    @property
    def L(self):
        if self._L is None:
            self._L = self.lab[self.simp]
        return self._L

    @property
    def bich(self):
        if self._bich is None:
            L = self.L
            # side k is opposite vertex k: labels L[:, k+1], L[:, k+2]
            self._bich = np.column_stack([L[:, (k + 1) % 3] != L[:, (k + 2) % 3] for k in range(3)])
        return self._bich

    @property
    def nlab(self):
        if self._nlab is None:
            nbi = self.bich.sum(axis=1)
            self._nlab = np.where(nbi == 0, 1, np.where(nbi == 3, 3, 2)).astype(np.int8)
        return self._nlab

    @property
    def cc(self):
        if self._cc is None:
            self._cc = circumcentres(*(self.P[self.simp[:, k]] for k in range(3)))
        return self._cc

    @property
    def seed(self):
        if self._seed is None:
            rows, values = self._seed_rows
            self._seed = np.full((len(self.simp), 2), np.nan)
            self._seed[rows] = values
            self._seed_rows = None
        return self._seed

    def compact(self) -> None:
        """Drop what is made again on first use (``L``, ``bich``, ``nlab``, ``cc``), the previous
        triangulation's polylines (``prior_edge_memo``: this triangulation's edges are made) and
        the rows of ``seed`` that are NaN (the others are kept with their bits); the results of
        every method are unchanged.  For the triangulation that a diagram keeps after its
        construction (:class:`runtime.voronoi.construction.ConstructionState`)."""
        self._L = self._bich = self._nlab = self._cc = None
        self.prior_edge_memo = self.walk_list = None
        if self._seed is not None:
            bits = self._seed.view(np.int64)
            rows = np.nonzero((bits != np.array(np.nan).view(np.int64)).any(axis=1))[0]
            self._seed_rows = (rows.astype(self.simp.dtype), self._seed[rows])
            self._seed = None

    def update(self, remove, Pnew, labnew):
        """The triangulation after removing the samples ``remove`` (indices) and inserting ``Pnew``
        (labels ``labnew``), by a batch Bowyer–Watson step (Bowyer 1981, Watson 1981); None when a
        full triangulation is needed (an extreme hull sample removed, a failed check).

        A triangle whose closed circumdisk holds no new sample and which has no removed corner
        keeps an empty open circumdisk, so it is a triangle of the new Delaunay triangulation.
        A hull side stays one unless a new sample lies on or beyond its line (the "ghost
        triangle" of the side, whose disk is the open half-plane beyond it, is then in conflict).
        Removed hull samples are allowed when they lie on the straight side between their hull
        neighbours (the samples of a segment on the hull): the hull polygon does not change.
        The rest (the *cavity*, with the area the hull gains) is re-triangulated by qhull from the
        cavity's remaining corners and the new samples; every new Delaunay triangle lies there and
        is Delaunay for these points.  The local triangles that fill the cavity are found by
        flooding the local triangulation, without crossing the cavity's boundary sides, from the
        local triangles on the inner side of those boundary sides and from the new samples.
        The result is checked: no side in more than two triangles, every sample a corner, each
        new side locally Delaunay with its two triangles on opposite sides of it (Delaunay's
        lemma: locally Delaunay everywhere is Delaunay), and one boundary that is the convex hull
        (its vertices on the hull of the samples, the triangles' area the hull's, Euler's count
        T = 2n − h − 2).  A cavity of more than :data:`CAVITY_MAX` samples is declined.  Points: kept samples in their order, then ``Pnew``; triangles: kept
        ones in their order, then the new ones."""
        P, simp, nb = self.P, self.simp, self.nb
        self._L = self._bich = self._nlab = None     # not read here: the peak of the update is lower
        n = len(P)
        Pnew = np.asarray(Pnew, float).reshape(-1, 2)
        rm = np.zeros(n, bool)
        rm[np.asarray(remove, dtype=np.int64)] = True
        if not (len(Pnew) or rm.any()):
            return None
        hull_t, hull_k = np.nonzero(nb == -1)
        ha, hb = simp[hull_t, (hull_k + 1) % 3], simp[hull_t, (hull_k + 2) % 3]
        scale = float(np.abs(P).max()) + 1.0
        if (rm[ha].any() or rm[hb].any()) and not _straight_on_hull(P, ha, hb, rm, scale):
            return None
        conflict = rm[simp].any(axis=1)
        visible = np.zeros(len(hull_t), bool)      # hull sides whose ghost triangle is in conflict
        if len(Pnew):
            rad = np.hypot(*(P[simp[:, 0]] - self.cc).T)
            fin = np.isfinite(rad)
            conflict |= ~fin
            reach = rad * (1 + 1e-9) + 1e-12 * scale              # the closed disk, with rounding room
            cand = np.nonzero(fin & _may_hold(self.cc, reach, Pnew))[0]
            cnt = cKDTree(Pnew).query_ball_point(self.cc[cand], reach[cand], return_length=True)
            conflict[cand[cnt > 0]] = True
            visible = _visible_sides(P, ha, hb, Pnew, scale)
            conflict[hull_t[visible]] = True
            conflict = _connected_cavity(P, simp, nb, conflict, rm, hull_t[visible], Pnew, scale)
        cav = np.nonzero(conflict)[0]
        U = np.unique(simp[cav])
        U = U[~rm[U]]
        if len(U) + len(Pnew) > CAVITY_MAX:
            return None
        g2l = np.full(n, -1)
        g2l[U] = np.arange(len(U))
        loc_pts = np.vstack([P[U], Pnew])
        try:
            loc, _ = delaunay(loc_pts)
        except Exception:  # noqa: BLE001 - qhull refuses (too few / flat points): full rebuild
            return None
        if len(loc.coplanar):
            return None          # a sample qhull left out: full rebuild
        # the cavity's boundary sides: towards kept triangles, or kept hull sides of the cavity
        tt, kk = np.repeat(cav, 3), np.tile(np.arange(3), len(cav))
        out_nb = nb[tt, kk]
        vis_side = np.zeros(nb.shape, bool)
        vis_side[hull_t[visible], hull_k[visible]] = True
        ga, gb = simp[tt, (kk + 1) % 3], simp[tt, (kk + 2) % 3]
        bnd = np.where(out_nb == -1, ~vis_side[tt, kk] & ~rm[ga] & ~rm[gb], ~conflict[np.maximum(out_nb, 0)])
        ga, gb, gc, gu = ga[bnd], gb[bnd], simp[tt[bnd], kk[bnd]], out_nb[bnd]
        a, b = g2l[ga], g2l[gb]
        m = len(loc_pts)
        bkeys = np.minimum(a, b) * m + np.maximum(a, b)
        ls, ln = loc.simplices.astype(np.int64), loc.neighbors     # keys below reach m² > 2³¹
        sk = np.stack([np.minimum(ls[:, (k + 1) % 3], ls[:, (k + 2) % 3]) * m
                       + np.maximum(ls[:, (k + 1) % 3], ls[:, (k + 2) % 3]) for k in range(3)], axis=1)
        cross = ~np.isin(sk, bkeys) & (ln >= 0)
        # the local triangles on each boundary side: the inner one (its third corner on the side of
        # the cavity triangle's third corner) seeds the flood, an outer one must stay out of it
        flat_keys = sk.ravel()
        order = np.argsort(flat_keys, kind="stable")
        lo_ = np.searchsorted(flat_keys, bkeys, sorter=order)
        hi_ = np.searchsorted(flat_keys, bkeys, side="right", sorter=order)
        if (hi_ == lo_).any() or (hi_ - lo_ > 2).any():
            return None          # a boundary side that the local triangulation does not have
        # the inner side of each boundary side: towards the cavity triangle's third corner or away
        # from the kept neighbour's, whichever is farther from the side's line (a sliver's corner
        # is a rounding away from it); a hull side's towards the centre of the hull's vertices
        A_, B_ = P[ga], P[gb]
        ref = _orient(A_, B_, P[gc])
        kept_nb = gu >= 0
        if kept_nb.any():
            w = gu[kept_nb]
            far = simp[w, np.argmax(nb[w] == tt[bnd][kept_nb][:, None], axis=1)]
            away = -_orient(A_[kept_nb], B_[kept_nb], P[far])
            ref[kept_nb] = np.where(np.abs(away) > np.abs(ref[kept_nb]), away, ref[kept_nb])
        if (~kept_nb).any():
            centre = P[np.unique(np.concatenate([ha, hb]))].mean(axis=0)
            ref[~kept_nb] = _orient(A_[~kept_nb], B_[~kept_nb], np.broadcast_to(centre, (int((~kept_nb).sum()), 2)))
        ref = np.sign(ref)
        tiny = 1e-12 * scale * np.hypot(*(B_ - A_).T)
        seeds, outer = [loc.vertex_to_simplex[len(U) + np.arange(len(Pnew))]], []
        for j in (0, 1):
            has = hi_ - lo_ > j
            f = order[np.where(has, lo_ + j, lo_)]
            lt, lk = f // 3, f % 3
            s = _orient(A_, B_, loc_pts[ls[lt, lk]]) * ref
            seeds.append(lt[has & (s > tiny)])
            outer.append(lt[has & (s < -tiny)])
        seeds, outer = np.concatenate(seeds), np.concatenate(outer)
        if (seeds < 0).any() or (seeds >= len(ls)).any():
            return None
        r, c = np.nonzero(cross)
        g = coo_matrix((np.ones(len(r)), (r, ln[r, c])), shape=(len(ls), len(ls)))
        _, comp = connected_components(g, directed=False)
        inside = np.isin(comp, np.unique(comp[seeds]))
        if inside[outer].any():
            return None          # the flood leaked out of the cavity
        # the new triangulation
        keep_pts = ~rm
        o2n = np.cumsum(keep_pts) - 1
        n_keep = int(keep_pts.sum())
        l2n = np.concatenate([o2n[U], n_keep + np.arange(len(Pnew))])
        kept_t = np.nonzero(~conflict)[0]
        simp2 = np.vstack([o2n[simp[kept_t]], l2n[ls[inside]]])
        n2 = n_keep + len(Pnew)
        nb2 = side_neighbours(simp2, n2)
        P2 = np.vstack([P[keep_pts], Pnew])
        cc2 = np.vstack([self.cc[kept_t], circumcentres(*(P2[simp2[len(kept_t):, k]] for k in range(3)))])
        if nb2 is None or not _valid(P2, simp2, nb2, len(kept_t), cc2, scale):
            return None
        lab2 = np.concatenate([self.lab[keep_pts], labnew])
        seed2 = np.vstack([self.seed[kept_t], np.full((int(inside.sum()), 2), np.nan)])
        out = SampleTriangulation(P2, lab2, simp2, nb2, cc2, seed2)
        out.prior_edge_memo = self.edge_memo
        return out

    def legalized(self, allow=None, rows=None):
        """This triangulation after Lawson's flips of its edges that are not locally Delaunay in
        exact arithmetic (:func:`runtime.voronoi.exact_delaunay.lawson_flips`, ``allow`` and
        ``rows`` as there: which illegal sides may be flipped, which triangles to examine);
        ``self`` when none is.  qhull and the batch
        update decide in floats: four samples co-circular within their roundoff (which grows with
        the samples' number and magnitude) may come back with either diagonal.  Flipped triangles
        get their circumcentres anew and no seed; the samples and their order are kept."""
        got = lawson_flips(self.P, self.simp, self.nb, allow, rows)
        if got is None:
            return self
        simp, nb, changed = got
        cc = self.cc.copy()
        cc[changed] = circumcentres(*(self.P[simp[changed, k]] for k in range(3)))
        seed = self.seed.copy()
        seed[changed] = np.nan
        out = SampleTriangulation(self.P, self.lab, simp, nb, cc, seed)
        out.prior_edge_memo = self.prior_edge_memo
        return out

    def walks(self, vectorised: bool = True):
        """The edges of the labelled triangulation: list of (pair, start, chain, end) where start /
        end are ("tri", t) for a 3-label triangle, ("hull", t, k) for the hull side k of triangle
        t, None for a closed chain (then start is None too), or ("bad", t) for a walk that could not
        be closed; chain = the 2-label triangles in order.

        Vectorised (:func:`runtime.voronoi.sample_walks.chain_walks`) unless a chain closes up or
        a neighbourhood is inconsistent; then step by step."""
        if vectorised:
            res = chain_walks(self)
            if res is not None and not len(res[1]):
                self.walk_list = res[0]
                return res[0]
        nlab = self.nlab
        nbl = self.nb.tolist()
        two = nlab == 2
        ks = np.argsort(~self.bich, axis=1, kind="stable")[:, :2]
        t_idx = np.arange(len(nlab))
        n1 = np.where(two, self.nb[t_idx, ks[:, 0]], -2).tolist()
        n2 = np.where(two, self.nb[t_idx, ks[:, 1]], -2).tolist()
        k1 = ks[:, 0].tolist()
        k2 = ks[:, 1].tolist()
        nl = nlab.tolist()
        L = self.L
        seen = [False] * len(nl)
        out = []

        def pair_of(t, k):
            a, b = int(L[t, (k + 1) % 3]), int(L[t, (k + 2) % 3])
            return (a, b) if a < b else (b, a)

        def walk(cur, k_in, start_t):
            chain = []
            while True:
                if nl[cur] == 3:
                    return chain, ("tri", cur)
                if seen[cur]:
                    return chain, (None if cur == start_t else ("bad", cur))
                seen[cur] = True
                chain.append(cur)
                k_out = k2[cur] if k1[cur] == k_in else k1[cur]
                nxt = nbl[cur][k_out]
                if nxt == -1:
                    return chain, ("hull", cur, k_out)
                if nl[nxt] == 2:
                    k_in = k1[nxt] if n1[nxt] == cur else k2[nxt]
                cur = nxt

        for t in np.nonzero(nlab == 3)[0].tolist():
            for k in range(3):
                u = nbl[t][k]
                if u == -1:
                    out.append((pair_of(t, k), ("tri", t), [], ("hull", t, k)))
                    continue
                if nl[u] == 3:
                    if u > t:
                        out.append((pair_of(t, k), ("tri", t), [], ("tri", u)))
                    continue
                if seen[u]:
                    continue
                chain, end = walk(u, k1[u] if n1[u] == t else k2[u], -1)
                out.append((pair_of(t, k), ("tri", t), chain, end))
        left = two & ~np.array(seen, dtype=bool)       # 2-label triangles not on a walk yet
        twos = np.nonzero(left & ((self.nb[t_idx, ks[:, 0]] == -1) | (self.nb[t_idx, ks[:, 1]] == -1)))[0].tolist()
        for t in twos:                      # chains from the hull to the hull
            if seen[t]:
                continue
            for nn, kk in ((n1[t], k1[t]), (n2[t], k2[t])):
                if nn == -1:
                    chain, end = walk(t, kk, -1)
                    out.append((pair_of(t, kk), ("hull", t, kk), chain, end))
                    break
        for t in np.nonzero(left)[0].tolist():      # closed chains around nested sites
            if seen[t]:
                continue
            chain, end = walk(t, k1[t], t)
            out.append((pair_of(t, k1[t]), None if end is None else ("bad", t), chain, end))
        self.walk_list = out
        return out


def circumcentres(A, B, C):
    bx, by = B[:, 0] - A[:, 0], B[:, 1] - A[:, 1]
    cx, cy = C[:, 0] - A[:, 0], C[:, 1] - A[:, 1]
    d = 2 * (bx * cy - by * cx)
    b2, c2 = bx * bx + by * by, cx * cx + cy * cy
    with np.errstate(divide="ignore", invalid="ignore"):
        ux = (cy * b2 - by * c2) / d
        uy = (bx * c2 - cx * b2) / d
    return np.column_stack([A[:, 0] + ux, A[:, 1] + uy])



def _areas(P, simp):
    A, B, C = (P[simp[:, k]] for k in range(3))
    return np.abs((B[:, 0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (B[:, 1] - A[:, 1]) * (C[:, 0] - A[:, 0])) / 2


def _orient(A, B, C):
    """Twice the signed area of the triangles (A, B, C) (rows)."""
    return (B[:, 0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (B[:, 1] - A[:, 1]) * (C[:, 0] - A[:, 0])


def _connected_cavity(P, simp, nb, conflict, rm, visible_t, Pnew, scale):
    """The conflict triangles joined through shared sides to a triangle that contains a new
    sample (closed, with rounding room), has a removed corner or lies on a visible hull side.
    In exact arithmetic the triangles whose circumdisks hold a point p form a connected set
    around the triangle containing p (Bowyer 1981, Watson 1981), so this is the whole cavity.
    A triangle flagged apart from all of them is in conflict only through rounding: a sliver of
    nearly collinear samples of one segment, whose huge circumdisk, widened by the rounding room,
    reaches a sample thousands of units away.  It is kept as it is (the result is checked as
    before); taking it into the cavity made the cavity disconnected and its flood leak."""
    idx = np.nonzero(conflict)[0]
    if not len(idx):
        return conflict
    T = simp[idx]
    seed = rm[T].any(axis=1) | np.isin(idx, visible_t)
    A, B, C = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    mid = (A + B + C) / 3
    reach = np.max(np.stack([np.hypot(*(X - mid).T) for X in (A, B, C)]), axis=0) + 1e-9 * scale
    area = _orient(A, B, C)
    room = 1e-12 * scale * (np.abs(area) / np.maximum(reach, 1e-300) + reach)
    tree = cKDTree(Pnew)
    for r, near in enumerate(tree.query_ball_point(mid, reach)):
        if seed[r] or not near:
            continue
        Q = Pnew[near]
        a, b, c = (np.broadcast_to(X[r], Q.shape) for X in (A, B, C))
        sg = 1.0 if area[r] >= 0 else -1.0
        inside = ((sg * _orient(a, b, Q) >= -room[r]) & (sg * _orient(b, c, Q) >= -room[r])
                  & (sg * _orient(c, a, Q) >= -room[r]))
        seed[r] = bool(inside.any())
    pos = np.full(len(simp), -1)
    pos[idx] = np.arange(len(idx))
    t, k = np.nonzero(nb[idx] >= 0)
    u = pos[nb[idx][t, k]]
    ok = u >= 0
    g = coo_matrix((np.ones(int(ok.sum())), (t[ok], u[ok])), shape=(len(idx), len(idx)))
    _, comp = connected_components(g, directed=False)
    keep = np.isin(comp, np.unique(comp[seed]))
    out = np.zeros(len(simp), bool)
    out[idx[keep]] = True
    return out


def _straight_on_hull(P, ha, hb, rm, scale) -> bool:
    """Every removed hull sample lies on the straight segment between its two hull neighbours
    (relative 10⁻⁹ of the angle, plus rounding): removing them leaves the hull polygon as it is."""
    ends = np.concatenate([ha, hb])
    other = np.concatenate([hb, ha])
    order = np.argsort(ends, kind="stable")
    ends, other = ends[order], other[order]
    first = np.searchsorted(ends, np.nonzero(rm)[0])
    v = np.nonzero(rm)[0]
    on = (first + 1 < len(ends)) & (ends[np.minimum(first, len(ends) - 1)] == v)
    v, first = v[on], first[on]
    if not len(v):
        return True
    if (ends[first + 1] != v).any() or ((first + 2 < len(ends)) & (ends[np.minimum(first + 2, len(ends) - 1)] == v)).any():
        return False              # a hull vertex not on exactly two hull sides
    u, w = P[other[first]], P[other[first + 1]]
    x = P[v]
    lu, lw = np.hypot(*(u - x).T), np.hypot(*(w - x).T)
    straight = np.abs(_orient(u, x, w)) <= 1e-9 * lu * lw + 1e-14 * scale * (lu + lw)
    between = np.einsum("ij,ij->i", u - x, w - x) < 0
    return bool((straight & between).all())


#: new samples times hull sides per block of :func:`_visible_sides`
VISIBLE_BLOCK = 4_000_000


def _visible_sides(P, ha, hb, Q, scale):
    """The hull sides (ha, hb) that a point of ``Q`` lies on or beyond (relative 10⁻¹² of the
    coordinates): their ghost triangles are in conflict.  Only the points that are not inside the
    hull by a margin of 10⁻⁹ of the coordinates are tested against every side."""
    hv = np.unique(np.concatenate([ha, hb]))
    H = P[hv]
    centre = H.mean(axis=0)               # inside the convex hull polygon
    try:
        eq = ConvexHull(H).equations
        worst = np.full(len(Q), -np.inf)
        for e in eq:
            np.maximum(worst, Q @ e[:2] + e[2], out=worst)
        near = np.nonzero(worst > -1e-9 * scale)[0]
    except QhullError:
        near = np.arange(len(Q))
    visible = np.zeros(len(ha), bool)
    if not len(near):
        return visible
    A, B = P[ha], P[hb]
    d = B - A
    s = np.sign(d[:, 0] * (centre[1] - A[:, 1]) - d[:, 1] * (centre[0] - A[:, 0]))
    tol = 1e-12 * scale * np.hypot(d[:, 0], d[:, 1])
    rows = max(1, VISIBLE_BLOCK // max(len(ha), 1))
    for k in range(0, len(near), rows):
        R = Q[near[k:k + rows]]
        side = s[:, None] * (d[:, 0:1] * (R[None, :, 1] - A[:, 1:2]) - d[:, 1:2] * (R[None, :, 0] - A[:, 0:1]))
        visible |= (side <= tol[:, None]).any(axis=1)
    return visible


def _valid(P, simp, nb, first_new, cc, scale) -> bool:
    """The checks of :meth:`SampleTriangulation.update` on its result (``simp[first_new:]`` the new
    triangles, ``cc`` the circumcentres): every point a corner; across each side of a new
    triangle, the neighbour's far corner on the other side of the side and the side locally
    Delaunay (relative 10⁻⁹); the boundary sides' vertices on the convex hull of the points,
    each on two boundary sides, T = 2n − h − 2 and the triangles' area the hull's."""
    n, T = len(P), len(simp)
    if np.bincount(simp.ravel(), minlength=n).min() == 0:
        return False
    t, k = np.nonzero(nb[first_new:] >= 0)
    t = t + first_new
    u = nb[t, k]
    ku = np.argmax(nb[u] == t[:, None], axis=1)
    if not (nb[u, ku] == t).all():
        return False
    A, B = P[simp[t, (k + 1) % 3]], P[simp[t, (k + 2) % 3]]
    X, Y = P[simp[t, k]], P[simp[u, ku]]
    sx, sy = _orient(A, B, X), _orient(A, B, Y)
    lab_ = np.hypot(*(B - A).T)
    tiny = 1e-12 * scale * lab_
    if ((sx > tiny) & (sy > tiny) | (sx < -tiny) & (sy < -tiny)).any():
        return False              # a fold: both triangles on one side of their common side
    # not locally Delaunay: each far corner inside the other triangle's circumdisk by more than
    # 10⁻⁹ of the coordinates and radius (one of the two is well conditioned unless the four
    # corners are nearly co-circular, a tie that the perturbation of qhull's input may break)
    def inside(tri, Z, W):
        rad = np.hypot(*(Z - cc[tri]).T)
        with np.errstate(invalid="ignore"):
            return np.hypot(*(W - cc[tri]).T) < rad - 1e-9 * (rad + scale)

    if (inside(t, X, Y) & inside(u, Y, X)).any():
        return False
    bt, bk = np.nonzero(nb == -1)
    bv = np.concatenate([simp[bt, (bk + 1) % 3], simp[bt, (bk + 2) % 3]])
    uv, cnt = np.unique(bv, return_counts=True)
    if (cnt != 2).any() or T != 2 * n - len(bt) - 2:
        return False
    try:
        H = ConvexHull(P[uv])
    except QhullError:
        return False
    off = (P[uv] @ H.equations[:, :2].T + H.equations[:, 2]).max(axis=1)
    if (off < -1e-9 * scale).any():
        return False              # a boundary vertex inside the hull
    return bool(abs(_areas(P, simp).sum() - H.volume) <= 1e-9 * max(H.volume, 1e-300))


def side_neighbours(simp, npts, dtype=np.int64):
    """``nb[t, k]``: the triangle across the side opposite corner k (−1: none); None when a side is
    shared by more than two triangles."""
    T = len(simp)
    a = np.concatenate([simp[:, (k + 1) % 3] for k in range(3)]).astype(np.int64)
    b = np.concatenate([simp[:, (k + 2) % 3] for k in range(3)]).astype(np.int64)
    key = np.minimum(a, b) * npts + np.maximum(a, b)
    del a, b
    # any order among equal keys: the two triangles of a side are set across from each other
    order = np.argsort(key)
    ks = key[order]
    del key
    same = ks[1:] == ks[:-1]
    del ks
    if (same[1:] & same[:-1]).any():
        return None
    nb = np.full(3 * T, -1, dtype=dtype)
    i = np.nonzero(same)[0]
    s1, s2 = order[i], order[i + 1]
    nb[s1] = s2 % T
    nb[s2] = s1 % T
    return nb.reshape(3, T).T.copy()


def _may_hold(cc, rad, Q):
    """A cheap superset of the disks (cc, rad) that may hold a point of Q: on a grid of cell
    h = 2 × the median radius, a disk of radius ≤ h can hold q only if the cells of its centre
    and of q are neighbours (|cc − q| ≤ h); larger disks (and centres off the grid) are kept."""
    fin = np.isfinite(rad)
    if not fin.any() or not len(Q):
        return np.ones(len(rad), bool)
    h = 2.0 * float(np.median(rad[fin]))
    lo = Q.min(axis=0) - 2 * h
    n = np.ceil((Q.max(axis=0) + 2 * h - lo) / h).astype(np.int64) + 1 if h > 0 else None
    if n is None or n[0] * n[1] > 4_000_000:
        return np.ones(len(rad), bool)
    grid = np.zeros((n[0] + 2, n[1] + 2), bool)
    gq = np.floor((Q - lo) / h).astype(np.int64) + 1
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            grid[gq[:, 0] + dx, gq[:, 1] + dy] = True
    with np.errstate(invalid="ignore"):
        g = np.floor((cc - lo) / h) + 1
    on = np.isfinite(g).all(axis=1) & (g[:, 0] >= 0) & (g[:, 1] >= 0) & (g[:, 0] < n[0] + 2) & (g[:, 1] < n[1] + 2)
    out = ~on | ~fin | (rad > h)
    gi = np.where(on[:, None], g, 0).astype(np.int64)
    out |= on & grid[gi[:, 0], gi[:, 1]]
    return out
