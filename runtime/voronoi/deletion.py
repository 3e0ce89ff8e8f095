"""Deletion of a site from a Voronoi diagram: locally, re-proving only what changed.

**Points, circles and ellipses** (thesis §1.2; Karavelas & Yvinec, ESA 2002, for the deletion in
additively weighted Voronoi diagrams, CGAL's ``Apollonius_graph_2::remove``; disjoint convex sites
form an abstract Voronoi diagram, Klein, Mehlhorn & Meiser, CGTA 3 (1993), where the same holds): the region of site i is shared
among its Delaunay neighbours and nothing else changes.  The vertices of i (their circles touch i)
and the edges of i and at those vertices are removed; for circles and points the diagram of i's
neighbours inside i's old region is first built directly (:mod:`runtime.voronoi.hole_region`),
else (or when that candidate does not close or is not proved) the diagram of i's neighbours and
their neighbours is built and its vertices inside i's old region (their circles reach site i) and
the edges ending there are spliced in (:func:`runtime.voronoi.insertion.delete_local`).  Why the kept
part keeps its proof: a kept vertex's circle was empty of all the old sites, so of the remaining
ones; a kept edge was a whole edge of the old diagram (every point strictly closer to its two sites
than to any other old site, ends at vertices), and neither end is a removed vertex, so it is a
whole edge of the new diagram; the new vertices and edges and the closure at the vertices whose
edges changed are proved now, against every site that can reach them.  At infinity nothing changes
when i had no unbounded edge (its support function was strictly below the others' maximum in every
direction, by the old proof); otherwise every unbounded edge is proved again against all sites and
the accounting at infinity is redone with the verifier's routines.  ``certified`` is True only
when the original diagram was certified and the changed part is proved.
``stats["deletion"]``: "local", "local, unbounded edges and accounting at infinity re-proved" or,
when the local splice does not apply (parabola or hyperbola sites, nested sites, fewer than 5 sites, a far scene,
a splice that does not close or is not proved), the sample-based route below.

**Sample-based route** (every site kind), updating the sample triangulation locally.

When site i is deleted, its region is shared among its Delaunay neighbours and nothing else
changes (thesis §1.2: a point's nearest sites among the others are unchanged unless its nearest
site was i).  The construction (:mod:`runtime.voronoi.construction`) is sample-based, so the
deletion works on the samples: the samples of i are removed from the sample Delaunay
triangulation by a local Bowyer–Watson step
(:meth:`runtime.voronoi.sample_delaunay.SampleTriangulation.update`: only the triangles with a
corner on site i are re-triangulated, from their other corners), the refined vertex points and
the edge polylines of the unchanged triangles are kept, and the usual rounds run from there: every
vertex is proved again (existence and emptiness among the remaining sites), every vertex must
have its three edges, and failures refine the sampling locally, exactly as in a construction
from scratch.  The result is therefore the diagram :func:`runtime.voronoi.construction.voronoi`
would certify for the remaining sites, with the same guarantees.

The remaining samples are re-triangulated by qhull (the rounds still reuse them) when a sample
of site i is a vertex of the sample hull (removing it changes the hull: the local step declines);
point sites only are rebuilt from scratch (their collinear case has its own path).  A diagram
read from JSON has no construction state: :class:`ValueError` (build it with ``voronoi`` first).

Indices: by default (``renumber="shift"``) the remaining sites are **renumbered** — site j > i
becomes j − 1 — so the result is exactly the diagram of ``sites[:i] + sites[i+1:]``; relabelling
every vertex and edge with a site above i costs O(N).  With ``renumber="last"`` the last site
N − 1 takes index i (the diagram of ``sites[:i] + [sites[-1]] + sites[i+1:-1]``), and only its own
vertices and edges are relabelled.  Vertex and edge ids stay their positions in the lists (a
removed one's slot takes a new one or the last one), so ids of kept parts may change.

Public API: :func:`delete_site`.
"""
from __future__ import annotations

import dataclasses
import time

import numpy as np

from ..threads import one_blas_thread
from .insertion import delete_local
from .sample_delaunay import SampleTriangulation
from .sampling import Samples
from .site_arrays import SiteArrays

__all__ = ["delete_site"]


@one_blas_thread
def delete_site(diagram, i: int, *, certify: bool = True, renumber: str = "shift", inplace: bool = False):
    """The Voronoi diagram of ``diagram``'s sites without site ``i`` (``renumber="shift"``: j > i
    becomes j − 1; ``"last"``: site N − 1 becomes i); ``diagram`` is left unchanged, or with
    ``inplace=True`` it is updated and returned (no copy of its lists when the deletion is local).
    ``stats["deletion"]`` says "local" or "local, unbounded edges and accounting at infinity
    re-proved" (points, circles, ellipses: module docstring), "local sample triangulation" (the sample
    triangulation updated around site i, all vertices proved again), "local triangulation
    declined" (samples re-triangulated by qhull, the rounds reused) or "rebuild".  The construction functions come from the diagram's state
    (:class:`runtime.voronoi.construction.ConstructionState`)."""
    n = len(diagram.sites)
    i = int(i)
    if not 0 <= i < n:
        raise IndexError(f"no site {i}: the diagram has {n} sites")
    if renumber not in ("shift", "last"):
        raise ValueError(f'renumber must be "shift" or "last", not {renumber!r}')
    if n - 1 < 2:
        raise ValueError(f"the Voronoi diagram needs at least 2 sites, {n - 1} would remain")
    st = diagram.construction
    if st is None:
        raise ValueError("this diagram has no construction state (read from JSON?): build the diagram of the "
                         "remaining sites with voronoi(...)")
    local = delete_local(diagram, i, certify=certify, renumber=renumber, inplace=inplace)
    if local is not None:
        return local
    out = _delete_by_construction(diagram, st, i, n, certify, renumber)
    if inplace:
        for f in dataclasses.fields(diagram):
            setattr(diagram, f.name, getattr(out, f.name))
        return diagram
    return out


def _delete_by_construction(diagram, st, i, n, certify, renumber):
    """The sample-based route of the module docstring (or a rebuild)."""
    rest = [s for k, s in enumerate(diagram.sites) if k != i]
    if renumber == "last" and i < n - 1:
        rest = list(diagram.sites[:i]) + [diagram.sites[-1]] + list(diagram.sites[i + 1:-1])
    if st.samples is None or st.samples.tri is None or (renumber == "last" and i < n - 1):
        D = st.scratch(rest, certify=certify)
        D.stats["deletion"] = "rebuild"
        return D
    t_start = time.perf_counter()
    S = st.S
    keep = np.ones(n, bool)
    keep[i] = False
    new_index = np.cumsum(keep) - 1
    new_index[i] = -1
    S2 = SiteArrays(rest, [g for k, g in enumerate(S.geoms) if k != i])
    if S2.all_circles and not S2.R.any():
        D = st.scratch(rest, certify=certify)      # points only: the collinear case needs its own path
        D.stats["deletion"] = "rebuild"
        return D
    old = st.samples
    samples = Samples(S2, old.spacing[keep])
    if old.base is not None:
        samples.base = old.base[keep]
    tri = old.tri.update(np.nonzero(old.tri.lab == i)[0], np.zeros((0, 2)), np.zeros(0, np.int64))
    how = "local triangulation declined"
    if tri is not None:
        moved = SampleTriangulation(tri.P, new_index[tri.lab], tri.simp, tri.nb, tri.cc, tri.seed)
        moved.prior_edge_memo = tri.prior_edge_memo
        samples.tri, samples.sampled = moved, old.sampled[keep].copy()
        how = "local sample triangulation"
    cache = {}
    for tr, found in st.cache.items():
        if i not in tr:
            t2 = tuple(int(new_index[t]) for t in tr)
            cache[t2] = [dict(c, triple=t2) for c in found]
    stats: dict = {"sites": len(rest), "rounds": 0, "samples": 0, "deletion": how}
    timing = {"input": time.perf_counter() - t_start}
    return st.build(S2, samples, cache, [], stats, timing, certify=certify, t_start=t_start)
