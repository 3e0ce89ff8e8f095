"""Float geometry of a site with rigorous error bounds: the one interface the diagram uses.

The Voronoi diagram of curved sites (thesis §1.2, §5.1–5.2) is decided by one function per
site, the Euclidean distance d(q, S) = min over p ∈ S of |q − p|.  The diagram code (construction
and verification) never asks what kind of site it holds: it talks to a :class:`SiteGeometry`
(the design of CGAL's ``Apollonius_graph_traits_2``: predicates and constructions behind one
traits object).  Each site kind implements

* cheap vectorised **float** evaluations (``distance``, ``foot_points``), used to construct;
* **rigorous bounds** (``distance_bounds``): for every query point q, lo ≤ d(q, S) ≤ hi,
  proved (floating point rounding accounted for), used to decide and to verify;
* a **bounding box** (infinite for unbounded sites) and boundary **samples**.

Every d(·, S) is 1-Lipschitz, so a bound at the centre c of a disc of radius h gives
d(B(c, h), S) ⊂ [lo(c) − h, hi(c) + h]: this is how bounds at points become bounds on regions.

Point and circle sites are implemented here (exact rational data in :mod:`runtime.predicates.circles`;
d(q, C) = | |q − c| − ρ |); conic sites (ellipse, hyperbola, parabola) in
:mod:`runtime.voronoi.conic_geometry`, whose :func:`~runtime.voronoi.conic_geometry.site_geometry`
turns any user site into its geometry.
"""
from __future__ import annotations

import math
from abc import ABC, abstractmethod

import numpy as np

from ..certify.interval_newton import UNIT_ROUNDOFF, gamma
from ..sites.kinds import SiteKind

__all__ = ["SiteGeometry", "PointGeometry", "CircleGeometry", "rounding_slack"]

#: unit roundoff of IEEE double (the kernel's rounding model, :mod:`runtime.certify.interval_newton`)
EPS = UNIT_ROUNDOFF


def rounding_slack(scale, ops: int = 16):
    """A bound on the accumulated rounding error of a float expression of ``ops`` basic
    operations whose intermediate magnitudes are at most ``scale`` (Higham, *Accuracy and
    Stability of Numerical Algorithms*, 2nd ed., §3.1: |error| ≤ γ_n·scale, γ_n = nu/(1−nu),
    :func:`runtime.certify.interval_newton.gamma`), doubled for safety.  Works elementwise on arrays."""
    return 2.0 * gamma(ops) * np.asarray(scale, dtype=float)


class SiteGeometry(ABC):
    """The float geometry of one site, with rigorous bounds.

    Attributes
    ----------
    kind : str
        The :attr:`runtime.sites.kinds.SiteKind.label` of the site: ``"point"``, ``"circle"``,
        ``"ellipse"``, ``"hyperbola"`` or ``"parabola"`` (:attr:`site_kind` is the enum member).
    exact : object
        The exact site: :class:`runtime.sites.circle.Circle` (points: r2 = 0) or
        :class:`runtime.sites.conic.Conic`; certification routes use it.
    """

    kind: str
    exact: object

    @property
    def site_kind(self) -> SiteKind:
        return SiteKind.of(self.kind)

    @property
    def bounded(self) -> bool:
        return SiteKind.of(self.kind).bounded

    @abstractmethod
    def bounding_box(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) containing the whole site (±inf for unbounded sites)."""

    @abstractmethod
    def samples(self, spacing: float, window: tuple[float, float, float, float]) -> np.ndarray:
        """Points of the site (float, within ~1e-15 relative of the curve), an (m, 2) array,
        consecutive points at most ``spacing`` apart along the curve; unbounded sites are
        clipped to ``window`` (xmin, ymin, xmax, ymax).  A point site returns its point."""

    @abstractmethod
    def distance(self, P: np.ndarray) -> np.ndarray:
        """Float Euclidean distance d(q, S) for each row q of the (n, 2) array ``P``."""

    @abstractmethod
    def distance_bounds(self, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Rigorous (lo, hi) with lo ≤ d(q, S) ≤ hi for each row q of ``P`` (floats, rounding
        accounted for).  ``lo`` may be 0 and ``hi`` inf where nothing better is proved."""

    @abstractmethod
    def foot_points(self, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(F, U): for each row q, a closest point F of the site and the unit vector U from F
        towards q (the site's normal at F; any unit vector if q is on the site).  Float."""

    def lower_bound_box(self) -> tuple[float, float, float, float]:
        return self.bounding_box()


class PointGeometry(SiteGeometry):
    """A point site (x0, y0): d(q) = |q − (x0, y0)|."""

    kind = SiteKind.POINT.label

    def __init__(self, exact, x0: float | None = None, y0: float | None = None):
        self.exact = exact
        self.x0 = float(exact.cx) if x0 is None else float(x0)
        self.y0 = float(exact.cy) if y0 is None else float(y0)

    def bounding_box(self):
        return (self.x0, self.y0, self.x0, self.y0)

    def samples(self, spacing, window):
        return np.array([[self.x0, self.y0]])

    def distance(self, P):
        P = np.asarray(P, dtype=float)
        return np.hypot(P[:, 0] - self.x0, P[:, 1] - self.y0)

    def distance_bounds(self, P):
        d = self.distance(P)
        P = np.asarray(P, dtype=float)
        # the centre's float value may be off by half an ulp of the exact rational
        s = rounding_slack(np.abs(P).sum(axis=1) + abs(self.x0) + abs(self.y0))
        return np.maximum(d - s, 0.0), d + s

    def foot_points(self, P):
        P = np.asarray(P, dtype=float)
        F = np.broadcast_to(np.array([self.x0, self.y0]), P.shape).copy()
        V = P - F
        n = np.hypot(V[:, 0], V[:, 1])
        U = np.where(n[:, None] > 0, V / np.where(n > 0, n, 1.0)[:, None], np.array([1.0, 0.0]))
        return F, U


class CircleGeometry(SiteGeometry):
    """A circle site |q − c| = ρ, ρ > 0: d(q) = | |q − c| − ρ | (thesis §3.1)."""

    kind = SiteKind.CIRCLE.label

    def __init__(self, exact, cx: float | None = None, cy: float | None = None, rho: float | None = None):
        self.exact = exact
        self.cx = float(exact.cx) if cx is None else float(cx)
        self.cy = float(exact.cy) if cy is None else float(cy)
        self.rho = math.sqrt(float(exact.r2)) if rho is None else float(rho)

    def bounding_box(self):
        r = self.rho
        return (self.cx - r, self.cy - r, self.cx + r, self.cy + r)

    def samples(self, spacing, window):
        n = max(8, int(math.ceil(2 * math.pi * self.rho / max(spacing, 1e-300))))
        t = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
        return np.column_stack([self.cx + self.rho * np.cos(t), self.cy + self.rho * np.sin(t)])

    def distance(self, P):
        P = np.asarray(P, dtype=float)
        return np.abs(np.hypot(P[:, 0] - self.cx, P[:, 1] - self.cy) - self.rho)

    def distance_bounds(self, P):
        P = np.asarray(P, dtype=float)
        d = self.distance(P)
        s = rounding_slack(np.abs(P).sum(axis=1) + abs(self.cx) + abs(self.cy) + self.rho)
        return np.maximum(d - s, 0.0), d + s

    def foot_points(self, P):
        P = np.asarray(P, dtype=float)
        V = P - np.array([self.cx, self.cy])
        n = np.hypot(V[:, 0], V[:, 1])
        D = np.where(n[:, None] > 0, V / np.where(n > 0, n, 1.0)[:, None], np.array([1.0, 0.0]))
        F = np.array([self.cx, self.cy]) + self.rho * D
        U = np.where((n >= self.rho)[:, None], D, -D)
        return F, U
