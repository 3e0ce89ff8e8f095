"""The support envelope of points and arcs that poke out of the points' hull, proved (the
general case of :mod:`runtime.segments.certificate_hull`, whose docstring states the argument).

Public API: :func:`envelope_directions`, :func:`tangent_ties`, :class:`Undecided`.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from flint import arb

from ..certify.foot import to_arb
from .certificate_sites import POINT, SEGMENT, SiteTable, direction_key

__all__ = ["envelope_directions", "tangent_ties", "Undecided"]


class Undecided(Exception):
    """The unbounded ends are not decided (a limit)."""


def _fail(msg):
    raise Undecided(msg)


def _angle(x, y) -> arb:
    return arb.atan2(to_arb(y) if not isinstance(y, arb) else y, to_arb(x) if not isinstance(x, arb) else x)


def _mod2pi(d: arb):
    """d mod 2π in [0, 2π) as a ball, or None when the ball straddles a multiple of 2π."""
    tp = 2 * arb.pi()
    for _ in range(8):
        if d < 0:
            d += tp
        elif d >= tp:
            d -= tp
        else:
            break
    return d if (d >= 0 and d < tp) else None


# ------------------------------------------------------------------------------ the float guess
def _sequence(T: SiteTable, hull, poking) -> list:
    pts, lab = [], []
    for p in hull:
        pts.append((float(p[0]), float(p[1])))
        lab.append(("p", p))
    normals = []
    for m in range(len(hull)):
        p, q = hull[m], hull[(m + 1) % len(hull)]
        normals.append(math.atan2(-(float(q[0]) - float(p[0])), float(q[1]) - float(p[1])))
    for k in poking:
        cx, cy = T.C[k]
        r = T.R[k]
        al = math.atan2(T.A[k][1] - cy, T.A[k][0] - cx)
        be = (math.atan2(T.B[k][1] - cy, T.B[k][0] - cx) - al) % (2 * math.pi) or 2 * math.pi
        m = max(16, int(512 * be / (2 * math.pi)))
        angs = list(al + be * np.arange(1, m) / m)
        angs += [a for a in normals if 0 < (a - al) % (2 * math.pi) < be]
        for a in angs:
            pts.append((cx + r * math.cos(a), cy + r * math.sin(a)))
            lab.append(("a", k))
    from scipy.spatial import ConvexHull

    P = np.array(pts)
    H = ConvexHull(P)
    seq = []
    for v in H.vertices:                      # counter-clockwise in 2-D
        if not seq or seq[-1] != lab[v]:
            seq.append(lab[v])
    while len(seq) > 1 and seq[0] == seq[-1]:
        seq.pop()
    out = []
    for m, X in enumerate(seq):               # the shared end of two consecutive arcs between them
        out.append(X)
        Y = seq[(m + 1) % len(seq)]
        if X[0] == "a" and Y[0] == "a" and T.b[X[1]] == T.a[Y[1]]:
            out.append(("p", T.b[X[1]]))
    return out


# ------------------------------------------------------------------------------ transitions
def _KC(T, X, Y):
    """h_Y − h_X = K·u + C (an arc by its circle)."""
    zx = X[1] if X[0] == "p" else T.cen[X[1]]
    zy = Y[1] if Y[0] == "p" else T.cen[Y[1]]
    rx = 0 if X[0] == "p" else T.rad[X[1]]
    ry = 0 if Y[0] == "p" else T.rad[Y[1]]
    return (zy[0] - zx[0], zy[1] - zx[1]), Fraction(ry - rx)


def _transition(T, X, Y):
    """(φ ball, rational direction or None, reference point or None, K, C, radial flags)."""
    if X[0] == "p" and Y[0] == "p":
        p, q = X[1], Y[1]
        u = (q[1] - p[1], -(q[0] - p[0]))
        return dict(phi=_angle(*u), u=u, ref=p)
    if X[0] == "p" and T.a[Y[1]] == X[1]:
        c = T.cen[Y[1]]
        u = (X[1][0] - c[0], X[1][1] - c[1])
        return dict(phi=_angle(*u), u=u, ref=X[1], start=Y[1])
    if Y[0] == "p" and T.b[X[1]] == Y[1]:
        c = T.cen[X[1]]
        u = (Y[1][0] - c[0], Y[1][1] - c[1])
        return dict(phi=_angle(*u), u=u, ref=Y[1], end=X[1])
    K, C = _KC(T, X, Y)
    nk = (to_arb(K[0] * K[0] + K[1] * K[1])).sqrt()
    ratio = -to_arb(C) / nk
    if not (ratio > -1 and ratio < 1):
        _fail(f"no common tangent of {X} and {Y}")
    phi = _angle(*K) - ratio.acos()
    out = dict(phi=phi, u=None, ref=None, K=K, C=C, atoms=(X, Y))
    # a tangent that happens to be rational (an axis, a simple slope, two equal radii): exact ties
    P = X if X[0] == "p" else (Y if Y[0] == "p" else None)
    if C == 0:
        u = (K[1], -K[0])
    else:
        ux, uy = float(phi.cos().mid()), float(phi.sin().mid())
        m = max(abs(ux), abs(uy))
        u = (Fraction(ux / m).limit_denominator(1000), Fraction(uy / m).limit_denominator(1000))
    ku = K[0] * u[0] + K[1] * u[1]
    if ku * C <= 0 and ku * ku == C * C * (u[0] * u[0] + u[1] * u[1]) and K[0] * (-u[1]) + K[1] * u[0] > 0:
        out.update(u=u, ref=P[1] if P is not None else ("arc", X[1]))  # the root where h_Y − h_X grows
    return out


def _exact_zero(tr, K, C) -> bool:
    """K·u + C|u| = 0 exactly at the rational direction of a transition."""
    u = tr["u"]
    if u is None:
        return False
    ku = K[0] * u[0] + K[1] * u[1]
    return ku * C <= 0 and ku * ku == C * C * (u[0] * u[0] + u[1] * u[1])


def _same(t1, t2) -> bool:
    if t1["u"] is not None and t2["u"] is not None:
        return direction_key(t1["u"]) == direction_key(t2["u"])
    if t1["u"] is not None:
        return _exact_zero(t1, t2["K"], t2["C"]) and t1["phi"].overlaps(t2["phi"])
    if t2["u"] is not None:
        return _exact_zero(t2, t1["K"], t1["C"]) and t1["phi"].overlaps(t2["phi"])
    return False


def _length(t1, t2):
    if _same(t1, t2):
        return arb(0)
    d = _mod2pi(t2["phi"] - t1["phi"])
    if d is None or not d > 0:
        _fail("two directions of the support envelope are not separated")
    return d


# ------------------------------------------------------------------------------ proofs on intervals
def _nonneg(K, C, t1, t2, length, pair=None) -> bool:
    """K·u + C ≥ 0 on the directions from t1 to t2 (counter-clockwise, ``length``), > 0 inside;
    ``pair``: the two atoms compared (a tangent transition of these two is an exact zero)."""
    Ka = (to_arb(K[0]), to_arb(K[1]))
    nk = (Ka[0] * Ka[0] + Ka[1] * Ka[1]).sqrt()
    Ca = to_arb(C)
    for t in (t1, t2):
        v = Ka[0] * t["phi"].cos() + Ka[1] * t["phi"].sin() + Ca
        if v > 0:
            continue
        if not (_exact_zero(t, K, C) or (pair is not None and set(t.get("atoms", ())) == set(pair))):
            return False
    if C >= 0 and C * C > K[0] * K[0] + K[1] * K[1]:
        return True
    if length == 0:
        return True
    star = _mod2pi(_angle(-Ka[0], -Ka[1]) - t1["phi"])
    for t, at in ((t1, 0), (t2, 1)):           # the minimum exactly at an end
        if t["u"] is not None and K[0] * t["u"][1] - K[1] * t["u"][0] == 0 and K[0] * t["u"][0] + K[1] * t["u"][1] < 0:
            return True
    if star is not None and (star > length or star <= 0):
        return True
    return bool(Ca - nk > 0)


def _in_range_interval(T, k, t1, t2, length) -> bool:
    """The directions from t1 to t2 (counter-clockwise, ``length``) lie in arc k's closed range."""
    c = T.cen[k]
    al = _angle(T.a[k][0] - c[0], T.a[k][1] - c[1])
    be = _mod2pi(_angle(T.b[k][0] - c[0], T.b[k][1] - c[1]) - al)
    if be is None:
        return False
    o1 = arb(0) if t1.get("start") == k else _mod2pi(t1["phi"] - al)
    if o1 is None:
        return False
    if t2.get("end") == k:                     # the interval ends at the range's end exactly
        return bool(t1.get("start") == k or o1 < be)
    return bool(o1 + length <= be)


def _clip(T, k, t1, t2, length):
    """The parts (s1, s2, length) of the directions from t1 to t2 that lie in arc k's closed range
    (ends: t1, t2 or the radial directions of k's ends); None when undecided."""
    c = T.cen[k]
    ua = (T.a[k][0] - c[0], T.a[k][1] - c[1])
    ub = (T.b[k][0] - c[0], T.b[k][1] - c[1])
    al = _angle(*ua)
    be = _mod2pi(_angle(*ub) - al)
    if be is None:
        return None
    ra = dict(phi=al, u=ua)
    rb = dict(phi=_angle(*ub), u=ub)
    tp = 2 * arb.pi()
    rat = t1["u"] is not None
    if t1.get("start") == k or (rat and direction_key(t1["u"]) == direction_key(ua)):
        t1 = dict(t1, start=k)
        r0 = arb(0)
    elif t1.get("end") == k or (rat and direction_key(t1["u"]) == direction_key(ub)):
        t1 = dict(t1, end=k)
        r0 = tp - be
    else:
        r0 = _mod2pi(al - t1["phi"])
        if r0 is None:
            return None
    if t2["u"] is not None and direction_key(t2["u"]) == direction_key(ua):
        t2 = dict(t2, start=k)
    elif t2["u"] is not None and direction_key(t2["u"]) == direction_key(ub):
        t2 = dict(t2, end=k)
    r1 = r0 + be
    parts = []
    if t2.get("start") != k and not (length == 0):
        if not (r0 < length):
            if not (r0 >= length):
                return None
        else:
            s1 = t1 if t1.get("start") == k else ra
            if t2.get("end") == k:
                parts.append((s1, t2, length - r0))
            elif r1 < length:
                parts.append((s1, rb, be))
            elif r1 >= length:
                parts.append((s1, t2, length - r0))
            else:
                return None
    if t1.get("end") != k and t1.get("start") != k:
        if r1 > tp:
            w = r1 - tp
            if t2.get("end") == k or w >= length:
                parts.append((t1, t2, length))
            elif w < length:
                parts.append((t1, rb, w))
            else:
                return None
        elif not (r1 <= tp):
            return None
    return parts


def envelope_directions(T: SiteTable, hull, poking) -> list:
    """The tie directions of the support envelope, proved (module docstring of
    :mod:`runtime.segments.certificate_hull`): ("rational", u, p) with the support u·p, or
    ("tangent", X, Y, K, C, φ)."""
    seq = _sequence(T, hull, poking)
    m = len(seq)
    if m < 2:
        _fail("the support envelope has fewer than two atoms")
    trans = [_transition(T, seq[i], seq[(i + 1) % m]) for i in range(m)]
    lengths = [_length(trans[i - 1], trans[i]) for i in range(m)]   # atom i: from trans[i-1] to trans[i]
    total = sum(lengths, arb(0))
    if not (total > 0 and total < 4 * arb.pi()):
        _fail("the support envelope does not go once around")
    hull_atoms = [("p", p) for p in hull]
    arcs = [("a", k) for k in poking]
    for i, X in enumerate(seq):
        t1, t2, L = trans[i - 1], trans[i], lengths[i]
        if X[0] == "a" and not _in_range_interval(T, X[1], t1, t2, L):
            _fail(f"arc {X[1]} is on the support envelope outside its range")
        for Y in hull_atoms + arcs:
            if Y == X:
                continue
            K, C = _KC(T, Y, X)                    # h_X − h_Y
            if Y[0] == "p":
                if _nonneg(K, C, t1, t2, L, (X, Y)):
                    continue
            elif L == 0:                           # one direction: in or out of the range
                if t1["u"] is not None and not T.in_range(Y[1], t1["u"][0], t1["u"][1], closed=True):
                    continue
                if _nonneg(K, C, t1, t1, L, (X, Y)):
                    continue
            else:                                  # an arc's circle bounds it in its range
                parts = _clip(T, Y[1], t1, t2, L)
                if parts is not None and all(_nonneg(K, C, s1, s2, l, (X, Y)) for s1, s2, l in parts):
                    continue
            _fail(f"{'arc ' + str(Y[1]) if Y[0] == 'a' else 'point ' + str(Y[1])} is not proved below the "
                  f"support of {'arc ' + str(X[1]) if X[0] == 'a' else 'point ' + str(X[1])}")
    out = []
    for i in range(m):
        if _same(trans[i], trans[(i + 1) % m]):
            continue                               # the next transition is the same direction
        t = trans[i]
        if t["u"] is not None:
            out.append(("rational", t["u"], t["ref"]))
        else:
            out.append(("tangent",) + t["atoms"] + (t["K"], t["C"], t["phi"]))
    return out


# ------------------------------------------------------------------------------ ties on a tangent
def tangent_ties(T: SiteTable, d):
    """(sites touching the common tangent, u as balls) for ("tangent", X, Y, K, C, φ)."""
    _, X, Y, K, C, phi = d
    u = (phi.cos(), phi.sin())
    uf = (float(u[0].mid()), float(u[1].mid()))
    zx = X[1] if X[0] == "p" else T.cen[X[1]]
    h = u[0] * to_arb(zx[0]) + u[1] * to_arb(zx[1]) + (0 if X[0] == "p" else to_arb(T.rad[X[1]]))
    hf = np.maximum(T.A @ uf, T.B @ uf)
    for k in T.cen:
        if T.in_range(k, u[0], u[1], closed=True) is not False:
            hf[k] = max(hf[k], float(T.C[k] @ uf) + T.R[k])
    cand = np.nonzero(np.abs(hf - float(h.mid())) <= 1e-6 * T.scale)[0].tolist()
    atoms = {X, Y}
    ties = []
    for k in cand:
        pts = [T.a[k]] if T.kind[k] == POINT else ([T.a[k], T.b[k]] if T.kind[k] == SEGMENT else None)
        if pts is not None:
            on = [_on_tangent(T, q, X, Y, u, h) for q in pts]
            if all(on):
                ties.append(k)
            continue
        if ("a", k) in atoms:
            ties.append(k)
            continue
        if T.in_range(k, u[0], u[1], closed=True) is False:
            continue
        cx, cy, rho = T.arb_arc(k)
        v = u[0] * cx + u[1] * cy + rho - h
        if v < 0:
            continue
        _fail(f"arc {k} may touch the common tangent of {X} and {Y}")
    return ties, u


def _on_tangent(T, q, X, Y, u, h) -> bool:
    if ("p", q) in (X, Y):
        return True
    v = u[0] * to_arb(q[0]) + u[1] * to_arb(q[1]) - h
    if v < 0:
        return False
    if v > 0:
        _fail(f"the point {q} is above the support envelope")
    P = X if X[0] == "p" else Y                # a point and an arc: exact test
    A = Y if P is X else X
    if P[0] != "p" or A[0] != "a":
        _fail(f"the point {q} may lie on a common tangent of two arcs")
    p, c, rho = P[1], T.cen[A[1]], T.rad[A[1]]
    w = (q[0] - p[0], q[1] - p[1])
    cr = (c[0] - p[0]) * (-w[1]) + (c[1] - p[1]) * w[0]
    if cr * cr != rho * rho * (w[0] * w[0] + w[1] * w[1]):
        return False
    _fail(f"the point {q} lies on a tangent from {p} to arc {A[1]} (collinear ties on a tangent: not proved)")
