"""The secant identity of an ellipse, for the certificate's edges next to elliptic pieces
(:mod:`runtime.segments.certificate_ellipse_edges`; thesis ch. 4, the offset x = e(φ*) + σ t ν(φ*)
of a conic by its foot point, and §2.2, the ends of a piece as harmless point sites).

For e(φ) = c + cos φ M + sin φ N with det(M, N) > 0, the outward unit normal
ν(φ) = (e'_y, −e'_x)/|e'(φ)| and a point x = e(φ*) + σ t ν(φ*) (σ = ±1, t ≥ 0), for every φ

    |x − e(φ)|² − t² = 4 sin²((φ − φ*)/2) · L(φ),
    L(φ) = |e'(m)|² + σ t det(M, N)/|e'(φ*)|,   m = (φ + φ*)/2,
    |e'(m)|² = (|M|² + |N|²)/2 + (|N|² − |M|²)/2 · cos(φ + φ*) − M·N sin(φ + φ*).

Proof: e(φ) − e(φ*) = 2 sin((φ − φ*)/2) e'(m) (sum-to-product on cos and sin), and
ν(φ*)·e'(m) = (e'(m) × e'(φ*))/|e'(φ*)| = −sin((φ − φ*)/2) det(M, N)/|e'(φ*)|; expanding
|e(φ) − e(φ*) − σ t ν|² − t² gives the product.  The double zero of the left side at the contact
φ = φ* — the first-order degeneracy of every derivative test at a vertex whose contact is a
piece's end — is the factor sin², taken out exactly; L is smooth and its sign is decided by plain
ball arithmetic.  A point q = e(ψ) of the ellipse is given by its exact (cos ψ, sin ψ)
(:func:`on_ellipse`); then cos(ψ + φ*) = cos ψ cos φ* − sin ψ sin φ*.

Consequences used by the edge proof:

* **outside** (σ = +1): L > 0, every point of the ellipse other than the contact is strictly
  farther than t (the convexity of the filled ellipse);
* **inside** (σ = −1), on a **monotone piece** (M ⟂ N, |M| ≠ |N|, the piece in one closed
  quadrant of its frame, i.e. between two consecutive vertices — :func:`monotone_piece`):
  |e'(m)|² = (|M|² + |N|²)/2 + (|N|² − |M|²)/2 · cos 2m is strictly monotone in m on the quadrant,
  and m stays in the piece's range, so L is strictly monotone in φ on the piece and its minimum is
  at an end.  Hence the contact e(φ*) is a nearest point of the closed piece, at distance t,
  exactly when L ≥ 0 at both ends of the piece, i.e. when both ends are at distance ≥ t from x
  (for an end e(ψ) ≠ e(φ*), |x − e(ψ)|² − t² has the sign of L(ψ)); the only other points at
  distance t are ends with L = 0.  At the contact itself L(φ*) = det/|e'(φ*)| · (R(φ*) − t), R the
  radius of curvature: the centre of curvature is where the inner normal stops being nearest;
* **a point of the ellipse as a third site**: |x − e(ψ)| > t ⟺ L(ψ) > 0 whenever φ* ≠ ψ (mod 2π) —
  a sign test without the double zero at a vertex whose contact is that point;
* **the foot curve of a piece and a point E = e(ψ) of its own ellipse** (σ = −1): the foot
  parameter t solving |x − E| = t is t_E(φ) = |e'((φ + ψ)/2)|² |e'(φ)|/det(M, N) (L(ψ) = 0),
  free of the 0/0 of the generic formula at φ = ψ; at φ = ψ it is the radius of curvature, so the
  curve starts at E's centre of curvature (:func:`end_foot_t`).

* **an end E = e(ψ) owning a piece's ties at any point x** (the rule R2 of the edges of E):
  |x − e(φ)|² − |x − E|² = 4 sin((φ − ψ)/2) · W(φ, x),
  W = sin((φ − ψ)/2) |e'(m)|² + e'(m)·(E − x), m = (φ + ψ)/2 (the same sum-to-product), so E
  is the piece's unique nearest point exactly when ±W > 0 on the piece but at ψ (+ when E is the
  start, − the end): no 0/0 at φ = ψ, and W is affine in x (:func:`end_factor`).

Public API: :func:`on_ellipse`, :func:`monotone_piece`, :func:`speed2_mid`,
:func:`secant_factor`, :func:`end_foot_t`, :func:`end_factor`, :func:`end_tangent`.
"""
from __future__ import annotations

from fractions import Fraction

from flint import arb

from ..certify.foot import to_arb

__all__ = ["on_ellipse", "monotone_piece", "speed2_mid", "secant_factor", "end_foot_t", "end_factor",
           "end_tangent"]


def on_ellipse(P, q):
    """(cos ψ, sin ψ), exact rationals, when the rational point q is e(ψ) on the ellipse of piece
    P (c + u M + v N with u² + v² = 1, solved exactly); else None."""
    (cx, cy), (Mx, My), (Nx, Ny) = P.c, P.M, P.N
    det = Fraction(Mx) * Ny - Fraction(My) * Nx
    if det == 0:
        return None
    wx, wy = Fraction(q[0]) - cx, Fraction(q[1]) - cy
    u = (wx * Ny - wy * Nx) / det
    v = (Mx * wy - My * wx) / det
    return (u, v) if u * u + v * v == 1 else None


def _frame(P):
    (Mx, My), (Nx, Ny) = P.M, P.N
    a2 = Fraction(Mx) ** 2 + Fraction(My) ** 2
    b2 = Fraction(Nx) ** 2 + Fraction(Ny) ** 2
    mn = Fraction(Mx) * Nx + Fraction(My) * Ny
    det = Fraction(Mx) * Ny - Fraction(My) * Nx
    return a2, b2, mn, det


def monotone_piece(P) -> bool:
    """M ⟂ N, |M| ≠ |N|, det(M, N) > 0 and the piece's ends (exact directions ``ua``, ``ub``, the
    piece counter-clockwise from ``ua`` to ``ub`` by less than π) in one closed quadrant of the
    frame: then |e'(m)|² is strictly monotone on the piece's parameter range (module docstring)."""
    a2, b2, mn, det = _frame(P)
    if mn != 0 or a2 == b2 or not det > 0:
        return False
    (u0, v0), (u1, v1) = P.ua, P.ub
    if not u0 * v1 - v0 * u1 > 0:
        return False
    return (u0 >= 0 and u1 >= 0 or u0 <= 0 and u1 <= 0) and (v0 >= 0 and v1 >= 0 or v0 <= 0 and v1 <= 0)


def speed2_mid(P, cs, C, S):
    """|e'(m)|² at m = (ψ + φ)/2 from cs = (cos ψ, sin ψ) (exact or balls) and C = cos φ,
    S = sin φ (balls or jets of :mod:`runtime.segments.certificate_ellipse_curves`)."""
    a2, b2, mn, _det = (to_arb(v) for v in _frame(P))
    cp, sp = (v if isinstance(v, arb) else to_arb(v) for v in cs)
    c2 = C * cp - S * sp                      # cos(ψ + φ)
    s2 = S * cp + C * sp                      # sin(ψ + φ)
    return c2 * ((b2 - a2) / 2) + s2 * (-mn) + (a2 + b2) / 2


def secant_factor(P, cs, Phi, T, sigma: int):
    """L(ψ) of the module docstring for the contact parameters Φ* = ``Phi`` (a ball), the
    distances ``T`` (a ball, t ≥ 0) and the side σ: |x − e(ψ)|² − t² = 4 sin²((ψ − φ*)/2)·L(ψ).
    ``cs`` = (cos ψ, sin ψ): exact rationals, or balls (a whole stretch of parameters ψ)."""
    (Mx, My), (Nx, Ny) = (tuple(to_arb(v) for v in P.M), tuple(to_arb(v) for v in P.N))
    det = to_arb(_frame(P)[3])
    C, S = Phi.cos(), Phi.sin()
    tx, ty = C * Nx - S * Mx, C * Ny - S * My
    speed = (tx * tx + ty * ty).sqrt()
    return speed2_mid(P, cs, C, S) + sigma * T * det / speed


def end_foot_t(P, cs, C, S, speed):
    """t_E(φ) = |e'((φ + ψ)/2)|² |e'(φ)|/det(M, N): the distance along the inner normal at e(φ)
    to the point equidistant from e(φ) and E = e(ψ) (cs = (cos ψ, sin ψ); C, S = cos φ, sin φ and
    ``speed`` = |e'(φ)|, balls or jets)."""
    det = to_arb(_frame(P)[3])
    return speed2_mid(P, cs, C, S) * speed / det


def end_tangent(P, psi, Phi):
    """e'(m) at m = (φ + ψ)/2 for φ in ``Phi`` (balls)."""
    m = (Phi + psi) / 2
    c, s = m.cos(), m.sin()
    (Mx, My), (Nx, Ny) = (tuple(to_arb(v) for v in P.M), tuple(to_arb(v) for v in P.N))
    return -s * Mx + c * Nx, -s * My + c * Ny


def end_factor(P, psi, E, Phi, X, Y):
    """W(φ, x) of the module docstring for φ in ``Phi``, the end E = e(ψ) (ψ and E balls) and
    x in the box (X, Y)."""
    tx, ty = end_tangent(P, psi, Phi)
    h = ((Phi - psi) / 2).sin()
    return h * (tx * tx + ty * ty) + tx * (E[0] - X) + ty * (E[1] - Y)
