"""The edge walks of the labelled sample triangulation, vectorised by list ranking.

A triangle with two labels {i, j} has exactly two bichromatic sides (its two *ports*); the
2-label triangles therefore form chains, each an approximation of one Voronoi edge (i, j), that
end at 3-label triangles (candidate vertices), at the hull (unbounded edges), or close up (a
vertex-less edge around a nested site, thesis Prop. 1.2.1).  Here each chain is found with
numpy instead of a step-by-step walk: the *half-edges* "leave triangle t through port p" form
disjoint directed paths (successor: the neighbour across port p, left through its other port),
and pointer jumping (Wyllie's list ranking, JáJá, *An Introduction to Parallel Algorithms* §3.1)
gives every half-edge its path end and its distance to it in O(log length) vectorised rounds.
Each undirected chain is reported once, from its end that a scan of the 3-label triangles (then
of the 2-label triangles) meets first, in that scan's order, as a step-by-step walk would.
Closed chains (no end) and inconsistent neighbourhoods are left to the caller.

The half-edge arrays are int32 when the triangles allow (:func:`index_type`) and the ports one byte
each: at 8·10⁵ triangles (3·10⁴ random circles) they are the bulk of the walks' temporary memory.

Public API: :func:`chain_walks`, :func:`index_type`.
"""
from __future__ import annotations

import numpy as np

__all__ = ["chain_walks", "index_type"]

#: the two ports of a triangle by its pattern of bichromatic sides (side k two-coloured: bit k):
#: the first two sides in the order of ``np.argsort(~bichromatic, kind="stable")``
PORTS = np.array([np.argsort([not (code >> k) & 1 for k in range(3)], kind="stable")[:2] for code in range(8)],
                 dtype=np.int8)


def index_type(n: int):
    """int32 when indices below ``n`` fit (half the memory of int64 for the half-edge arrays), else
    int64."""
    return np.int32 if n < 2 ** 31 - 1 else np.int64


def chain_walks(tri):
    """The walks of :meth:`runtime.voronoi.sample_delaunay.SampleTriangulation.walks` that are not
    closed chains, as (walks, triangles on closed chains); None when a neighbourhood is not
    consistent (the caller then walks step by step)."""
    nb, nlab, L = tri.nb, tri.nlab, tri.L
    T = len(nlab)
    it = index_type(2 * T)
    two = nlab == 2
    # the two ports of a 2-label triangle (side numbers 0..2: one byte each)
    bich = tri.bich
    ks = PORTS[bich[:, 0] + 2 * bich[:, 1].astype(np.int8) + 4 * bich[:, 2].astype(np.int8)]
    nbr = np.take_along_axis(nb, ks.astype(np.intp), axis=1).astype(it)
    # half-edge h = 2t + p leaves t through port p; its successor leaves the neighbour u through the
    # port that does not face t
    h_all = np.nonzero(np.repeat(two, 2))[0].astype(it)
    t_h, p_h = h_all // 2, h_all % 2
    u = nbr[t_h, p_h]
    nxt = np.full(2 * T, -1, dtype=it)
    cont = (u >= 0) & two[np.maximum(u, 0)]
    uc = u[cont]
    facing0 = nbr[uc, 0] == t_h[cont]
    facing1 = nbr[uc, 1] == t_h[cont]
    if (facing0 == facing1).any():
        return None
    nxt[h_all[cont]] = 2 * uc + np.where(facing0, 1, 0)
    # pointer jumping: end (last half-edge) and distance to it
    endp = np.where(nxt >= 0, nxt, np.arange(2 * T, dtype=it))
    dist = (nxt >= 0).astype(it)
    for _ in range(int(np.log2(2 * T + 1)) + 2):
        nd = endp[endp]
        if np.array_equal(nd, endp):
            break
        dist = dist + dist[endp]
        endp = nd
    done = nxt[endp] < 0                      # reached an end (the others are on closed chains)
    cyc_t = np.unique(t_h[~done[h_all]])
    hs = h_all[done[h_all]]
    has_pred = np.zeros(2 * T, bool)
    has_pred[nxt[nxt >= 0]] = True
    heads = hs[~has_pred[hs]]
    # the start of a path: g = head ^ 1 leaves its first triangle through the side it was entered
    # by.  Key of a start: (0, u, k) for the side k of a 3-label triangle u, (1, t, p) for the hull
    # port p of triangle t.  Each chain is reported once, from the start with the smaller key (the
    # order of a scan of the 3-label triangles and their sides, then of the 2-label triangles)
    g = heads ^ 1
    gt, gp = g // 2, g % 2
    su = nbr[gt, gp]
    on_hull = su < 0
    s_side = np.where(on_hull, gp, _side_towards(nb, np.maximum(su, 0), gt))
    key = np.stack([on_hull.astype(np.int64), np.where(on_hull, gt, su), s_side], axis=1)
    pos = np.full(2 * T, -1, dtype=it)
    pos[heads] = np.arange(len(heads))
    other = pos[endp[heads] ^ 1]                  # the head of the reverse path
    kk, ko = key, key[other]
    first = (kk[:, 0] < ko[:, 0]) | ((kk[:, 0] == ko[:, 0]) & ((kk[:, 1] < ko[:, 1]) | (
        (kk[:, 1] == ko[:, 1]) & (kk[:, 2] < ko[:, 2]))))
    keep_heads = heads[first]
    walks, keys = [], [np.zeros((0, 3), np.int64)]       # the walks and their scan keys
    if len(keep_heads):
        members = hs[np.isin(endp[hs], endp[keep_heads])]
        order = np.lexsort((-dist[members], endp[members]))
        members = members[order]
        cuts = np.nonzero(np.diff(endp[members]))[0] + 1
        bounds = np.concatenate([[0], cuts, [len(members)]]).tolist()
        tris = (members // 2).tolist()
        hd = members[bounds[:-1]]
        c0 = hd // 2
        k0 = ks[c0, 0]
        la, lb = L[c0, (k0 + 1) % 3], L[c0, (k0 + 2) % 3]
        pairs = zip(np.minimum(la, lb).tolist(), np.maximum(la, lb).tolist())
        starts, ends = _terminals(hd ^ 1, nbr, ks), _terminals(endp[hd], nbr, ks)
        walks = [(pr, s, tris[bounds[m]:bounds[m + 1]], e) for m, (pr, s, e) in enumerate(zip(pairs, starts, ends))]
        keys.append(key[pos[hd]])
    # 3-label triangles next to a 3-label triangle or to the hull: edges without chain triangles
    t3, k3 = np.nonzero((nlab == 3)[:, None] & np.ones((1, 3), bool))
    u3 = nb[t3, k3]
    direct = (u3 == -1) | ((u3 > t3) & (nlab[np.maximum(u3, 0)] == 3))
    for t, k, v in zip(t3[direct].tolist(), k3[direct].tolist(), u3[direct].tolist()):
        a, b = int(L[t, (k + 1) % 3]), int(L[t, (k + 2) % 3])
        walks.append(((a, b) if a < b else (b, a), ("tri", t), [], ("hull", t, k) if v == -1 else ("tri", v)))
    keys.append(np.column_stack([np.zeros(int(direct.sum()), np.int64), t3[direct], k3[direct]]))
    K = np.concatenate(keys)
    order = np.lexsort((K[:, 2], K[:, 1], K[:, 0]))       # stable, as the scan meets the starts
    return [walks[m] for m in order.tolist()], cyc_t


def _terminals(h, nbr, ks):
    """Where the half-edges h (path ends) lead: ("tri", u) for a 3-label neighbour u, ("hull", t, k)
    for the hull side k of their triangle t."""
    t, p = h // 2, h % 2
    u, k = nbr[t, p], ks[t, p]
    return [("hull", a, c) if b < 0 else ("tri", b) for a, b, c in zip(t.tolist(), u.tolist(), k.tolist())]


def _side_towards(nb, u, t):
    """The side k of triangle u[m] whose neighbour is t[m] (vectorised)."""
    return np.argmax(nb[u] == t[:, None], axis=1)
