"""Ends at infinity in a direction where several sites tie (rows of identical shapes).

Far in direction θ the nearest site maximises the support function h_k(θ) (thesis §1.2;
d_k(m + t·u) = t − h_k(u) + O(W²/t)).  When several sites T tie for the maximum at θ*, far out in
that direction at lateral offset s (q = m + t·u + s·u⊥) the nearest of them is the one whose
support point has the lateral coordinate ℓ_k = h_k'(θ*) closest to s
(d_k = t − h_k + (s − ℓ_k)²/(2t) + O(1/t²)), so the unbounded edges with direction θ* are exactly
those of the pairs of T consecutive in the order of ℓ: parallel edges, as for collinear points.

:func:`tied_sectors` checks the ends proved by :mod:`runtime.voronoi.verify.mirror_tail` in each
such direction: T is found from the floats (h_k within the rounding bound of the maximum) and
proved exactly tied by mirrors parallel to u between lateral neighbours (a reflection in a line
parallel to u preserves h(u): :func:`runtime.predicates.symmetry.mirror_line`) or by exact
support levels (:func:`runtime.voronoi.verify.tied_tail.support_data`); the others are strictly
below.  The proved ends must be exactly the consecutive pairs.  Each direction then
counts as a small sector [θ* − δ⁻, θ* + δ⁺] for the walk around the circle of directions
(:func:`runtime.voronoi.verify.closure.verify_accounting_conics`): on (θ*, θ* + δ⁺] the tied site
s with the largest ℓ strictly maximises h (for k ∈ T: h_s − h_k = (ℓ_s − ℓ_k)·x + ½(h_s'' − h_k'')·x²
with x = θ − θ* and |h''| ≤ ρ + W, the tie at θ* being exact; for k ∉ T: the gap at θ* minus 2W·x),
and symmetrically the smallest ℓ on [θ* − δ⁻, θ*).

Public API: :func:`tied_sectors`.
"""
from __future__ import annotations

import math

import numpy as np

from ...predicates.symmetry import mirror_line
from .tied_tail import same_level, support_data

__all__ = ["tied_sectors"]


def _parallel_mirror(sites, a, b, u):
    """Is the tie of sites a and b in the rational direction u proved: by a mirror line parallel
    to u mapping a onto b, or by exact support levels (:func:`runtime.voronoi.verify.tied_tail.
    support_data` and :func:`same_level`, when u is a unit vector)?"""
    ml = mirror_line(sites[a], sites[b])
    if ml is not None and ml[0][0] * u[0] + ml[0][1] * u[1] == 0:
        return True
    if u[0] * u[0] + u[1] * u[1] != 1:
        return False
    da, db = support_data(sites[a], u), support_data(sites[b], u)
    return da is not None and db is not None and same_level(da, db)


def tied_sectors(sup, sites, mirror_ends, problems):
    """The small sectors of the directions with mirror-proved ends (module docstring): a list of
    (θ* − δ⁻, θ* + δ⁺, first pair, edge id, last pair) for the walk, or None (problem recorded).
    ``mirror_ends``: (θ, pair, ("mirror", (ux, uy), lateral), edge id) records."""
    groups: dict = {}
    for th, pair, (_, u, _lat), eid in mirror_ends:
        key = _direction_key(u)
        groups.setdefault(key, []).append((th, tuple(int(s) for s in pair), eid, u))
    out = []
    n = sup.n
    for key, ends in groups.items():
        u = ends[0][3]
        th = math.atan2(float(u[1]), float(u[0]))
        hv = sup.h(np.arange(n), np.full(n, th))
        top = float(hv.max())
        cand = [int(k) for k in np.nonzero(hv >= top - 8 * sup.mu)[0]]
        lat = sup.hp(np.array(cand), np.full(len(cand), th))
        order = [cand[t] for t in np.argsort(lat, kind="stable")]
        ls = sorted(lat.tolist())
        if any(b - a <= 4 * sup.mu for a, b in zip(ls, ls[1:])):
            problems.append(f"sites {', '.join(map(str, order))} tie at infinity at {math.degrees(th):.6g} degrees "
                            "with support points too close to order")
            return None
        for a, b in zip(order, order[1:]):
            if not _parallel_mirror(sites, a, b, u):
                problems.append(f"sites {a} and {b} nearly tie at infinity at {math.degrees(th):.6g} degrees, "
                                "but no mirror proves the tie")
                return None
        want = sorted(tuple(sorted((a, b))) for a, b in zip(order, order[1:]))
        got = sorted(tuple(sorted(p)) for _, p, _, _ in ends)
        if want != got:
            problems.append(f"the unbounded edges at {math.degrees(th):.6g} degrees are between sites "
                            f"{got}, expected the neighbours {want} of the sites tied there")
            return None
        lat_of = dict(zip(cand, lat.tolist()))
        others = [k for k in range(n) if k not in lat_of]
        gap = top - float(hv[others].max()) - 2 * sup.mu if others else math.inf
        deltas = []
        for s, sign in ((order[-1], 1), (order[0], -1)):
            lim = [gap / (2 * sup.W)] if others else []
            for k in order:
                if k == s:
                    continue
                d = sign * (lat_of[s] - lat_of[k]) - 2 * sup.mu
                C = 0.5 * (sup.rcurv[s] + sup.rcurv[k]) + sup.W
                lim.append(d / C)
            delta = 0.5 * min(lim) if lim else 0.1
            if not delta > 0:
                problems.append(f"the sites tied at infinity at {math.degrees(th):.6g} degrees cannot be separated")
                return None
            deltas.append(min(delta, 0.1))
        first = tuple(sorted((order[0], order[1])))
        last = tuple(sorted((order[-2], order[-1])))
        eid_first = next(e for _, p, e, _ in ends if tuple(sorted(p)) == first)
        a0 = (th - deltas[1]) % (2 * math.pi)
        out.append((a0, a0 + deltas[1] + deltas[0], first, eid_first, last))
    return out


def _direction_key(u):
    """A hashable key of the direction of the rational vector u (positive multiples identified)."""
    from fractions import Fraction

    x, y = Fraction(u[0]), Fraction(u[1])
    s = abs(x) if x != 0 else abs(y)
    return (x / s, y / s)
