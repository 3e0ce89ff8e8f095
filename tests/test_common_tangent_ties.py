"""Sites touching an irrational common tangent of two arcs (the support envelope's ties,
:func:`runtime.segments.certificate_envelope.tangent_ties`), against closed forms.

The circles X (centre (0, 0), radius 1) and Y (centre (10, 0), radius 2) have the outer common
tangent above them with unit normal u = (−1/10, √99/10): u·c + ρ is the same for both,
−0 + 1 = −1 + 2 = 1 = h (the tangent's level, h > 0).  A circle (c, ρ) touches that line from
below iff u·c + ρ = h; for c = (x, 0) this is ρ = 1 + x/10, so the circle about (20, 0) of radius
3 touches it too (three circles with centres on one line and radii linear along it share their
two outer tangents).  The circle about (5, y₃) of radius 1 with y₃ = 502518907/10⁹ <
5/√99 = 0.5025189076… has u·c + ρ = 1/2 + y₃√99/10 = h − 6.26·10⁻¹⁰ (mpmath, 50 digits):
strictly below the tangent, within 10⁻⁶ of the scene's scale (so the float filter keeps it as a
candidate and the exact test must decide it).  Each circle carries its upper half as an arc
(counter-clockwise from (c_x + ρ, c_y) to (c_x − ρ, c_y)), which holds the direction u.
"""
from __future__ import annotations

from fractions import Fraction as F

import mpmath as mp
import pytest
from flint import arb

from curvedvoronoi.runtime.segments.certificate_envelope import Undecided, tangent_ties
from curvedvoronoi.runtime.segments.certificate_sites import SiteTable
from curvedvoronoi.runtime.sites.arc import Arc

Y3 = F(502518907, 10 ** 9)


def _upper_half(cx, cy, r):
    return Arc((cx, cy), r, (cx + r, cy), (cx - r, cy))


def _tangent():
    """("tangent", X, Y, K, C, φ) with φ the direction of u as an arb ball (K, C unused here)."""
    phi = arb.atan2(arb(99).sqrt() / 10, arb(-1) / 10)
    return ("tangent", ("a", 0), ("a", 1), None, None, phi)


def test_the_third_circle_is_below_the_tangent_by_six_tenths_of_a_nanometre():
    """The premise of the next test, in mpmath (50 digits): 0 < h − (u·c + ρ) < 10⁻⁹."""
    with mp.workdps(50):
        gap = 1 - (mp.mpf(-5) / 10 + mp.mpf(Y3.numerator) / Y3.denominator * mp.sqrt(99) / 10 + 1)
        assert mp.mpf("6.2e-10") < gap < mp.mpf("6.3e-10")


def test_an_arc_just_below_an_irrational_common_tangent_does_not_tie():
    """X, Y and the arc about (5, y₃): only X and Y touch the tangent (ties [0, 1]); the third
    arc, 6.26·10⁻¹⁰ below it, neither ties nor leaves the ends undecided."""
    T = SiteTable([_upper_half(0, 0, 1), _upper_half(10, 0, 2), _upper_half(5, Y3, 1)])
    ties, u = tangent_ties(T, _tangent())
    assert ties == [0, 1]
    assert u[0].overlaps(arb(-1) / 10) and u[1].overlaps(arb(99).sqrt() / 10)


def test_an_arc_on_the_irrational_common_tangent_is_not_claimed():
    """X, Y and the arc about (20, 0) of radius 3, which touches the same tangent (module
    docstring): three curves tying on an irrational tangent are a stated limit, reported as
    undecided, never a proof that leaves the third out."""
    T = SiteTable([_upper_half(0, 0, 1), _upper_half(10, 0, 2), _upper_half(20, 0, 3)])
    with pytest.raises(Undecided, match="arc 2 may touch"):
        tangent_ties(T, _tangent())
