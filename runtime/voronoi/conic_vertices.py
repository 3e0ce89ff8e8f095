"""Voronoi vertices of triples with a conic: a batched proof, else one refinement and one proof per vertex.

Candidate seeds come from the 3-label triangles of the sample triangulation (thesis §5.2: a
vertex is a point equidistant from three sites with an empty circle).  A candidate within a
quarter radius of exactly one vertex of its triple proved in an earlier round takes that proof;
all other candidates of convex sites are first proved at once by the kernel's Krawczyk test on
the distance differences
(:func:`runtime.voronoi.verify.conic_vertices.prove_conic_vertices`, vectorised: a unique zero of
(d_i − d_j, d_i − d_k) in a small square, with its radius enclosed); the others are refined by
``refine_vertex`` and proved by ``certify_vertex`` of :mod:`runtime.voronoi.vertex` (arb Krawczyk on
the foot-point system), one at a time.  Candidates of one triple are merged only when one proof
box holds the other.

Public API: :func:`conic_vertices`.
"""
from __future__ import annotations

import math

import numpy as np

from .apollonius_vertices import newton_vertices
from .site_arrays import SiteArrays
from .verify.conic_vertices import prove_conic_vertices

__all__ = ["conic_vertices"]


def _vertex_generic(S: SiteArrays, triple, seed, stats):
    """Refine and prove one vertex of a triple with a conic (runtime.voronoi.vertex)."""
    try:
        from .vertex import certify_vertex, refine_vertex
    except ImportError:
        return None
    geoms = [S.geoms[t] for t in triple]
    sites = [S.sites[t] for t in triple]
    stats["triple_solves"] = stats.get("triple_solves", 0) + 1
    try:
        r = refine_vertex(geoms, float(seed[0]), float(seed[1]))
    except Exception as exc:  # noqa: BLE001 - a failed refinement is a problem, not a crash
        stats.setdefault("vertex_errors", []).append(f"{triple}: {exc}")
        return None
    if r is None:
        return None
    x, y, _ = r
    try:
        pf = certify_vertex(sites, geoms, x, y)
    except Exception as exc:  # noqa: BLE001
        stats.setdefault("vertex_errors", []).append(f"{triple}: {exc}")
        return None
    if pf.box is None or not pf.certified:
        return {"triple": tuple(triple), "x": float(x), "y": float(y), "ok": False, "rlo": 0.0, "rhi": 0.0,
                "h": 0.0, "exact": None, "reason": getattr(pf, "reason", "")}
    (xlo, xhi), (ylo, yhi) = pf.box
    return {"triple": tuple(triple), "x": pf.x, "y": pf.y, "ok": bool(pf.certified),
            "rlo": float(pf.radius_bounds[0]), "rhi": float(pf.radius_bounds[1]),
            "box": ((xlo, xhi), (ylo, yhi)), "h": max(xhi - xlo, yhi - ylo) / 2, "exact": None,
            "radius": pf.radius, "reason": getattr(pf, "reason", "")}


def _batch_vertex(triple, proof):
    """The cluster of a vertex proved by the batched test: (x, y, h, r_lo, r_hi), a unique zero of
    the distance differences in the square of centre (x, y) and half-width h."""
    x, y, h, rlo, rhi = proof
    return {"triple": tuple(triple), "x": x, "y": y, "ok": True, "rlo": rlo, "rhi": rhi,
            "box": ((math.nextafter(x - h, -math.inf), math.nextafter(x + h, math.inf)),
                    (math.nextafter(y - h, -math.inf), math.nextafter(y + h, math.inf))),
            "h": h, "exact": None, "radius": 0.5 * (rlo + rhi), "reason": ""}


def conic_vertices(S: SiteArrays, T3, seeds, stats, cache):
    """Candidates of triples with a conic, one proof per vertex.  ``cache`` (triple -> proved
    vertices of earlier rounds) is reused when a seed lies within a quarter of the radius of exactly
    one proved vertex of its triple."""
    cid = np.full(len(T3), -1)
    clusters = []
    by_triple: dict = {}
    start = np.asarray(seeds, float).copy()
    started = np.zeros(len(T3), bool)
    fin = np.abs(S.boxes[np.isfinite(S.boxes)])
    scale = 1.0 + (float(fin.max()) if len(fin) else 0.0)
    table = S.site_table() if len(T3) else None

    def batch(rows):
        """The batched proofs of the candidates ``rows`` (each row's proof depends on that row only)."""
        _newton_starts(S, T3, start, started, rows)
        return prove_conic_vertices(S.geoms, T3[rows], start[rows], scale, table=table)

    # the batched proofs of the candidates that the cache of earlier rounds does not serve (a seed
    # within a quarter radius of exactly one proved vertex of its triple); a candidate found
    # unserved after all (the cache grew in this round) is proved when met
    trs = [tuple(t) for t in np.asarray(T3, np.int64).reshape(-1, 3).tolist()]
    seed_list = np.asarray(seeds, float).reshape(-1, 2).tolist()
    near0 = [_cache_near(cache, tr, sd) for tr, sd in zip(trs, seed_list)]
    known = {tr: len(cache.get(tr, ())) for tr in trs}        # cache entries when near0 was listed
    quick = [False] * len(T3)
    want = [m for m in range(len(T3)) if len(near0[m]) != 1]
    # a candidate whose triple has another candidate is compared with that one's proof box
    # through its Newton point as well
    _newton_starts(S, T3, start, started, _repeated_triples(T3))
    for m, q in zip(want, batch(np.array(want, dtype=np.int64)) if want else []):
        quick[m] = q
    for m in range(len(T3)):
        tr = trs[m]
        found = None
        for c in by_triple.get(tr, []):
            cl = clusters[c]
            if cl["ok"] and "box" in cl:
                (xlo, xhi), (ylo, yhi) = cl["box"]
                if any(xlo <= p[0] <= xhi and ylo <= p[1] <= yhi for p in (seeds[m], start[m])):
                    found = c
                    break
        if found is None:
            near = near0[m] if len(cache.get(tr, ())) == known[tr] else _cache_near(cache, tr, seed_list[m])
            if len(near) == 1:
                cl = dict(near[0])
                stats["vertex_cache_hits"] = stats.get("vertex_cache_hits", 0) + 1
            else:
                if quick[m] is False:
                    quick[m] = batch(np.array([m], dtype=np.int64))[0]
                if quick[m] is not None:
                    cl = _batch_vertex(tr, quick[m])
                else:
                    cl = _vertex_generic(S, tr, start[m], stats)
                if cl is not None and cl["ok"]:
                    cache.setdefault(tr, []).append(dict(cl))
            if cl is None:
                cl = {"triple": tr, "x": float(seeds[m, 0]), "y": float(seeds[m, 1]), "ok": False,
                      "rlo": 0.0, "rhi": 0.0, "h": 0.0, "exact": None}
            # same triple, box overlapping a proved box: same vertex only if one box holds the other
            for c in by_triple.get(tr, []):
                o = clusters[c]
                if o["ok"] and cl["ok"] and _box_contains(o["box"], cl["box"]):
                    found = c
                    break
                if o["ok"] and cl["ok"] and _box_contains(cl["box"], o["box"]):
                    clusters[c] = dict(cl, members=o["members"])
                    found = c
                    break
            if found is None:
                cl["members"] = []
                found = len(clusters)
                clusters.append(cl)
                by_triple.setdefault(tr, []).append(found)
        clusters[found].setdefault("members", []).append(m)
        cid[m] = found
    return cid, clusters


def _newton_starts(S: SiteArrays, T3, start, started, rows):
    """Vectorised Newton on d_a = d_b = d_c (:func:`runtime.voronoi.apollonius_vertices.newton_vertices`,
    the distances of all ellipses at once) from the seeds ``start[rows]`` not yet ``started``,
    in place: the per-vertex proofs then start at a converged point.  A point that left the
    seed's neighbourhood (beyond the distance to the sites) is not used.  Newton moves each row
    on its own data, so a row's point does not depend on the other rows of the call."""
    rows = np.asarray(rows, dtype=np.int64)
    rows = rows[~started[rows]]
    if not len(rows):
        return
    started[rows] = True
    seed = start[rows]
    Q, _ = newton_vertices(S, T3[rows], seed)
    dseed, _ = S.dist_grad(seed, T3[rows, 0])
    good = np.isfinite(Q).all(axis=1) & (np.hypot(*(Q - seed).T) <= dseed + 1e-12 * S.scale)
    start[rows[good]] = Q[good]


def _repeated_triples(T3):
    """The rows of ``T3`` whose triple occurs in another row as well."""
    if not len(T3):
        return np.zeros(0, np.int64)
    _, inv, counts = np.unique(np.asarray(T3, np.int64).reshape(-1, 3), axis=0, return_inverse=True,
                               return_counts=True)
    return np.nonzero(counts[inv.ravel()] > 1)[0]


def _cache_near(cache, tr, seed):
    """The proved vertices of triple ``tr`` in ``cache`` within a quarter of their radius of ``seed``."""
    return [c for c in cache.get(tr, ()) if math.hypot(c["x"] - seed[0], c["y"] - seed[1]) < 0.25 * c["rlo"]]


def _box_contains(a, b):
    (axl, axh), (ayl, ayh) = a
    (bxl, bxh), (byl, byh) = b
    return axl <= bxl and bxh <= axh and ayl <= byl and byh <= ayh

