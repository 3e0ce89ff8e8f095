"""The conditions of an edge proof along a curve (for :mod:`runtime.segments.certificate_edges`):
functions that must be > 0 on the open arc, proved with the pieces
(:mod:`runtime.segments.certificate_pieces`).

* R2 along a parabola or an arc's bisector: a curve k ending at the edge's point p has p alone
  as its nearest point — linear functions g·x + g₀ (:func:`runtime.segments.certificate_rules.
  linear_rule`);
* along an arc's bisector (:mod:`runtime.segments.certificate_arcs`): t > 0 (and t < ρ inside the
  circle, so that v = c + (ρ − t) u has its contact at u); a segment partner's
  foot in (0, 1) (two linear functions; then its line's distance is the segment's); an arc
  partner's contact direction in its open range (two linear functions — cross products with its
  ends' directions — both > 0 for an arc of at most 180°, one of them for a larger one: their
  maximum), and t < ρ₂ when it is touched from inside.

At a finite end vertex a condition may vanish: a curve touched there at its end (it is listed),
a corner (t = 0, the foot at the corner).  Each of its functions f that is ≥ 0 there (exactly 0
when the vertex lists the site that makes it vanish, else proved) covers the start of the arc
when f' > 0 into it (:meth:`runtime.segments.certificate_pieces.PieceProofs._prefix`); the
condition (f itself, or a maximum with f) is then > 0 on the covered part.

Public API: :func:`arc_conditions`, :func:`cover_conditions`.
"""
from __future__ import annotations

import math

from .certificate_curves import down, up
from .certificate_rules import linear_rule, range_lines
from .certificate_sites import ARC, SEGMENT
from ..certify.foot import to_arb

__all__ = ["arc_conditions", "cover_conditions"]


def _lin(c, g):
    gx, gy, g0 = (to_arb(v) for v in g)

    def fv(t, X, Y, rho):
        return gx * X + gy * Y + g0

    def fd(t, X, Y):
        dx, dy = c.dxy(t)
        return gx * dx + gy * dy
    return fv, fd


def _cond(name, fns, combine="min"):
    if len(fns) == 1:
        value = fns[0][0]
    else:
        def value(t, X, Y, rho):
            vals = [f[0](t, X, Y, rho) for f in fns]
            out = vals[0]
            for v in vals[1:]:
                out = out.max(v) if combine == "max" else out.min(v)
            return out
    return {"name": name, "value": value, "fns": fns, "lo": -math.inf, "hi": math.inf}


def _tie_of(T, s, code) -> set:
    """The sites whose listing at a vertex means curve s is touched at its end ``code``."""
    if code >= 0:
        return {code}
    return {o for o in T.joint_curves(code) if o != s}


def arc_conditions(pr, only_linear: bool = False) -> list:
    T, c = pr.T, pr.curve
    out = []
    for k, mode, conds in pr.linear:
        p = next(e for e in T.ends[k] if e in (pr.i, pr.j))
        name = f"curve {k} is not proved to have its end {p} as its nearest point"
        fns = [_lin(c, g) + ({k, p},) for g in conds]
        if mode == "max":
            out.append(_cond(name, fns, "max"))
        else:
            out += [_cond(name, [f]) for f in fns]
    if only_linear:
        return out
    out.append(_cond("its distance is not proved positive", [(lambda t, X, Y, rho: rho,
                                                             lambda t, X, Y: c.drho(t, X, Y), "corner")]))
    if c.sigma < 0:                          # inside the circle: v = c + (ρ − t) u needs t < ρ
        r = to_arb(T.rad[c.s])
        out.append(_cond(f"the centre of arc {c.s} is not proved off the edge",
                         [(lambda t, X, Y, rho: r - rho, lambda t, X, Y: -c.drho(t, X, Y), set())]))
    k = c.k
    if T.kind[k] == SEGMENT:
        for e in T.ends[k]:
            fv, fd = _lin(c, linear_rule(T, k, e, True)[0])
            out.append(_cond(f"the foot on segment {k} is not proved inside it (end {e})",
                             [(fv, fd, _tie_of(T, k, e))]))
    elif T.kind[k] == ARC:
        (cx, cy) = T.cen[k]
        ua = (T.a[k][0] - cx, T.a[k][1] - cy)
        ub = (T.b[k][0] - cx, T.b[k][1] - cy)
        ga, gb = range_lines(T, k)
        fa = _lin(c, ga) + (_tie_of(T, k, T.ends[k][0]),)
        fb = _lin(c, gb) + (_tie_of(T, k, T.ends[k][1]),)
        ab = ua[0] * ub[1] - ua[1] * ub[0]
        name = f"the contact with arc {k} is not proved inside its range"
        if ab > 0:
            out += [_cond(name, [fa]), _cond(name, [fb])]
        elif ab < 0:
            out.append(_cond(name, [fa, fb], "max"))
        else:                                               # a half circle: ca vanishes at both ends
            out.append(_cond(name, [fa[:2] + (fa[2] | fb[2],)]))
        if c.tau < 0:
            r2 = to_arb(T.rad[k])
            out.append(_cond(f"the circle of arc {k} is not proved touched from inside",
                             [(lambda t, X, Y, rho: r2 - rho, lambda t, X, Y: -c.drho(t, X, Y), set())]))
    return out


def _zero_ok(vp, tie) -> bool:
    if tie == "corner":
        return vp.corner is not None
    return bool(set(vp.listed) & tie) or (vp.corner is not None and vp.corner in tie)


def cover_conditions(pr, span: float) -> bool:
    """Covers of the conditions at the finite end vertices (module docstring)."""
    ok = True
    for cd in pr.conditions:
        for end, at_lo in ((pr.lo, True), (pr.hi, False)):
            if end[0] != "v":
                continue
            vp, t0 = end[2], end[1]
            positive = bool(cd["value"](t0, vp.x, vp.y, vp.r) > 0)  # a cover still helps when tiny
            base, back = (up(t0), down(t0)) if at_lo else (down(t0), up(t0))
            best = None
            for fv, fd, tie in cd["fns"]:
                f0 = fv(t0, vp.x, vp.y, vp.r)
                if not (f0 >= 0 or _zero_ok(vp, tie)):
                    continue
                sgn = 1 if at_lo else -1
                reach = pr._prefix(lambda J, X, Y, fd=fd: fd(J, X, Y) * sgn, back, base, span, at_lo)
                if reach is not None and (best is None or (reach > best if at_lo else reach < best)):
                    best = reach
                    if abs(best - base) >= span:       # the whole edge: no other does better
                        break
            if best is None:
                if not positive:
                    pr.report(f"{cd['name']} next to its end vertex {end[3]}")
                    ok = False
                continue
            if at_lo:
                cd["lo"] = max(cd["lo"], best)
            else:
                cd["hi"] = min(cd["hi"], best)
        cd["fns"] = [f[:2] for f in cd["fns"]]
    return ok

