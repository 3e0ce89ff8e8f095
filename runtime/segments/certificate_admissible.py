"""Admissible sites of the point/segment/arc certificate (step 1 of
:mod:`runtime.segments.certificate`).

Every site is a :class:`runtime.sites.circle.Point`, a
:class:`runtime.sites.segment.Segment` or a :class:`runtime.sites.arc.Arc` (their open
interiors); none is repeated; every end of a curve is a point site of the list or a **smooth
joint**: a point that is no site where exactly two curves end, not both segments, leaving it in
opposite directions (exact tangents; the normal line there is their bisector).  Curves meet only
at common ends and no point lies in a curve's interior
(:func:`runtime.segments.crossings.check_pieces`, exact); two curves leaving a point site in
opposite directions are refused (degree 2: merge them, or drop the point; degree ≥ 3: a whole ray
would be equidistant from three sites), and two curves leaving a point site in the *same*
direction (tangent curves) are a limit: not proved.

Public API: :func:`admissibility`.
"""
from __future__ import annotations

from ..voronoi.verify.problems import Problem, fault
from .certificate_sites import ARC, ELLIPSE, SEGMENT, SiteTable

__all__ = ["admissibility"]


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def admissibility(T: SiteTable) -> list:
    """Problems that make the sites inadmissible (module docstring); empty when admissible."""
    out = []
    for k in T.unsupported:
        out.append(Problem(f"site {k}: {type(T.sites[k]).__name__} is not a point, a segment or an arc: this "
                           "certificate proves diagrams of points, segments and arcs only", kind="site",
                           sites=(k,), fault=False))
    for p, q in T.repeated_points:
        out.append(fault(f"sites {p} and {q}: the same point repeated", kind="site", sites=(p, q)))
    seen: dict = {}
    for k, end in T.bad_ends:
        what = {SEGMENT: "segment", ARC: "arc", ELLIPSE: "elliptic arc"}[T.kind[k]]
        out.append(fault(f"site {k}: the endpoint ({end[0]}, {end[1]}) of the {what} is not a point site of the "
                         "diagram (every endpoint is its own site, unless exactly two curves, not both segments, "
                         "continue each other smoothly there)", kind="site", sites=(k,)))
    for k in range(T.n):
        if not T.is_curve(k):
            continue
        if T.kind[k] == ELLIPSE:
            key = (ELLIPSE, T.sites[k].key())
            if key in seen:
                out.append(fault(f"sites {seen[key]} and {k}: the same curve repeated", kind="site",
                                 sites=(seen[key], k)))
            seen.setdefault(key, k)
            continue
        key = (T.kind[k], T.cen.get(k), T.rad.get(k)) + ((T.a[k], T.b[k]) if T.kind[k] == ARC else
                                                          (frozenset((T.a[k], T.b[k])),))
        if key in seen:
            out.append(fault(f"sites {seen[key]} and {k}: the same curve repeated", kind="site",
                             sites=(seen[key], k)))
        seen.setdefault(key, k)
    if out:
        return out
    try:
        from .crossings import check_pieces
        from ..voronoi.site_input import SiteError
    except ImportError:                       # pragma: no cover - ships with the package
        return [Problem("sites: the crossing check (runtime.segments.crossings) is not available", kind="site", fault=False)]
    try:
        check_pieces([s for s in T.sites])
    except SiteError as exc:
        return [fault(f"sites not admissible: {exc}", kind="site")]
    for p, segs in T.incident.items():
        dirs = [T.leaving(s, p) for s in segs]
        for x in range(len(dirs)):
            for y in range(x + 1, len(dirs)):
                u, v = dirs[x], dirs[y]
                if _cross(u, v) != 0:
                    continue
                if u[0] * v[0] + u[1] * v[1] < 0:
                    straight = T.kind[segs[x]] == SEGMENT and T.kind[segs[y]] == SEGMENT
                    what = (("two segments meeting at 180 degrees at a point of degree 2 are one elementary site "
                             "(merge them)") if straight else
                            "two curves continuing each other smoothly meet at a point site (drop the point: "
                            "the joint is no site)") if len(segs) == 2 else \
                        "a junction of three or more curves continues straight (or smoothly) through (a ray " \
                        "equidistant from three sites)"
                    out.append(fault(f"point site {p}: curves {segs[x]} and {segs[y]}: {what}", kind="site",
                                     sites=(p, segs[x], segs[y])))
                else:
                    out.append(Problem(f"point site {p}: curves {segs[x]} and {segs[y]} leave it in the same "
                                       "direction (tangent): not proved", kind="site", sites=(p, segs[x], segs[y]),
                                       fault=False))
    return out
