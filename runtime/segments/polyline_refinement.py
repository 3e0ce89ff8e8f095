"""The parameters of a drawn bisector's polyline, refined until each chord is close to the curve.

A bisector drawn by a parameter o (an arc's angle, an elliptic piece's foot parameter) is the
polyline through the curve's points at the parameters; a step [o_k, o_{k+1}] is halved while the
curve's point at the middle parameter is more than tol/2 from the step's chord (the deviation is
measured at that one point, not bounded: these polylines are drawings, the certificate bounds
the edges it proves by its own means).  The construction's arc bisectors
(:mod:`runtime.segments.bisectors`) and elliptic bisectors
(:mod:`runtime.segments.ellipse_bisectors`) share it.

Public API: :func:`refined_parameters`.
"""
from __future__ import annotations

import numpy as np

from .distance import distances

__all__ = ["refined_parameters"]


def refined_parameters(curve, o, tol: float, descending: bool, most: int, rounds: int = 14):
    """The parameters ``o`` (a float array in the drawing's order) with every step whose middle
    point is more than tol/2 from its chord halved, round after round, until no step is (or after
    ``rounds`` rounds, or once there are more than ``most`` parameters).  ``curve(o)`` returns
    the points (k × 2) and their distances; ``descending``: o runs downwards (kept after the
    sort of each round)."""
    for _ in range(rounds):
        V, _t = curve(o)
        mid = (o[:-1] + o[1:]) / 2
        Vm, _ = curve(mid)
        big = distances(V[:-1], V[1:], Vm)[0] > tol / 2
        if not big.any() or len(o) > most:
            break
        o = np.sort(np.concatenate([o, mid[big]]))
        if descending:
            o = o[::-1]
    return o
