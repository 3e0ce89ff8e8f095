"""The parameters of a drawn bisector's polyline, refined until each chord is close to the curve.

A bisector drawn by a parameter o (an arc's angle, an elliptic piece's foot parameter) is the
polyline through the curve's points at the parameters.  Two refinements share the halving:

* :func:`refined_parameters` halves a step [o_k, o_{k+1}] while the curve's point at the middle
  parameter is more than tol/2 from the step's chord (measured at that one point; the arc
  bisectors of :mod:`runtime.segments.bisectors`, whose certificate bounds each chord by the
  circle's own geometry).
* :func:`interpolation_parameters` halves a step while its estimate of the linear interpolation
  error Δo²/8 · max|γ''| (the error of the chord of a C² curve γ over a step Δo: de Boor,
  *A Practical Guide to Splines*, ch. II, (2.4)) is above tol/2, and returns the largest
  estimate.  This is the bound the certificate of the elliptic edges proves with interval jets
  (:mod:`runtime.segments.certificate_ellipse_curves`, ``sag_bound``), and it can be far above
  the middle point's deviation: where the foot parameter drives the point fast along a nearly
  straight bisector (an edge vertex far out, t(φ) steep), γ'' is mostly tangential, and the
  middle point sits on the chord while the bound is 100 times the tolerance.  max|γ''| over a
  step is estimated from the second differences of the curve at its quarter parameters
  (S_k = γ_{k−1} − 2γ_k + γ_{k+1} = h² γ''(ξ_k) componentwise, h = Δo/4, so Δo²/8 · |γ''| ≈
  2 |S_k|), extrapolated linearly to the step's ends (where γ'' grows towards a far vertex) and
  widened by 5/4 for the growth beyond linear; an estimate, not a proof — the certificate proves
  or refuses each edge by its own bound.  The certificate's other bound, ℓ²κ/8 (arc length ℓ,
  curvature κ), is not aimed at: it encloses κ by max|γ' × γ''| / min|γ'|³ over interval jets,
  up to 36 times a float estimate of it, and polylines refined to a quarter of that estimate
  were refused on 15 of 178 edges of 40 random scenes (none with this one; 3 times the nodes
  of the middle-point refinement on those scenes, 1.3 times on the issue's).

Public API: :func:`refined_parameters`, :func:`interpolation_parameters`,
:func:`interpolation_estimates`.
"""
from __future__ import annotations

import numpy as np

from .distance import distances

__all__ = ["refined_parameters", "interpolation_parameters", "interpolation_estimates"]


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


def interpolation_estimates(curve, o) -> np.ndarray:
    """Per step of ``o`` the estimate of Δo²/8 · max|γ''| over it (module docstring); a step with
    a point where ``curve`` has no root (NaN distance) counts as 0: the callers draw only where
    the curve is defined, and a drawn step there is the certificate's to refuse."""
    o = np.asarray(o, float)
    if len(o) < 2:
        return np.zeros(0)
    q = (o[:-1, None] + np.arange(5)[None, :] / 4 * np.diff(o)[:, None]).ravel()
    V, t = curve(q)
    V = np.asarray(V, float).reshape(len(o) - 1, 5, 2)
    V = np.where(np.isfinite(np.asarray(t, float)).reshape(len(o) - 1, 5, 1) & np.isfinite(V), V, 0.0)
    S = V[:, :-2] - 2 * V[:, 1:-1] + V[:, 2:]                     # (m, 3, 2): h² γ'' at 1/4, 1/2, 3/4
    ends = np.stack([2 * S[:, 0] - S[:, 1], 2 * S[:, 2] - S[:, 1]], axis=1)
    top = np.concatenate([np.hypot(S[..., 0], S[..., 1]), np.hypot(ends[..., 0], ends[..., 1])], axis=1)
    return 2.5 * top.max(axis=1)


def interpolation_parameters(curve, o, tol: float, descending: bool, most: int, rounds: int = 14):
    """(parameters, largest estimate): ``o`` with every step whose interpolation error estimate
    (:func:`interpolation_estimates`) is above tol/2 halved, round after round, until none is
    (or after ``rounds`` rounds, or once there are more than ``most`` parameters); the estimate
    of the parameters returned, so that a caller states at least twice it."""
    o = np.asarray(o, float)
    for k in range(rounds + 1):
        est = interpolation_estimates(curve, o)
        big = est > tol / 2
        if not big.any() or len(o) > most or k == rounds:
            break
        o = np.sort(np.concatenate([o, ((o[:-1] + o[1:]) / 2)[big]]))
        if descending:
            o = o[::-1]
    return o, float(np.max(est, initial=0.0))
