"""The proof kernel of runtime/certify at its boundaries (issue 31 items 2-3), CGAL-style: inputs on
both sides of each inequality the proofs rely on, with the verdict computed by hand.

* ``strictly_inside``: K ⊂ int(m + [−r, r]) is strict: a ball of radius exactly r around m is NOT
  inside (its end points are on the boundary), radius r·(1 − 2⁻²⁰) is; in the complex case both
  the real and the imaginary part are tested;
* ``krawczyk_image`` on F(x) = x² − 2, m = 3/2, X = m + [−1/10, 1/10], Y = 1/3:
  K = 3/2 − (1/3)(1/4) + (1 − (1/3)[14/5, 16/5])·[−1/10, 1/10] = 17/12 + [−1/150, 1/150]
  (1 − [14/15, 16/15] = [−1/15, 1/15]); √2 = 1.41421… lies in it, 17/12 does not equal √2, so an
  image without its (I − Y J)(X − m) term misses the zero;
* ``krawczyk_inflation``: x² = 2 is proved near 1.4 with √2 in the enclosure (inside X); x² = 0
  (a double zero) and x² = −1 (no real zero) are not proved.
"""
from __future__ import annotations

from fractions import Fraction as F

import pytest
from flint import acb, arb, arb_mat

from curvedvoronoi.runtime.certify.interval_newton import (KrawczykFailure, krawczyk_image, krawczyk_inflation,
                                                          strictly_inside)

R = arb(F(1, 8).numerator) / 8                   # 1/8, exact in binary


@pytest.mark.parametrize("m", [0, 1, -3])
def test_strictly_inside_real_at_the_boundary(m):
    m = arb(m)
    assert not strictly_inside(arb(m, R), m, R)                     # touches m ± r: not interior
    assert not strictly_inside(m + R, m, R)                         # the end point itself
    assert not strictly_inside(m - R, m, R)
    assert strictly_inside(arb(m, R * (1 - arb(2) ** -20)), m, R)   # a hair inside
    assert strictly_inside(m, m, R)
    assert not strictly_inside(arb(m, 2 * R), m, R)


def test_strictly_inside_complex_needs_both_parts():
    m = acb(1, -2)
    inner = R * (1 - arb(2) ** -20)
    assert strictly_inside(acb(arb(1, inner), arb(-2, inner)), m, R)
    assert not strictly_inside(acb(arb(1, R), arb(-2, inner)), m, R)      # real part on the boundary
    assert not strictly_inside(acb(arb(1, inner), arb(-2, R)), m, R)      # imaginary part on the boundary
    assert not strictly_inside(acb(arb(1), arb(-2) + R), m, R)
    assert not strictly_inside(acb(arb(1) - R, arb(-2)), m, R)


def test_krawczyk_image_by_hand():
    m = [arb(3) / 2]
    dX = [arb(0, arb(1) / 10)]
    Y = arb_mat([[arb(1) / 3]])
    YF = Y * arb_mat([[m[0] * m[0] - 2]])
    JX = arb_mat([[2 * (m[0] + dX[0])]])
    (K,) = krawczyk_image(m, YF, Y, JX, dX)
    assert K.contains(arb(2).sqrt())
    assert K.contains(arb(17) / 12 + arb(1) / 150) and K.contains(arb(17) / 12 - arb(1) / 150)
    assert not K.contains(arb(17) / 12 + arb(1) / 140) and not K.contains(arb(17) / 12 - arb(1) / 140)


def _square(c):
    def F_(z):
        return [z[0] * z[0] - c]

    def J_(z):
        return [[2 * z[0]]]
    return F_, J_


def test_krawczyk_inflation_proves_sqrt2_inside_its_box():
    # √2 ∈ (1.41421356237309, 1.41421356237310): the enclosure must meet the zero's ball and, when
    # tight, lie within 1e-12 of it
    K, X = krawczyk_inflation(*_square(2), [arb(1.4)])
    assert K[0].overlaps(arb(2).sqrt()) and X[0].contains(K[0])
    assert float(K[0].lower()) < 1.41421356237309 and float(K[0].upper()) > 1.41421356237310
    K, X = krawczyk_inflation(*_square(2), [arb(1.4142135623730951)])
    assert K[0].overlaps(arb(2).sqrt()) and X[0].contains(K[0]) and K[0].rad() < 1e-12
    assert float(K[0].lower()) < 1.41421356237310 and float(K[0].upper()) > 1.41421356237309


@pytest.mark.parametrize("c, m", [(0, 1e-9), (0, 0.5), (-1, 0.5), (-1, 1e-3)])
def test_krawczyk_inflation_refuses_double_and_missing_zeros(c, m):
    with pytest.raises(KrawczykFailure):
        krawczyk_inflation(*_square(c), [arb(m)])


def test_krawczyk_inflation_complex_zero():
    """z² = −1: the zero i is proved from 1e-9 + (1 + 1e-9) i, and −i is not in its enclosure."""
    K, X = krawczyk_inflation(*_square(-1), [acb(1e-9, 1 + 1e-9)])
    assert K[0].contains(acb(0, 1)) and not K[0].contains(acb(0, -1))
    assert X[0].real.contains(K[0].real) and X[0].imag.contains(K[0].imag)


# ----------------------------------------------------------------------------- zero-dimensionality
# runtime.certify.dimension: the top-degree forms of g_i(x, y, T) (polynomials without R are their
# own circle-space form) must be coprime modulo p, and the affine part finite; every branch where
# that is not established must say "not proven" (False), never True.

def _dim():
    from curvedvoronoi.runtime.certify import dimension
    return dimension


def test_top_forms_with_a_common_factor_are_not_coprime():
    """Tops x·y, x·(x + y), x² share x (a point at infinity of a curve); the whole polynomials
    xy + 1, x² + xy + y, x² + 1 are coprime, so only the top forms show it."""
    d = _dim()
    P = d.DIMENSION_PRIME
    common = [{(1, 1, 0): 1, (0, 0, 0): 1}, {(2, 0, 0): 1, (1, 1, 0): 1, (0, 1, 0): 1}, {(2, 0, 0): 1, (0, 0, 0): 1}]
    assert d._top_forms_coprime(common, P) is False
    coprime = [{(1, 1, 0): 1, (0, 0, 0): 1}, {(2, 0, 0): 1, (0, 1, 0): 1}, {(0, 2, 0): 1, (1, 0, 0): 1}]
    assert d._top_forms_coprime(coprime, P) is True         # tops xy, x², y²: gcd 1


def test_top_form_vanishing_modulo_p_is_not_coprime():
    """p·x² + y has a top form ≡ 0 mod p: the plane at infinity is not excluded (False); with
    (p + 1)·x² + y (top ≡ x²) and x² + 1, y² + 1 the tops x², x², y² are coprime."""
    d = _dim()
    P = d.DIMENSION_PRIME
    rest = [{(2, 0, 0): 1, (0, 0, 0): 1}, {(0, 2, 0): 1, (0, 0, 0): 1}]
    assert d._top_forms_coprime([{(2, 0, 0): P, (0, 1, 0): 1}] + rest, P) is False
    assert d._top_forms_coprime([{(2, 0, 0): P + 1, (0, 1, 0): 1}] + rest, P) is True


@pytest.fixture
def fresh_dimension_cache():
    d = _dim()
    d.clear_dimension_cache()
    yield d
    d.clear_dimension_cache()


def test_without_msolve_zero_dimensionality_is_not_proved(fresh_dimension_cache, monkeypatch):
    import curvedvoronoi.runtime.solve.exact as ex
    from curvedvoronoi.runtime.predicates.locator import demo_configuration

    d = fresh_dimension_cache
    triple = demo_configuration()[:3]
    monkeypatch.setattr(ex, "msolve_available", lambda: False)
    ok, note = d.zero_dimensional(*triple)
    assert ok is False and "not installed" in note


def test_msolve_failure_is_not_a_proof(fresh_dimension_cache, monkeypatch):
    import curvedvoronoi.runtime.solve.exact as ex
    from curvedvoronoi.runtime.predicates.locator import demo_configuration

    d = fresh_dimension_cache
    triple = demo_configuration()[:3]

    def boom(*a, **k):
        raise ex.MsolveError("planted failure")
    monkeypatch.setattr(ex, "msolve_available", lambda: True)
    monkeypatch.setattr(ex, "parametrisation_degree", boom)
    ok, note = d.zero_dimensional(*triple)
    assert ok is False and "planted failure" in note


# ----------------------------------------------------------------------------- foot points
# x² + xy + y² = 1 has a == c but b ≠ 0: an ellipse (semi-axes √(2/3) along (1, 1), √2 along
# (1, −1)), NOT a circle.  From q = (3, 1): (1, 0) is on it and its normal (2x + y, x + 2y) = (2, 1)
# is parallel to q − (1, 0), so (1, 0) is a foot with D = 5; dense sampling of the parametrisation
# gives the farthest foot D = 17.49129813875… (to 1e-9).  The circle x² + y² = 1 from (3, 1) has
# feet at distance √10 ∓ 1.

def test_foot_points_of_an_ellipse_with_equal_diagonal_coefficients():
    from flint import arb as arb_
    from curvedvoronoi.runtime.certify.foot import foot_polynomial, real_feet_ball, working_prec

    fp = foot_polynomial(tuple(F(v) for v in (1, 1, 1, 0, 0, -1)))
    assert not fp.is_circle
    with working_prec(128):
        feet = sorted(real_feet_ball(fp, arb_(3), arb_(1)), key=lambda f: float(f.D.mid()))
    assert len(feet) == 2 and not any(f.possible for f in feet)
    assert feet[0].D.contains(5) and feet[0].px.contains(1) and feet[0].py.contains(0)
    assert abs(float(feet[1].D.mid()) - 17.4912981387565) < 1e-9


def test_foot_points_of_a_circle():
    from flint import arb as arb_
    from curvedvoronoi.runtime.certify.foot import foot_polynomial, real_feet_ball, working_prec

    fp = foot_polynomial(tuple(F(v) for v in (1, 0, 1, 0, 0, -1)))
    assert fp.is_circle
    with working_prec(128):
        feet = sorted(real_feet_ball(fp, arb_(3), arb_(1)), key=lambda f: float(f.D.mid()))
        ref = [(arb_(10).sqrt() - 1) ** 2, (arb_(10).sqrt() + 1) ** 2]
    assert len(feet) == 2 and all(f.D.overlaps(r) for f, r in zip(feet, ref))
    assert all(abs(float(f.D.mid()) - float(r.mid())) < 1e-12 for f, r in zip(feet, ref))
