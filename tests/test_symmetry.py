"""A common axis of symmetry (runtime/sites/symmetry.py) and the exact solve on the quotient by the
reflection (runtime/solve/exact.symmetric_boxes).

* the axis is checked independently of how it was found: every conic takes the same exact value at
  a random rational point and at its mirror image (reflection in the line, a rational map);
* drawings without a common axis give None;
* the quotient's real solutions equal those of the full system (msolve on o1 = o2 = o3 = 0 in
  circle space, an independent computation): one quotient box in each full box, the same number.
"""
from __future__ import annotations

import sys
from fractions import Fraction as F
from pathlib import Path

import numpy as np
import pytest

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.sites.symmetry import common_axis, in_axis_frame
from curvedvoronoi.runtime.solve import exact

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_nongeneric import random_nongeneric  # noqa: E402
from reference import reference_vertices  # noqa: E402


def _assert_oracle_vertices(cs, res, count: int) -> None:
    """``res`` certified and complete, with the oracle's ``count`` vertices (x, y and radius to
    1e-7 relative; tests/reference.py: distances and mpmath Newton, no offsets, no msolve)."""
    assert res.certified and res.complete, res.notes
    ref = reference_vertices(*cs[:3])
    assert len(ref) == len(res.vertices) == count
    for x, y, r in ref:
        assert sum(abs(v.x - float(x)) <= 1e-7 * (1 + abs(float(x))) and abs(v.y - float(y)) <= 1e-7 * (1 + abs(float(y)))
                   and abs(v.radius - float(r)) <= 1e-7 * (1 + float(r)) for v in res.vertices) == 1


def _mirror(frame, x, y):
    """Reflection of (x, y) in the line through (x0, y0) with direction (dx, dy) (exact)."""
    dx, dy, k2 = frame.dx, frame.dy, frame.k2
    px, py = x - frame.x0, y - frame.y0
    a = ((dx * dx - dy * dy) * px + 2 * dx * dy * py) / k2
    b = (2 * dx * dy * px + (dy * dy - dx * dx) * py) / k2
    return frame.x0 + a, frame.y0 + b


@pytest.mark.parametrize("kind", ["shared symmetry axis", "coaxial mixed sites"])
@pytest.mark.parametrize("seed", range(6))
def test_common_axis_is_a_line_of_symmetry_of_every_site(kind, seed):
    cs = random_nongeneric(kind, seed)[:3]
    frame = common_axis(cs)
    assert frame is not None
    rng = np.random.default_rng(seed)
    for c in cs:
        for _ in range(5):
            x, y = F(int(rng.integers(-400, 400)), 7), F(int(rng.integers(-400, 400)), 11)
            assert c(x, y) == c(*_mirror(frame, x, y))
        co = in_axis_frame(c, frame).coefficients
        assert co[1] == co[4] == 0
    # the frame's axis is a symmetry line, and a line that is not one is refused: shift one site
    a, b, cc, d, e, f = cs[2].coefficients
    moved = Conic.from_coefficients(a, b, cc, d + a, e + b / 2 + cc, f)
    assert common_axis([cs[0], cs[1], moved]) is None


@pytest.mark.parametrize("kind", ["identical translated ellipses", "collinear centres", "equal circles"])
def test_no_common_axis(kind):
    assert common_axis(random_nongeneric(kind, 0)[:3]) is None


def test_circles_on_a_line_share_it():
    cs = [Conic.circle((0, 0), 1), Conic.circle((3, 4), 2), Conic.ellipse((6, 8), (2, 1), (F(3, 5), F(4, 5)))]
    frame = common_axis(cs)
    assert frame is not None and frame.k2 == 1          # a Pythagorean direction: a rotation


@pytest.mark.parametrize("seed,spread", [(0, 1), (3, 1), (5, 1), (2, 100), (10, 100)])
def test_quotient_solutions_equal_the_full_systems(seed, spread):
    cs = random_nongeneric("shared symmetry axis", seed, spread)[:3]
    frame = common_axis(cs)
    quotient = exact.symmetric_boxes(*cs, frame)
    full = [exact.world_box(b) for b in exact.real_boxes(exact.circle_space_system(exact.exact_triple_system(*cs)))]
    assert len(quotient) == len(full)

    def meets(p, q):
        return all(lo <= h2 and l2 <= hi for (lo, hi), (l2, h2) in zip(p, q))

    for q in quotient:
        assert sum(meets(q, b) for b in full) == 1
    assert exact._pairwise_disjoint(quotient)


def test_locator_answers_symmetric_drawings_on_the_quotient():
    """A shared-axis drawing 100× apart: the exact route on the quotient answers (0.4–0.6 s where
    the numeric route took up to 2 s), certified, complete, with the independent oracle's vertices
    (tests/reference.py: distances and mpmath Newton, no offsets, no msolve)."""
    from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts
    cs = random_nongeneric("shared symmetry axis", 10, spread=100)
    clear_cache()
    res = locate_conflicts(*cs)
    assert any("solved on the quotient by the reflection" in n for n in res.notes), res.notes
    _assert_oracle_vertices(cs, res, 2)


def test_solution_on_the_axis():
    """Circles of radius 1 centred at u = 0 and u = 10 and an ellipse centred at u = 5 with semi-axes
    3 along the axis and 4 across it (the whole drawing rotated by (3/5, 4/5) and moved): the
    ellipse's centre is at distance 4 from both circles and from the ends of the ellipse's axis
    across (normals through the centre), so (centre, R = 16) solves the offset system on the axis
    (V = 0 in the quotient).  The axis system decides it: one exact point, the other six in mirror pairs, the
    same seven real solutions as the full system, and the locator agrees with the oracle."""
    from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts

    c, s = F(3, 5), F(4, 5)

    def at(u, v):
        return (F(7, 2) + c * u - s * v, F(-1, 3) + s * u + c * v)

    cs = [Conic.circle(at(0, 0), 1), Conic.circle(at(10, 0), 1), Conic.ellipse(at(5, 0), (3, 4), (c, s)),
          Conic.ellipse(at(5, 6), (F(1, 2), F(1, 3)), (c, s))]
    frame = common_axis(cs[:3])
    assert frame is not None and frame.k2 == 1
    quotient = exact.symmetric_boxes(*cs[:3], frame)
    x5, y5 = at(5, 0)
    on = [b for b in quotient if b == ((x5, x5), (y5, y5), (16, 16))]
    assert len(on) == 1
    full = [exact.world_box(b) for b in exact.real_boxes(exact.circle_space_system(exact.exact_triple_system(*cs[:3])))]
    assert len(full) == len(quotient) == 7
    for q in quotient:
        assert sum(all(lo <= h2 and l2 <= hi for (lo, hi), (l2, h2) in zip(q, b)) for b in full) == 1
    clear_cache()
    res = locate_conflicts(*cs)
    assert res.certified and res.complete, res.notes
    assert len(res.vertices) == len(reference_vertices(*cs[:3]))


def test_far_vertices_of_a_coaxial_drawing_are_certified():
    """Two ellipses and a circle centred on one line, 100× apart (a held-out drawing): the two true
    vertices lie 4.7e6 away.  The initial foot points there need 512 bits (the zones around an
    ellipse's singular multipliers overlap below: their radius is 2^(-prec/4) times a root bound
    of the foot polynomial, 1e38); at 64 bits both vertices stayed uncertified.  Certified,
    complete, the oracle's vertices."""
    from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts

    cs = [Conic.from_coefficients(5200, 2160, 6649, 18312000, 33583600, 50631752775),
          Conic.from_coefficients(6649, -2160, 5200, 5044300, 8284000, 5079995275),
          Conic.from_coefficients(17, 0, 17, -30100, -59200, 64862432),
          Conic.from_coefficients(9124, -4800, 5904, 1761828, 1619280, 290718473)]
    assert common_axis(cs[:3]) is not None
    clear_cache()
    res = locate_conflicts(*cs)
    _assert_oracle_vertices(cs, res, 2)


def test_axis_of_irrational_direction_is_a_similarity():
    """Ellipses with rational coefficients but axes along (1, 2)/√5 (an irrational rotation) and a
    circle, centred on one line: the frame is the similarity x = x0 + u − 2v, y = y0 + 2u + v of
    ratio √5 (R scales by k² = 5, no square root).  The quotient's real solutions equal the full
    system's, and the locator equals the oracle."""
    from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts

    def ellipse(cx, cy, A, B):
        c2, s2, cs = F(1, 5), F(4, 5), F(2, 5)          # cos², sin², cos·sin of the direction (1, 2)
        a, c, b = c2 / A ** 2 + s2 / B ** 2, s2 / A ** 2 + c2 / B ** 2, 2 * cs * (1 / A ** 2 - 1 / B ** 2)
        return Conic.from_coefficients(a, b, c, -2 * a * cx - b * cy, -2 * c * cy - b * cx,
                                       a * cx * cx + b * cx * cy + c * cy * cy - 1)

    ox, oy = F(3, 2), F(-1, 3)
    cs = [ellipse(ox, oy, F(2), F(1)), ellipse(ox + 4, oy + 8, F(1, 2), F(3, 2)),
          Conic.circle((ox - 3, oy - 6), F(3, 4)), Conic.circle((ox + 2, oy + 5), F(1, 3))]
    assert cs[0].exact_frame is None                     # the rotation is irrational
    frame = common_axis(cs[:3])
    assert frame is not None and frame.k2 == 5
    quotient = exact.symmetric_boxes(*cs[:3], frame)
    full = [exact.world_box(b) for b in exact.real_boxes(exact.circle_space_system(exact.exact_triple_system(*cs[:3])))]
    assert len(quotient) == len(full) == 8
    assert all(sum(exact._meet(q, b) for b in full) == 1 for q in quotient)
    clear_cache()
    res = locate_conflicts(*cs)
    _assert_oracle_vertices(cs, res, 2)
