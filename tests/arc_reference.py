"""Independent reference for diagrams with circular arcs (tests only; NOT used by the runtime).

Shares no code with ``runtime/segments``: the distance to a closed elementary site is written
here from its definition in mpmath (40 digits) —

* a point p: |x − p|;
* a closed segment [a, b]: the distance to the foot clamped to [a, b];
* a closed circular arc (centre c, radius ρ, counter-clockwise from a to b): | |x − c| − ρ | when
  the angle of x − c lies in the arc's angular range (read with ``mpmath.atan2``), else the nearer
  end's distance.

:func:`bisector_offset` bounds the distance from a point q to the bisector {d_i = d_j} of two
sites: it looks for a sign change of f = d_i − d_j along the line through q in a given direction
(the polyline's normal), at distances 0, ±h, ±2h, … up to ``reach`` and refines it by bisection;
the zero found (to 10⁻⁶ of the grid step, its far side reported) is a point of the bisector, so
|q − zero| bounds the distance from q to the bisector (a point of the closed bisector set; the caller checks that the other sites are
farther there with :func:`nearest_margin`).
"""
from __future__ import annotations

from fractions import Fraction

import mpmath

DPS = 40


def mp(v) -> mpmath.mpf:
    """An mpf of the exact rational v (Fraction, int, flint fmpq, float)."""
    if isinstance(v, mpmath.mpf):
        return v
    if not isinstance(v, (int, Fraction, float)):
        v = Fraction(str(v))                    # flint fmpq prints as p/q
    if isinstance(v, Fraction):
        return mpmath.mpf(v.numerator) / v.denominator
    return mpmath.mpf(v)


def site_data(site):
    """("point", p) | ("segment", a, b) | ("arc", c, ρ, a, b) with mpf coordinates, read from the
    public attributes of a :class:`curvedvoronoi.Arc`, ``Segment`` or point site."""
    if hasattr(site, "rho") and hasattr(site, "c"):
        return ("arc", (mp(site.c[0]), mp(site.c[1])), mp(site.rho), (mp(site.a[0]), mp(site.a[1])),
                (mp(site.b[0]), mp(site.b[1])))
    if hasattr(site, "q") and hasattr(site, "p"):
        return ("segment", (mp(site.p[0]), mp(site.p[1])), (mp(site.q[0]), mp(site.q[1])))
    return ("point", (mp(site.x), mp(site.y)))


def _angle_in(c, a, b, x) -> bool:
    """The direction of x − c lies in the closed counter-clockwise range from a − c to b − c."""
    two_pi = 2 * mpmath.pi
    a0 = mpmath.atan2(a[1] - c[1], a[0] - c[0])
    span = (mpmath.atan2(b[1] - c[1], b[0] - c[0]) - a0) % two_pi
    w = (mpmath.atan2(x[1] - c[1], x[0] - c[0]) - a0) % two_pi
    return w <= span


def distance(site, x) -> mpmath.mpf:
    """The distance from the point x (mpf pair) to the closed site (:func:`site_data` form)."""
    with mpmath.workdps(DPS):
        if site[0] == "point":
            p = site[1]
            return mpmath.hypot(x[0] - p[0], x[1] - p[1])
        if site[0] == "segment":
            a, b = site[1], site[2]
            dx, dy = b[0] - a[0], b[1] - a[1]
            u = ((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) / (dx * dx + dy * dy)
            u = min(max(u, mpmath.mpf(0)), mpmath.mpf(1))
            return mpmath.hypot(x[0] - a[0] - u * dx, x[1] - a[1] - u * dy)
        c, rho, a, b = site[1], site[2], site[3], site[4]
        if _angle_in(c, a, b, x):
            return abs(mpmath.hypot(x[0] - c[0], x[1] - c[1]) - rho)
        return min(mpmath.hypot(x[0] - a[0], x[1] - a[1]), mpmath.hypot(x[0] - b[0], x[1] - b[1]))


def bisector_offset(si, sj, q, direction, reach, steps: int = 64):
    """(offset, zero): the smallest |s| (on the grid s = ±k·reach/steps, then refined by bisection)
    with d_i − d_j changing sign between q + s' n and q + s n (n the unit ``direction``), and the
    bisector point found there; (None, None) when f keeps its sign on the whole segment."""
    with mpmath.workdps(DPS):
        q = (mp(q[0]), mp(q[1]))
        nx, ny = mp(direction[0]), mp(direction[1])
        nn = mpmath.hypot(nx, ny)
        nx, ny = nx / nn, ny / nn

        def f(s):
            x = (q[0] + s * nx, q[1] + s * ny)
            return distance(si, x) - distance(sj, x)

        f0 = f(mpmath.mpf(0))
        if f0 == 0:
            return mpmath.mpf(0), q
        h = mp(reach) / steps
        prev = {1: (mpmath.mpf(0), f0), -1: (mpmath.mpf(0), f0)}
        for k in range(1, steps + 1):
            for sg in (1, -1):
                s = sg * k * h
                fs = f(s)
                s0, f_prev = prev[sg]
                if (fs > 0) != (f_prev > 0) or fs == 0:
                    lo, hi, flo = s0, s, f_prev
                    for _ in range(200):
                        mid = (lo + hi) / 2
                        fm = f(mid)
                        if (fm > 0) == (flo > 0):
                            lo, flo = mid, fm
                        else:
                            hi = mid
                        if abs(hi - lo) < h * mpmath.mpf(10) ** -6:
                            break
                    z = hi if abs(hi) > abs(lo) else lo
                    return abs(z), (q[0] + z * nx, q[1] + z * ny)
                prev[sg] = (s, fs)
        return None, None


def polyline_offsets(si, sj, P, reach, per_segment: int = 8, steps: int = 64):
    """The largest :func:`bisector_offset` over ``per_segment`` + 1 points of each segment of the
    polyline P (floats), along the segment's normal; None when some point finds no zero."""
    worst = mpmath.mpf(0)
    zeros = []
    for m in range(len(P) - 1):
        (x0, y0), (x1, y1) = P[m], P[m + 1]
        dx, dy = mp(x1) - mp(x0), mp(y1) - mp(y0)
        if dx == 0 and dy == 0:
            continue
        for k in range(per_segment + 1):
            u = Fraction(k, per_segment)
            q = (mp(x0) + mp(u) * dx, mp(y0) + mp(u) * dy)
            off, z = bisector_offset(si, sj, q, (-dy, dx), reach, steps)
            if off is None:
                return None, zeros
            worst = max(worst, off)
            zeros.append(z)
    return worst, zeros


def nearest_margin(sites, i, j, x) -> mpmath.mpf:
    """min over k ∉ {i, j} of d_k(x) − max(d_i(x), d_j(x)) (sites in :func:`site_data` form)."""
    own = max(distance(sites[i], x), distance(sites[j], x))
    return min(distance(s, x) - own for k, s in enumerate(sites) if k not in (i, j))
