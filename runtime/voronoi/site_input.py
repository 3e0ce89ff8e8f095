"""Input sites: conversion of user sites to exact sites and the disjointness check.

Thesis §1.2 defines the Voronoi diagram of pairwise *disjoint* sites; intersecting or repeated
sites are rejected with an error naming the pair (circles and points: exact rational test;
conics: :func:`runtime.sites.intersection.sites_intersect`).

Public API: :func:`as_site`, :func:`check_disjoint`, :func:`sites_equal`, :class:`SiteError`.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from ..predicates.circles import Circle, Point, as_circle
from ..sites.conic import Conic
from ..sites.intersection import circles_meet, sites_intersect
from ..result import InvalidConicError
from .conic_geometry import site_geometry

__all__ = ["as_site", "check_disjoint", "sites_equal", "SiteError"]


class SiteError(InvalidConicError):
    """Sites that intersect or repeat: the diagram of the thesis (§1.2) needs disjoint sites."""



def as_site(s: Any) -> Circle | Conic:
    """A user site as an exact site: Circle / Point / Conic pass through; a pair (x, y) is a
    point; a triple (cx, cy, r) is a circle of radius r (r = 0: a point, thesis §3.1.2); a list
    of six numbers is the coefficient list of a conic; a dict is a site record of
    :func:`runtime.sites.reader.parse_site`.  Pairs and triples may be tuples, lists or numpy
    arrays; numbers are taken exactly (floats at their binary value)."""
    if isinstance(s, (Circle, Conic)):
        return s
    if isinstance(s, dict):
        from ..sites.reader import parse_site
        return parse_site(s)
    if isinstance(s, (str, bytes)):
        raise InvalidConicError(f"not a site: {s!r} (expected Circle, Point, Conic, (x, y) or (cx, cy, r))")
    if isinstance(s, (list, tuple)) and len(s) == 6:
        return Conic.from_coefficients(*s)
    try:
        vals = tuple(s)
    except TypeError:
        vals = ()
    if len(vals) == 2:
        return Point(*vals)
    if len(vals) != 3:
        raise InvalidConicError(f"not a site: {s!r} (expected Circle, Point, Conic, (x, y) or (cx, cy, r))")
    cx, cy, r = vals
    if r == 0:
        return Point(cx, cy)
    return as_circle((cx, cy, r))


def check_disjoint(sites, geoms=None) -> None:
    """Raise :class:`SiteError` naming the first pair of sites that intersect or repeat.

    Circles and points: candidate pairs from a k-d tree (a pair of overlapping discs is found
    from the larger one), a float filter, then the exact test.  Pairs with a conic: bounding
    boxes, then :func:`runtime.sites.intersection.sites_intersect`."""
    if geoms is None:
        geoms = [site_geometry(s) for s in sites]
    circ = [i for i, g in enumerate(geoms) if g.kind in ("point", "circle")]
    if len(circ) > 1:
        idx = np.array(circ)
        C = np.array([[geoms[i].cx if geoms[i].kind == "circle" else geoms[i].x0,
                       geoms[i].cy if geoms[i].kind == "circle" else geoms[i].y0] for i in circ])
        R = np.array([geoms[i].rho if geoms[i].kind == "circle" else 0.0 for i in circ])
        scale = float(np.abs(C).max() + R.max() + 1.0)
        tree = cKDTree(C)
        lists = tree.query_ball_point(C, 2 * R + 1e-9 * scale)
        for a, js in enumerate(lists):
            for b in js:
                if b == a or R[b] > R[a] or (R[b] == R[a] and b < a):
                    continue
                d = math.hypot(C[a, 0] - C[b, 0], C[a, 1] - C[b, 1])
                tol = 1e-9 * scale
                if d > R[a] + R[b] + tol or d < abs(R[a] - R[b]) - tol:
                    continue
                i, j = sorted((int(idx[a]), int(idx[b])))
                if sites_equal(sites[i], sites[j]):
                    raise SiteError(f"site {i} and site {j} are the same site (repeated): remove one")
                ci, cj = as_circle(sites[i]), as_circle(sites[j])
                if circles_meet((ci.cx, ci.cy, ci.r2), (cj.cx, cj.cy, cj.r2)):
                    raise SiteError(f"site {i} and site {j} intersect: the Voronoi diagram needs disjoint sites")
    conics = [i for i, g in enumerate(geoms) if g.kind not in ("point", "circle")]
    if conics:
        boxes = np.array([g.bounding_box() for g in geoms], dtype=float)
        is_conic = np.zeros(len(geoms), bool)
        is_conic[conics] = True
        for i, over in zip(conics, _overlapping_boxes(boxes, conics)):
            for j in over.tolist():
                if j == i or (is_conic[j] and j < i):
                    continue
                a, b = sorted((i, j))
                if sites_equal(sites[a], sites[b]):
                    raise SiteError(f"site {a} and site {b} are the same site (repeated): remove one")
                if sites_intersect(sites[a], sites[b]):
                    raise SiteError(f"site {a} and site {b} intersect: the Voronoi diagram needs disjoint sites")


def _overlapping_boxes(boxes, rows):
    """For each box ``boxes[i]``, i in ``rows``: the indices j (ascending) of the boxes that meet it
    (closed boxes (x0, y0, x1, y1), compared in floats).  Candidates from a k-d tree on the
    centres of the finite boxes in the max-norm (two boxes that meet have centres within the sum
    of their half-widths, up to the rounding of the centres, covered by a margin of 1e-9 of the
    coordinates); the boxes more than 4x the median half-width, and the unbounded ones, are
    candidates for every box."""
    lo, hi = boxes[:, :2], boxes[:, 2:]
    finite = np.isfinite(boxes).all(axis=1)
    with np.errstate(invalid="ignore", over="ignore"):
        centre, half = (lo + hi) / 2, ((hi - lo) / 2).max(axis=1)
    small = finite & (half <= 4 * (np.median(half[finite]) if finite.any() else 0.0))
    always = np.nonzero(~small)[0]
    idx = np.nonzero(small)[0]
    found = [[] for _ in rows]
    rows = np.asarray(rows, dtype=np.int64)
    if len(idx):
        scale = float(np.abs(boxes[finite]).max()) + 1.0
        ask = np.nonzero(finite[rows])[0]
        reach = half[rows[ask]] + float(half[idx].max()) + 1e-9 * scale
        for k, js in zip(ask.tolist(), cKDTree(centre[idx]).query_ball_point(centre[rows[ask]], reach, p=np.inf)):
            found[k] = js
    out = []
    for k, i in enumerate(rows.tolist()):
        cand = np.arange(len(boxes)) if not finite[i] else np.union1d(idx[np.asarray(found[k], dtype=np.int64)], always)
        b, bi = boxes[cand], boxes[i]
        over = (b[:, 0] <= bi[2]) & (b[:, 2] >= bi[0]) & (b[:, 1] <= bi[3]) & (b[:, 3] >= bi[1])
        out.append(cand[over])
    return out


def sites_equal(a, b) -> bool:
    """Exact equality of two sites (conics up to a nonzero factor)."""
    if isinstance(a, Circle) and isinstance(b, Circle):
        return a.cx == b.cx and a.cy == b.cy and a.r2 == b.r2
    ca = getattr(a, "coefficients", None)
    cb = getattr(b, "coefficients", None)
    if ca is None or cb is None:
        return False
    ka = next((k for k, v in enumerate(ca) if v != 0), None)
    kb = next((k for k, v in enumerate(cb) if v != 0), None)
    if ka != kb or ka is None:
        return False
    return all(x * cb[ka] == y * ca[ka] for x, y in zip(ca, cb))

