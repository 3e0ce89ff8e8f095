"""Contact order and emptiness of a proved vertex (step 2 of :mod:`runtime.segments.certificate`).

**Order**: the contact point of each listed site seen from the vertex — a point, the foot on a
segment, c + ρ (v − c)/|v − c| on an arc, the foot e(φ(v)) on an elliptic piece, the end e (or smooth joint) where a curve touches at
its end — must turn once counter-clockwise in the listed order (the angles between consecutive
contacts, each in (0, 2π), sum to 2π).  Two consecutive sites sharing a contact (an end and its
curve, the two curves of a joint) are ordered by the side the curve leaves the contact to (after
when it leaves counter-clockwise around the vertex); for k = 3 every pair is consecutive anyway.

**Emptiness**: every other site is strictly farther than the radius (rigorous balls after a k-d
tree and a float filter), except a curve ending at a listed point e whose nearest point is e
alone, strictly beyond it (the foot beyond e, an arc's direction in the half of its gap next to
e, an elliptic piece's distance increasing away from e and above it on the rest; an elliptic piece
with both ends listed may have its two ends as nearest points: they own the tie), or an arc whose direction from its centre is strictly in its gap (its nearest points are
ends; an end at the radius that is not listed is a site or a joint whose other curve the same
check finds too close): the tie is the ends'.

Public API: :func:`ccw`, :func:`empty`.
"""
from __future__ import annotations

import numpy as np
from flint import arb

from ..certify.foot import to_arb
from ..voronoi.verify.problems import Problem, fault
from .certificate_ellipses import contact_point, owned_by_both_ends
from .certificate_float_bounds import bounds_at
from .certificate_sites import ARC, ELLIPSE, SEGMENT, SiteTable, hypot

__all__ = ["ccw", "empty"]


def _contacts(T: SiteTable, sites, terms, X, Y):
    """Per listed site: (x, y, tie key, leaving direction or None)."""
    out = []
    for s, t in zip(sites, terms):
        if t[0] == "pt":
            if t[3] is None:
                ax, ay = T.arb_ends(s)[:2]
                out.append((ax, ay, s, None))
            else:
                code, curve = t[3]
                jx, jy = T.pt_arb(code)
                out.append((jx, jy, code, T.leaving(curve, code)))
        elif t[0] == "ln":
            ax, ay, bx, by = T.arb_ends(s)
            u = T.foot(s, X, Y)
            out.append((ax + u * (bx - ax), ay + u * (by - ay), None, None))
        elif t[0] == "arc":
            cx, cy, rho = T.arb_arc(s)
            wx, wy = X - cx, Y - cy
            n = hypot(wx, wy)
            out.append((cx + rho * wx / n, cy + rho * wy / n, None, None))
        elif t[0] == "el":
            ex, ey = contact_point(T.piece[s], X, Y)
            out.append((ex, ey, None, None))
        else:
            e = t[5]
            ex, ey = T.pt_arb(e)
            out.append((ex, ey, e, T.leaving(s, e)))
    return out


def ccw(T: SiteTable, sites, terms, X, Y) -> bool:
    k = len(sites)
    C = _contacts(T, sites, terms, X, Y)
    total = arb(0)
    two_pi = 2 * arb.pi()
    for m in range(k):
        c, c2 = C[m], C[(m + 1) % k]
        if c[2] is not None and c[2] == c2[2]:
            if k >= 4:
                side = []
                for d in (c, c2):
                    if d[3] is None:
                        side.append(0)
                        continue
                    lx, ly = to_arb(d[3][0]), to_arb(d[3][1])
                    cr = (d[0] - X) * ly - (d[1] - Y) * lx
                    side.append(1 if cr > 0 else (-1 if cr < 0 else None))
                if None in side or not side[0] < side[1]:
                    return False
            continue
        ux, uy, vx, vy = c[0] - X, c[1] - Y, c2[0] - X, c2[1] - Y
        cr = ux * vy - uy * vx
        dt = ux * vx + uy * vy
        if cr > 0:
            total += arb.atan2(cr, dt)
        elif cr < 0:
            total += arb.atan2(cr, dt) + two_pi
        elif dt < 0:
            total += arb.pi() + (cr / dt).atan()
        else:
            return False
    return bool(total < 2 * two_pi)


def empty(T: SiteTable, v, sites, X, Y, R, problems, name: str) -> bool:
    listed = set(sites)
    cx, cy = float(X.mid()), float(Y.mid())
    rad = float(X.rad()) + float(Y.rad())
    r_hi = float(R.upper())
    cand = [k for k in T.near(cx, cy, r_hi + 2 * rad) if k not in listed]
    if not cand:
        return True
    b = bounds_at(T, cand, cx, cy)
    if b is None:
        lo = T.float_bounds(np.array(cand, dtype=int), np.repeat([[cx, cy]], len(cand), axis=0))[0].tolist()
    else:
        lo = b[0]
    limit = r_hi * (1 + 1e-12) + 1e-300
    clear = [t - 2 * rad > limit for t in lo]
    ok = True
    for k, c in zip(cand, clear):
        if c:
            continue
        if T.kind[k] in (SEGMENT, ARC, ELLIPSE):
            le = [e for e in T.ends[k] if e >= 0 and e in listed]
            if le:
                good = len(le) == 1 and T.owned_by_end(k, le[0], X, Y) is True
                if T.kind[k] == ELLIPSE and len(le) == 2:   # both ends listed: its nearest points
                    good = owned_by_both_ends(T.piece[k], X, Y) is True
                if T.kind[k] == ARC and not good:       # strictly in its gap: its nearest points are ends
                    cx_, cy_, _ = T.arb_arc(k)
                    good = T.in_range(k, X - cx_, Y - cy_, closed=True) is False
                if not good and T.kind[k] == ELLIPSE and not T.distance(k, X, Y) < R:
                    # an elliptic piece's ownership is proved or left undecided, never refuted here
                    problems.append(Problem(f"{name}: elliptic piece {k}: its nearest points are not proved its "
                                            f"listed endpoints {le} (undecided)", kind="vertex",
                                            vertex=v.id, sites=tuple(sites) + (k,), fault=False))
                    ok = False
                elif not good:
                    problems.append(fault(f"{name}: curve {k} is closer than the radius (its nearest point is "
                                          f"not its listed endpoint {le[0]} alone), or too close to decide",
                                          kind="vertex", vertex=v.id, sites=tuple(sites) + (k,)))
                    ok = False
                continue
        dk = T.distance(k, X, Y)
        if not dk > R:
            what = "inside the circle" if dk < R else "too close to decide (on the circle?)"
            problems.append(fault(f"{name}: site {k} is {what}", kind="vertex", vertex=v.id,
                                  sites=tuple(sites) + (k,)))
            ok = False
    return ok
