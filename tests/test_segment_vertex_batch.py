"""The float Krawczyk test on many contact systems of points, segments and arcs
(runtime/segments/vertex_batch.py): closed-form vertices, every contact condition at its exact
boundary (where the batch must leave the row to the arb proof) and beside it by 1e-9, and
agreement with the arb Krawczyk proof of the same rows on random scenes."""
from __future__ import annotations

import math
from fractions import Fraction as Q

import numpy as np
import pytest
from flint import arb

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.segments.construction import segment_voronoi
from curvedvoronoi.runtime.segments.elementary import decompose
from curvedvoronoi.runtime.segments.vertex_batch import code_systems, prove_zeros_batch
from curvedvoronoi.runtime.segments.vertices import common_point, contact_equations, prove_zero
from curvedvoronoi.runtime.sites.arc import Arc
from curvedvoronoi.runtime.sites.segment import Segment

from scenes import random_points_off, random_segments


def _site(E, pred):
    return next(i for i in range(len(E.kind)) if pred(i))


def _batch(E, triple, z, seed=None):
    """The batch's verdict on the contact system of ``triple`` at the float centre ``z``."""
    eqs = contact_equations(E, triple, seed if seed is not None else (float(z[0]), float(z[1])))
    K, P = code_systems([eqs])
    return prove_zeros_batch(E, K, P, np.array([z], float), [eqs])[0]


def _contains(box, exact):
    return all(b.contains(arb(str(v.numerator)) / arb(str(v.denominator))) for b, v in zip(box, exact))


def _two_points_and_segment(a):
    """Points (c − 1, 1), (c + 1, 1) and the segment from (a, 0) to (5, 0) with c = 1: the vertex
    is (1, 1) of radius 1 (x = 1 by symmetry, then 1 + (y − 1)² = y²); the segment's foot
    parameter there is (1 − a)/(5 − a): 0 exactly when a = 1."""
    E = decompose([Segment((a, 0), (5, 0)), Point(0, 1), Point(2, 1)])
    seg = _site(E, lambda i: E.kind[i] != 0)
    p0 = _site(E, lambda i: E.kind[i] == 0 and tuple(E.xy[i]) == (0, 1))
    p1 = _site(E, lambda i: E.kind[i] == 0 and tuple(E.xy[i]) == (2, 1))
    return E, (p0, p1, seg)


def test_a_closed_form_vertex_of_two_points_and_a_segment_is_proved_with_its_exact_zero_in_the_box():
    E, triple = _two_points_and_segment(-5)
    sol = _batch(E, triple, (1.0 + 1e-13, 1.0 - 1e-13, 1.0))
    assert sol is not None and sol.status == "proved"
    assert _contains(sol.box, (Q(1), Q(1), Q(1)))
    # the arb proof of the same system finds the same zero
    arb_sol = prove_zero(E, triple, contact_equations(E, triple, (1.0, 1.0)), np.array([1.0, 1.0, 1.0]), 6.0)
    assert arb_sol.status == "proved" and all(a.overlaps(b) for a, b in zip(sol.box, arb_sol.box))


@pytest.mark.parametrize("a, proved", [(Q(1) - Q(1, 10 ** 9), True), (Q(1), False), (Q(1) + Q(1, 10 ** 9), False)])
def test_the_segment_foot_parameter_is_decided_only_strictly_inside(a, proved):
    # foot parameter (1 − a)/(5 − a): 2.5e-10 inside, exactly 0 (the segment's end: a degenerate
    # contact the arb route reports), −2.5e-10 (the contact is not on the segment)
    E, triple = _two_points_and_segment(a)
    sol = _batch(E, triple, (1.0, 1.0, 1.0))
    assert (sol is not None) == proved


@pytest.mark.parametrize("ulps", [-1, 1])
def test_a_centre_an_ulp_off_the_exact_zero_does_not_decide_a_foot_exactly_at_the_end(ulps):
    # c = 1/3: points (c ∓ 1, 1) and the segment from (c, 0): the exact foot parameter is 0, while
    # the float centre one ulp right of fl(1/3) puts it above 0 in floats -- only the rounding
    # bound of the foot's numerator keeps the row undecided
    c = Q(1, 3)
    E = decompose([Segment((c, 0), (5, 0)), Point(c - 1, 1), Point(c + 1, 1)])
    seg = _site(E, lambda i: E.kind[i] != 0)
    pts = [i for i in range(len(E.kind)) if E.kind[i] == 0 and E.xy[i][1] == 1]
    x = float(c)
    x = np.nextafter(x, np.inf) if ulps > 0 else x
    assert _batch(E, (pts[0], pts[1], seg), (x, 1.0, 1.0)) is None


def _arc_and_two_points(start, end):
    """The arc of the circle |q| = 5 from ``start`` to ``end`` (counter-clockwise) and the points
    (8, ±1): the vertex outside the arc is (20/3, 0) of radius 5/3 ((x − 8)² + 1 = (x − 5)²),
    touching the circle in the direction (1, 0)."""
    E = decompose([Arc((0, 0), 5, start, end), Point(8, 1), Point(8, -1)])
    arc = _site(E, lambda i: E.kind[i] != 0)
    pts = [i for i in range(len(E.kind)) if E.kind[i] == 0 and abs(E.xy[i][1]) == 1 and E.xy[i][0] == 8]
    return E, (pts[0], pts[1], arc)


@pytest.mark.parametrize("start, end, proved", [((4, -3), (0, 5), True),     # (1, 0) strictly inside
                                                ((5, 0), (0, 5), False),     # (1, 0) is the arc's end
                                                ((4, 3), (0, 5), False),     # (1, 0) outside the arc
                                                ((-3, -4), (-3, 4), True),   # a reflex arc around it
                                                ((-3, 4), (-3, -4), False)])  # its complement
def test_the_arc_contact_direction_is_decided_only_strictly_inside_the_arc(start, end, proved):
    E, triple = _arc_and_two_points(start, end)
    sol = _batch(E, triple, (20 / 3, 0.0, 5 / 3), seed=(7.0, 0.0))
    assert (sol is not None) == proved
    if proved:
        assert _contains(sol.box, (Q(20, 3), Q(0), Q(5, 3)))


def test_a_zero_of_negative_radius_is_not_a_vertex():
    # three points (0, 0), (2, 0), (0, 2): the squared equations have the zeros (1, 1, ±√2)
    E = decompose([Point(0, 0), Point(2, 0), Point(0, 2)])
    assert _batch(E, (0, 1, 2), (1.0, 1.0, -math.sqrt(2))) is None
    sol = _batch(E, (0, 1, 2), (1.0, 1.0, math.sqrt(2)))
    assert sol is not None and sol.box[2].contains(arb(2).sqrt())


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_batch_agrees_with_the_arb_proof_on_the_vertices_of_random_scenes(seed):
    segs = random_segments(60, seed)
    pieces = [Segment(*s) for s in segs] + [Point(*p) for p in random_points_off(segs, 20, seed)]
    d = segment_voronoi(pieces, certify=False)
    E = decompose(pieces)
    assert len(E.kind) == len(d.sites)
    rows = [v for v in d.vertices if len(v.sites) == 3 and common_point(E, v.sites) is None and v.radius > 0]
    systems = [contact_equations(E, v.sites, (v.x, v.y)) for v in rows]
    keep = [i for i, s in enumerate(systems) if s is not None]
    K, P = code_systems([systems[i] for i in keep])
    Z = np.array([[rows[i].x, rows[i].y, rows[i].radius] for i in keep])
    fast = prove_zeros_batch(E, K, P, Z, [systems[i] for i in keep])
    assert sum(s is not None for s in fast) >= 0.9 * len(keep)
    for i, sol in zip(keep, fast):
        ref = prove_zero(E, rows[i].sites, systems[i], Z[keep.index(i)], 1.0 + float(np.abs(E.A).max()))
        if sol is not None:
            assert ref.status == "proved", (rows[i].sites, ref.reason)
            assert all(a.overlaps(b) for a, b in zip(sol.box, ref.box))


@pytest.mark.parametrize("b, proved", [(Q(1) + Q(1, 10 ** 9), True), (Q(1), False), (Q(1) - Q(1, 10 ** 9), False)])
def test_the_segment_foot_parameter_at_the_far_end(b, proved):
    # the segment from (−5, 0) to (b, 0) with the vertex (1, 1): foot parameter 6/(b + 5), 1 exactly at b = 1
    E = decompose([Segment((-5, 0), (b, 0)), Point(0, 1), Point(2, 1)])
    seg = _site(E, lambda i: E.kind[i] != 0)
    pts = [i for i in range(len(E.kind)) if E.kind[i] == 0 and E.xy[i][1] == 1]
    assert (_batch(E, (pts[0], pts[1], seg), (1.0, 1.0, 1.0)) is not None) == proved


def test_a_centre_off_the_zero_within_its_box_does_not_decide_a_contact_at_an_end():
    # the exact contacts are at an end (foot parameter 0; the arc's start direction), the float
    # centres 1e-13 off on the inner side: only the box's own width keeps the rows undecided
    E, triple = _two_points_and_segment(Q(1))
    assert _batch(E, triple, (1.0 + 1e-13, 1.0, 1.0)) is None
    E, triple = _arc_and_two_points((5, 0), (0, 5))
    assert _batch(E, triple, (20 / 3, 1e-13, 5 / 3), seed=(7.0, 0.0)) is None


@pytest.mark.parametrize("p, proved", [((9, 4), True),            # q = (9, 0): beyond the arc's end e = (5, 0)
                                       ((-3, -4), False),         # q = (0, 0), the arc's centre: λ = 0
                                       ((-9, 4), False)])         # q = (−18/7, 0): behind the centre
def test_the_normal_line_at_an_arc_end_is_decided_only_beyond_the_end(p, proved):
    # the arc |q| = 5 from e = (5, 0) to (0, 5), its end e (a point site) and a point p: the
    # vertex lies on the normal line at e (the x-axis) equidistant from e and p
    E = decompose([Arc((0, 0), 5, (5, 0), (0, 5)), Point(*p)])
    arc = _site(E, lambda i: E.kind[i] != 0)
    e = _site(E, lambda i: E.kind[i] == 0 and tuple(E.xy[i]) == (5, 0))
    q = _site(E, lambda i: E.kind[i] == 0 and tuple(E.xy[i]) == p)
    x = {(9, 4): 9.0, (-3, -4): 0.0, (-9, 4): -18 / 7}[p]
    sol = _batch(E, (arc, e, q), (x, 0.0, abs(5 - x)), seed=(x + 0.1, 0.1))
    assert (sol is not None) == proved


def _exact_rows(rng, m):
    """m random contact equations with exact rational data (kinds 0–3) and their float coding."""
    K = rng.integers(0, 4, size=(m, 1))
    data, P = [], np.zeros((m, 1, 4))
    for i in range(m):
        mag = 10.0 ** rng.integers(-3, 6)
        v = [Q(int(rng.integers(-10 ** 6, 10 ** 6)), int(rng.integers(1, 10 ** 4))) * Q(mag) for _ in range(4)]
        if K[i, 0] == 3:
            v[2], v[3] = abs(v[2]) + 1, Q(int(rng.choice([-1, 1])))
        data.append(v)
        if K[i, 0] == 1:
            a, b, c, s = v[0], v[1], v[2], int(rng.choice([-1, 1]))
            data[-1] = [a, b, c, s]
            P[i, 0] = (float(a), float(b), float(c), s * math.sqrt(float(a * a + b * b)))
        else:
            P[i, 0] = [float(t) for t in v]
    return K, P, data


def _exact_eq(kind, v, z):
    """The exact equation's value and gradient at z (arb, 400 bits): point, line, normal, arc."""
    x, y, r = z
    A = [arb(str(t.numerator)) / arb(str(t.denominator)) if isinstance(t, Q) else arb(t) for t in v]
    if kind == 0:
        dx, dy = x - A[0], y - A[1]
        return dx * dx + dy * dy - r * r, (2 * dx, 2 * dy, -2 * r)
    if kind == 1:
        w = A[3] * (A[0] * A[0] + A[1] * A[1]).sqrt()
        return A[0] * x + A[1] * y + A[2] - w * r, (A[0], A[1], -w)
    if kind == 2:
        return A[0] * (x - A[2]) + A[1] * (y - A[3]), (A[0], A[1], arb(0))
    dx, dy, R = x - A[0], y - A[1], A[2] + A[3] * r
    return dx * dx + dy * dy - R * R, (2 * dx, 2 * dy, -2 * A[3] * R)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_residual_and_jacobian_bounds_enclose_the_exact_equations(seed):
    # F within F_rad of the exact equation at the centre; the exact Jacobian at the box's corners
    # within J_rad of the float one (rows are affine or quadratic: the corners bound the box)
    from flint import ctx

    from curvedvoronoi.runtime.segments.vertex_batch import residual_bounds
    rng = np.random.default_rng(seed)
    K, P, data = _exact_rows(rng, 60)
    Z = rng.normal(size=(60, 3)) * 10.0 ** rng.integers(-2, 6, size=(60, 1))
    # half the centres near their row's point or arc centre (x − p small against p: the rounding
    # of the differences decides the point and arc bounds there)
    Z[::2, :2] = P[::2, 0, :2] * (1 + rng.normal(size=(30, 2)) * 10.0 ** rng.integers(-12, -1, size=(30, 1)))
    R = np.abs(Z) * 10.0 ** rng.integers(-15, -3, size=(60, 1))
    F, F_rad, J, J_rad = residual_bounds(K, P, Z, R)
    old = ctx.prec
    ctx.prec = 400
    try:
        for i in range(60):
            f, _ = _exact_eq(int(K[i, 0]), data[i], [arb(float(t)) for t in Z[i]])
            assert abs(f - arb(float(F[i, 0]))) <= arb(float(F_rad[i, 0])), (i, int(K[i, 0]))
            for corner in np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).T.reshape(-1, 3):
                z = [arb(float(Z[i, j])) + int(corner[j]) * arb(float(R[i, j])) for j in range(3)]
                _, g = _exact_eq(int(K[i, 0]), data[i], z)
                for j in range(3):
                    assert abs(g[j] - arb(float(J[i, 0, j]))) <= arb(float(J_rad[i, 0, j])), (i, j)
    finally:
        ctx.prec = old


def test_the_point_bound_covers_a_conversion_error_of_half_an_ulp():
    # p_x = 1 + 2⁻⁵³(1 − 2⁻¹⁰) rounds to 1 (an error of almost u·|p|); at x = 1 + 2⁻⁵² the float
    # difference is 2⁻⁵², the exact one about 2⁻⁵³: F = d² is off by about 0.75·2⁻¹⁰⁴, which the
    # bound u(|p̃| + |d̃|)(2|d̃| + …) ≈ 2⁻¹⁰⁴ covers (half of it would not)
    from curvedvoronoi.runtime.segments.vertex_batch import residual_bounds
    px = Q(1) + Q(1, 2 ** 53) * (1 - Q(1, 2 ** 10))
    K = np.array([[0]])
    P = np.array([[[float(px), 0.0, 0.0, 0.0]]])
    Z = np.array([[1 + 2.0 ** -52, 0.0, 0.0]])
    F, F_rad, _J, _J_rad = residual_bounds(K, P, Z, np.full((1, 3), 1e-300))
    exact = (Q(Z[0, 0]) - px) ** 2
    assert abs(exact - Q(float(F[0, 0]))) <= Q(float(F_rad[0, 0]))
    assert abs(exact - Q(float(F[0, 0]))) > Q(float(F_rad[0, 0])) / 2
