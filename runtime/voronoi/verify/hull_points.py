"""Step 4 of the certificate (:mod:`runtime.voronoi.verify.certificate`) for point sites, exactly:
the unbounded edges of the Voronoi diagram of points are those of the pairs consecutive on the
boundary of their convex hull, collinear boundary points included.

Public API: :func:`verify_accounting_points`.
"""
from __future__ import annotations

from fractions import Fraction

__all__ = ["verify_accounting_points"]


def verify_accounting_points(geoms, ends_inf, problems) -> bool:
    """Step 4 for point sites only, exactly (rational arithmetic, so collinear and co-linear hull
    points are decided, not approximated).  Far in direction d the nearest point maximises p·d,
    and among the points tied for the maximum (a side of the convex hull, d its outer normal) the
    nearest is the one whose coordinate along the side is closest; so the unbounded edges of the
    Voronoi diagram are exactly the bisectors of the pairs consecutive on the boundary of the
    convex hull, collinear boundary points included, each going to infinity along the side's outer
    normal (Preparata & Shamos, *Computational Geometry*, §5.5; for collinear points both sides of
    the degenerate hull).  The proved ends (pair, σ: direction σ·rot90(p_j − p_i)) must be exactly
    these, each once."""
    pts = [(Fraction(int(g.exact.cx.p), int(g.exact.cx.q)), Fraction(int(g.exact.cy.p), int(g.exact.cy.q)))
           for g in geoms]
    n = len(pts)
    if n < 2:
        return True
    order = sorted(range(n), key=lambda k: pts[k])

    def cross(o, a, b):
        return ((pts[a][0] - pts[o][0]) * (pts[b][1] - pts[o][1])
                - (pts[a][1] - pts[o][1]) * (pts[b][0] - pts[o][0]))

    def chain(seq):
        out: list = []
        for k in seq:
            while len(out) >= 2 and cross(out[-2], out[-1], k) < 0:     # keep collinear points
                out.pop()
            out.append(k)
        return out

    lower, upper = chain(order), chain(order[::-1])
    boundary = lower[:-1] + upper[:-1]            # counter-clockwise, collinear points kept
    want: dict = {}
    for t in range(len(boundary)):
        a, b = boundary[t], boundary[(t + 1) % len(boundary)]
        i, j = min(a, b), max(a, b)
        # outer normal of the side a → b (ccw boundary: the interior on the left) vs rot90(p_j − p_i)
        ox, oy = pts[b][1] - pts[a][1], -(pts[b][0] - pts[a][0])
        rx, ry = -(pts[j][1] - pts[i][1]), pts[j][0] - pts[i][0]
        key = (i, j, 1 if ox * rx + oy * ry > 0 else -1)
        want[key] = want.get(key, 0) + 1
    got: dict = {}
    ids: dict = {}
    for _, pair, sigma, eid in ends_inf:
        key = (int(pair[0]), int(pair[1]), int(sigma))
        got[key] = got.get(key, 0) + 1
        ids.setdefault(key, eid)
    ok = True
    for key in sorted(set(want) | set(got)):
        w, g = want.get(key, 0), got.get(key, 0)
        if w == g:
            continue
        ok = False
        i, j, sg = key
        if g < w:
            problems.append(f"sites {i}, {j}: consecutive on the convex hull of the points, but no proved "
                            "unbounded edge between them goes out across that side")
        else:
            problems.append(f"edge {ids[key]} (sites {i}, {j}): an unbounded end that the convex hull of the "
                            "points does not have" + (" (reported more than once)" if w else ""))
    return ok
