"""Bisectors of two elementary sites in closed form, drawn as polylines with a proved deviation.

Thesis §2.2 (harmless sites) and §4 (generalised offsets of degree ≤ 2 here): the bisector of

* two points is their perpendicular bisector (a line);
* an endpoint e and the interior of a segment s ending at e is the perpendicular to s at e;
* a point p and the interior of a segment s (p not an endpoint) is the parabola of focus p and
  directrix the line of s, restricted to the points whose foot lies in s — parametrised here
  by the foot parameter u: v(u) = f(u) + h(u)·n, f(u) = a + u (b − a), n the unit normal on p's
  side and h(u) = |f(u) − p|² / (2 n·(p − f(u)));
* two segment interiors is a line: an angle bisector of their lines, or their mid-parallel.

A chord of a parabola of focal distance δ (curvature ≤ 1/δ) and length L stays within L²/(8δ)
of its arc (the sagitta bound), which sets the sampling density and the stated tolerance; line
edges are drawn as one straight piece (tolerance: rounding of the end points).

Public API: :func:`bisector_kind`, :func:`edge_polyline`, :func:`line_direction`.
"""
from __future__ import annotations

import math

import numpy as np

from .elementary import POINT, ElementarySites

__all__ = ["bisector_kind", "edge_polyline", "line_direction", "parabola_points"]

#: most pieces of one parabolic edge
MAX_PIECES = 4096


def bisector_kind(E: ElementarySites, i: int, j: int) -> str:
    """"points", "perpendicular" (an endpoint and its segment), "parabola" or "segments"."""
    ki, kj = E.kind[i], E.kind[j]
    if ki == POINT and kj == POINT:
        return "points"
    if ki == POINT or kj == POINT:
        p, s = (i, j) if ki == POINT else (j, i)
        return "perpendicular" if E.is_endpoint(p, s) else "parabola"
    return "segments"


def line_direction(E: ElementarySites, i: int, j: int) -> np.ndarray:
    """A unit direction of a straight bisector of kind "points" or "perpendicular"."""
    kind = bisector_kind(E, i, j)
    if kind == "points":
        d = E.A[j] - E.A[i]
    else:
        s = j if E.kind[j] != POINT else i
        d = E.B[s] - E.A[s]
    n = np.array([-d[1], d[0]])
    return n / np.hypot(*n)


def parabola_points(E: ElementarySites, p: int, s: int, u: np.ndarray) -> np.ndarray:
    """Points of the bisector of point site p and segment site s at foot parameters ``u``."""
    a, b, P = E.A[s], E.B[s], E.A[p]
    d = b - a
    n = np.array([-d[1], d[0]]) / np.hypot(*d)
    if np.dot(P - a, n) < 0:
        n = -n
    F = a + u[:, None] * d
    W = P - F
    h = np.einsum("ij,ij->i", W, W) / (2 * (W @ n))
    return F + h[:, None] * n


def _foot(E: ElementarySites, s: int, X) -> float:
    a, b = E.A[s], E.B[s]
    d = b - a
    return float(np.dot(np.asarray(X, float) - a, d) / np.dot(d, d))


def edge_polyline(E: ElementarySites, i: int, j: int, P0, P1, tol: float):
    """The polyline of the edge (i, j) from P0 to P1 (finite points; far points for infinite
    ends, already on the bisector) and its deviation bound from the true arc."""
    P0 = np.asarray(P0, float)
    P1 = np.asarray(P1, float)
    scale = 1.0 + float(np.max(np.abs(np.concatenate([P0, P1]))))
    rounding = 1e-12 * scale
    if bisector_kind(E, i, j) != "parabola":
        return np.array([P0, P1]), rounding
    p, s = (i, j) if E.kind[i] == POINT else (j, i)
    u0, u1 = _foot(E, s, P0), _foot(E, s, P1)
    a, b, P = E.A[s], E.B[s], E.A[p]
    d = b - a
    delta = abs(np.dot(P - a, np.array([-d[1], d[0]]))) / np.hypot(*d)     # focal distance
    fine = parabola_points(E, p, s, np.linspace(u0, u1, 65))
    length = float(np.sum(np.hypot(*np.diff(fine, axis=0).T)))
    n = int(min(MAX_PIECES, max(1, math.ceil(length / math.sqrt(8 * delta * tol)))))
    Q = parabola_points(E, p, s, np.linspace(u0, u1, n + 1))
    Q[0], Q[-1] = P0, P1
    chords = np.hypot(*np.diff(Q, axis=0).T)
    return Q, float(np.max(chords) ** 2 / (8 * delta)) + rounding
