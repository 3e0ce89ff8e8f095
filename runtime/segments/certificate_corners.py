"""Vertices decided exactly in rationals (step 2 of :mod:`runtime.segments.certificate`): corners
of radius 0 and the centres of arcs.

* **Corner** (the closures of all listed sites share a point site c): v = c exactly, radius 0.
  The sites at distance 0 from c are c and the curves ending at c; the listed sites must be
  exactly those curves sorted counter-clockwise by the exact direction in which they leave c
  (half-plane and cross-product comparisons of rationals; two curves leaving in the same
  direction by their signed curvature), with c inserted between the two curves bounding the
  reflex angle (> 180°) when there is one.  Emptiness is admissibility.
* **Arc centre** (a listed arc s with the reported vertex at its centre): v = c_s, r = ρ_s.  Every
  listed site is at distance exactly ρ from c (rationals and squares: an arc of the same circle
  along its whole length, another arc at | |c − c_k| − ρ_k | when c − c_k lies in its closed
  range, else at its nearer end), every other site farther, except a curve whose nearest point
  is a listed end e alone, strictly beyond it (the tie belongs to e): exactly, after a k-d tree
  and a float filter.  The listed order is the counter-clockwise order of the contacts (exact
  directions from c): an arc of the circle occupies its whole range, after the site at its start
  a and before the site at its end b; a curve touching at one of its ends comes just after the
  end's point when it leaves the contact counter-clockwise, just before otherwise.

Public API: :func:`prove_corner`, :func:`prove_arc_centre`, :func:`exact_direction_order`,
:func:`same_cycle`.
"""
from __future__ import annotations

import functools
from fractions import Fraction

from flint import arb

from ..certify.foot import to_arb
from ..voronoi.verify.problems import fault
from .certificate_sites import ARC, POINT, SEGMENT, SiteTable

__all__ = ["prove_corner", "prove_arc_centre", "exact_direction_order", "same_cycle"]


def _half(d) -> int:
    return 0 if (d[1] > 0 or (d[1] == 0 and d[0] > 0)) else 1


def _cmp(d, e) -> int:
    """Counter-clockwise comparison of two exact directions by angle in [0, 2π)."""
    h, g = _half(d), _half(e)
    if h != g:
        return h - g
    c = d[0] * e[1] - d[1] * e[0]
    return -1 if c > 0 else (1 if c < 0 else 0)


def exact_direction_order(T: SiteTable, c: int) -> list:
    """The corner list of point site c: its curves counter-clockwise by the exact direction in
    which they leave c (same direction: by signed curvature), c inserted in the reflex gap."""
    segs = list(T.incident[c])

    def key_cmp(s, t):
        r = _cmp(T.leaving(s, c), T.leaving(t, c))
        if r:
            return r
        ks, kt = T.curvature(s, c), T.curvature(t, c)
        return -1 if ks < kt else (1 if ks > kt else 0)

    order = sorted(segs, key=functools.cmp_to_key(key_cmp))
    m = len(order)
    if m == 1:
        return order + [c]
    for t in range(m):
        d, e = T.leaving(order[t], c), T.leaving(order[(t + 1) % m], c)
        if d[0] * e[1] - d[1] * e[0] < 0:
            return order[:t + 1] + [c] + order[t + 1:]
    return order


def same_cycle(a, b) -> bool:
    if len(a) != len(b) or set(a) != set(b):
        return False
    m = list(b).index(a[0])
    return list(a) == list(b[m:]) + list(b[:m])


def prove_corner(T: SiteTable, v, sites, c, problems, tol: float, name: str, proof):
    want = exact_direction_order(T, c)
    if set(sites) != set(want):
        problems.append(fault(f"{name}: the sites at distance 0 from the corner point site {c} are "
                              f"{sorted(want)}, the vertex lists {sorted(sites)}", kind="vertex", vertex=v.id,
                              sites=sites))
        return proof(False)
    if not same_cycle(sites, want):
        problems.append(fault(f"{name}: the sites of the corner {c} are not listed counter-clockwise "
                              f"(expected the cyclic order {tuple(want)})", kind="vertex", vertex=v.id, sites=sites))
        return proof(False)
    x, y = T.a[c]
    if not (abs(float(v.x) - float(x)) <= tol and abs(float(v.y) - float(y)) <= tol and abs(float(v.radius)) <= tol):
        problems.append(fault(f"{name}: the corner vertex is the point site {c} at ({x}, {y}) with radius 0, "
                              f"reported at ({v.x!r}, {v.y!r}) with radius {v.radius!r}", kind="vertex",
                              vertex=v.id, sites=sites))
        return proof(False)
    return proof(True, T.arb_ends(c)[0], T.arb_ends(c)[1], arb(0), c, frozenset(sites))


# ------------------------------------------------------------------------------------ arc centres
def _sgn(x) -> int:
    return (x > 0) - (x < 0)


def exact_contact(T: SiteTable, k: int, c, r: Fraction):
    """(sign of d_k(c) − r, contact) exactly for the rational point c: contact is
    ("dir", w, e, lean_dir) — w the exact direction of the nearest point from c, e the end code
    when that point is an end of k (else None) with the direction k leaves it — or ("range", k)
    for an arc of the circle (c, r) itself; ``clamped``: the nearest point is that end alone,
    strictly beyond it."""
    kind = T.kind[k]
    if kind not in (POINT, SEGMENT, ARC):
        raise ValueError(f"site {k}: no exact distance to an elliptic piece")
    if kind == POINT:
        w = (T.a[k][0] - c[0], T.a[k][1] - c[1])
        return _sgn(w[0] * w[0] + w[1] * w[1] - r * r), ("dir", w, None, None), False
    if kind == SEGMENT:
        (ax, ay), (bx, by) = T.a[k], T.b[k]
        dx, dy = bx - ax, by - ay
        u = ((c[0] - ax) * dx + (c[1] - ay) * dy) / (dx * dx + dy * dy)
        uc = min(max(u, Fraction(0)), Fraction(1))
        f = (ax + uc * dx, ay + uc * dy)
        w = (f[0] - c[0], f[1] - c[1])
        sign = _sgn(w[0] * w[0] + w[1] * w[1] - r * r)
        e = T.ends[k][0] if u <= 0 else (T.ends[k][1] if u >= 1 else None)
        return sign, ("dir", w, e, None if e is None else T.leaving(k, e)), (u < 0 or u > 1)
    ck, rk = T.cen[k], T.rad[k]
    w = (c[0] - ck[0], c[1] - ck[1])
    D2 = w[0] * w[0] + w[1] * w[1]
    if D2 == 0:
        return _sgn(rk - r), ("range", k), False
    if T.in_range(k, w[0], w[1], closed=True):
        # |D − ρ_k| vs r with D = √D2
        if D2 > (rk + r) ** 2:
            sign = 1
        elif D2 == (rk + r) ** 2:
            sign = 0
        elif rk - r > 0 and D2 < (rk - r) ** 2:
            sign = 1
        elif rk - r > 0 and D2 == (rk - r) ** 2:
            sign = 0
        else:
            sign = -1
        # the contact direction from c: −w (outside k's circle) or w (inside)
        out = D2 > rk * rk
        d = (-w[0], -w[1]) if out else w
        e = None
        if not T.in_range(k, w[0], w[1]):
            for code in T.ends[k]:
                q = T.pt(code)
                if (q[0] - ck[0]) * w[1] - (q[1] - ck[1]) * w[0] == 0 and \
                        (q[0] - ck[0]) * w[0] + (q[1] - ck[1]) * w[1] > 0:
                    e = code
        return sign, ("dir", d, e, None if e is None else T.leaving(k, e)), False
    best = None
    for code in T.ends[k]:
        q = T.pt(code)
        d2 = (q[0] - c[0]) ** 2 + (q[1] - c[1]) ** 2
        if best is None or d2 < best[0]:
            best = (d2, code, q)
        elif d2 == best[0]:
            best = (d2, None, None)               # both ends nearest: no single end owns the tie
    d2, e, q = best
    if e is None:
        return _sgn(d2 - r * r), ("dir", None, None, None), False
    return _sgn(d2 - r * r), ("dir", (q[0] - c[0], q[1] - c[1]), e, T.leaving(k, e)), True


def prove_arc_centre(T: SiteTable, v, sites, s, problems, tol: float, name: str, proof):
    """The vertex at the centre of arc s (module docstring)."""
    c, r = T.cen[s], T.rad[s]
    if not (abs(float(v.x) - float(c[0])) <= tol and abs(float(v.y) - float(c[1])) <= tol and
            abs(float(v.radius) - float(r)) <= tol):
        problems.append(fault(f"{name}: the vertex at the centre of arc {s} is ({c[0]}, {c[1]}) with radius {r}, "
                              f"reported at ({v.x!r}, {v.y!r}) with radius {v.radius!r}", kind="vertex",
                              vertex=v.id, sites=sites))
        return proof(False)
    items = []
    for k in sites:
        sign, contact, clamped = exact_contact(T, k, c, r)
        if sign != 0 or clamped or contact[0] == "dir" and contact[1] is None:
            what = "inside the circle" if sign < 0 else ("not on the circle" if sign > 0 else
                                                          "on the circle only through a listed end")
            problems.append(fault(f"{name}: site {k} is listed but {what} (the circle of arc {s})", kind="vertex",
                                  vertex=v.id, sites=sites))
            return proof(False)
        if contact[0] == "range":
            items.append((T.a[k][0] - c[0], T.a[k][1] - c[1], 1, k))
            continue
        _, w, e, lv = contact
        rank = 0
        if lv is not None:
            rank = 1 if w[0] * lv[1] - w[1] * lv[0] > 0 else -1
        items.append((w[0], w[1], rank, k))

    def icmp(p, q):
        r_ = _cmp(p[:2], q[:2])
        return r_ if r_ else (p[2] > q[2]) - (p[2] < q[2])

    items.sort(key=functools.cmp_to_key(icmp))
    if any(icmp(p, q) == 0 for p, q in zip(items, items[1:])) or \
            not same_cycle(tuple(sites), tuple(k for *_, k in items)):
        problems.append(fault(f"{name}: the sites are not listed counter-clockwise by their contacts with the "
                              f"circle of arc {s} (expected the cyclic order {tuple(k for *_, k in items)})",
                              kind="vertex", vertex=v.id, sites=sites))
        return proof(False)
    listed = set(sites)
    ok = True
    for k in T.near(float(c[0]), float(c[1]), float(r) * (1 + 1e-9)):
        if k in listed:
            continue
        sign, contact, clamped = exact_contact(T, k, c, r)
        if sign > 0:
            continue
        if sign == 0 and clamped and contact[2] is not None and contact[2] in listed:
            continue
        if sign == 0 and T.kind[k] == ARC and contact[1] is None and all(e in listed for e in T.ends[k]):
            continue                      # an arc whose nearest points are its two listed ends
        what = "inside the circle" if sign < 0 else "on the circle and not listed"
        problems.append(fault(f"{name}: site {k} is {what}", kind="vertex", vertex=v.id, sites=tuple(sites) + (k,)))
        ok = False
    if not ok:
        return proof(False)
    return proof(True, to_arb(c[0]), to_arb(c[1]), to_arb(r), None, frozenset(sites))
