"""Boxes (interval vectors) with outward rounding, and their bridge to ``flint.arb``.

A box is stored as two float numpy arrays ``lo <= hi``.  Evaluation converts each interval
to an arb ball that *contains* it (``arb(mid, rad)`` with the radius rounded up), and arb
results come back with bounds rounded outward (:func:`arb_lo`, :func:`arb_hi`).  This is
the interval vector of thesis §3.3.3 (``I = {(x_1_lo, x_1_hi), ...}``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from flint import arb

_INF = math.inf


def arb_lo(x: arb) -> float:
    """A float <= every point of the ball x (rigorous, outward rounded)."""
    if not x.is_finite():
        return -_INF
    m = float(x.mid())
    r = float(x.rad())
    if r == 0.0 and x.is_exact() and arb(m) == x:
        return m
    v = m - r - (math.ulp(m) + math.ulp(r))
    return math.nextafter(v, -_INF)


def arb_hi(x: arb) -> float:
    """A float >= every point of the ball x (rigorous, outward rounded)."""
    if not x.is_finite():
        return _INF
    m = float(x.mid())
    r = float(x.rad())
    if r == 0.0 and x.is_exact() and arb(m) == x:
        return m
    v = m + r + (math.ulp(m) + math.ulp(r))
    return math.nextafter(v, _INF)


def interval_arb(lo: float, hi: float) -> arb:
    """An arb ball containing [lo, hi] (lo, hi floats)."""
    if lo == hi:
        return arb(lo)
    mid = 0.5 * lo + 0.5 * hi
    rad = max(hi - mid, mid - lo)
    rad = math.nextafter(rad, _INF) * (1 + 2**-50)
    return arb(mid, rad)


@dataclass
class Box:
    lo: np.ndarray
    hi: np.ndarray

    @classmethod
    def from_bounds(cls, bounds) -> "Box":
        lo = np.array([float(b[0]) for b in bounds], dtype=float)
        hi = np.array([float(b[1]) for b in bounds], dtype=float)
        # rationals converted with outward rounding
        for i, b in enumerate(bounds):
            if float(b[0]) > b[0]:
                lo[i] = math.nextafter(lo[i], -_INF)
            if float(b[1]) < b[1]:
                hi[i] = math.nextafter(hi[i], _INF)
        if np.any(lo > hi):
            raise ValueError(f"empty box {bounds}")
        return cls(lo, hi)

    @classmethod
    def from_arbs(cls, xs) -> "Box":
        return cls(np.array([arb_lo(x) for x in xs]), np.array([arb_hi(x) for x in xs]))

    def copy(self) -> "Box":
        return Box(self.lo.copy(), self.hi.copy())

    def __len__(self):
        return len(self.lo)

    @property
    def width(self) -> np.ndarray:
        return self.hi - self.lo

    @property
    def mid(self) -> np.ndarray:
        return 0.5 * self.lo + 0.5 * self.hi

    def arbs(self) -> list[arb]:
        return [interval_arb(a, b) for a, b in zip(self.lo.tolist(), self.hi.tolist())]

    def mid_arbs(self) -> list[arb]:
        return [arb(m) for m in self.mid.tolist()]  # exact floats

    def contains(self, other: "Box") -> bool:
        return bool(np.all(self.lo <= other.lo) and np.all(other.hi <= self.hi))

    def overlaps(self, other: "Box") -> bool:
        return bool(np.all(self.lo <= other.hi) and np.all(other.lo <= self.hi))

    def contains_point(self, p) -> bool:
        p = np.asarray(p, dtype=float)
        return bool(np.all(self.lo <= p) and np.all(p <= self.hi))

    def hull(self, other: "Box") -> "Box":
        return Box(np.minimum(self.lo, other.lo), np.maximum(self.hi, other.hi))

    def inflate(self, factor: float = 1.0, absolute: float | np.ndarray = 0.0) -> "Box":
        m = self.mid
        h = 0.5 * self.width * factor + absolute
        return Box(m - h, m + h)

    def bisect(self, i: int, ratio: float = 0.5) -> tuple["Box", "Box"]:
        s = self.lo[i] + ratio * (self.hi[i] - self.lo[i])
        a, b = self.copy(), self.copy()
        a.hi[i] = s
        b.lo[i] = s
        return a, b

    def intersect_arbs(self, ks) -> "Box | None":
        """Box ∩ (hull of the arb vector ks); None when empty."""
        lo = np.maximum(self.lo, [arb_lo(k) for k in ks])
        hi = np.minimum(self.hi, [arb_hi(k) for k in ks])
        if np.any(lo > hi):
            return None
        return Box(lo, hi)

    def __repr__(self):
        return "Box(" + ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in zip(self.lo, self.hi)) + ")"
