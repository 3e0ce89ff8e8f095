"""The unbounded ends of a diagram with elliptic pieces outside the point sites' hull (step 5 of
:mod:`runtime.segments.certificate`), by the affine frame of their ellipse.

Step 5 needs, for every direction u of the circle of directions, the sites of largest support
h_k(u) = max over site k of u·x, where they touch the support line {x : u·x = h(u)}, their order
along it and the side a curve leaves a touching end to (:mod:`runtime.segments.certificate_hull`;
an unbounded edge goes out in direction u between each two consecutive ones; thesis
Prop. 1.2.1: an edge ends at a vertex or at a point at infinity).  All of these are affine
covariant.  Let every elliptic piece lie on one ellipse e(φ) = c + A (cos φ, sin φ), A = [M N]
(columns), Δ = det A > 0 (:class:`runtime.sites.elliptic_arc.EllipticArc`), and F(x) = A⁻¹(x − c)
(exact rationals: :func:`runtime.segments.certificate_ellipse_tails.frame_coords`).  For a compact
set S and w = Aᵀu,

    h_{F(S)}(w) = max over x in S of (Aᵀu)·A⁻¹(x − c) = h_S(u) − u·c,

so the sites of largest support in direction u are those whose images have the largest support in
direction w, touching the image line {X : w·X = h(u) − u·c} at the images of their contacts.  The
line's direction b = (−u_y, u_x) goes to A⁻¹b = b'/Δ with b' = (−w_y, w_x) (A J Aᵀ = Δ J for the
quarter turn J), so the contacts have the same order along the lines and a curve leaving a contact
along ±b leaves its image along ±b'.  u ↦ Aᵀu is linear with determinant Δ > 0: it maps the
circle of directions onto itself preserving its orientation, so the cyclic sequence of tie
directions and of consecutive pairs is the same.  The images are exact: a point or segment goes to
a point or segment with rational data, a piece from frame direction u_a to u_b to the arc of the
unit circle from u_a to u_b (counter-clockwise; its ends are rational, and a point-site end or a
smooth joint stays one).  So the expected ends of the sites are those of the images — found and
proved by the envelope of points, segments and circular arcs of
:func:`runtime.segments.certificate_hull.envelope_ties` (transitions at the tangents from points,
at an arc's end along its radius, at joints; every atom's interval of directions dominated; the
lengths summing to 2π) — with each tie direction w taken back to u = A⁻ᵀw (exact for a rational w,
balls for a tangent's) and each key computed from the sites themselves at u
(:func:`runtime.segments.certificate_hull.infinite_key`).  A circular arc is not mapped to a
circle, and pieces of two ellipses have no common frame: both are refused (a limit), as is
anything the envelope does not decide.

Public API: :func:`frame_infinite_ends`.
"""
from __future__ import annotations

from fractions import Fraction

from ..certify.foot import to_arb
from ..sites.arc import Arc
from ..sites.circle import Point
from ..sites.segment import Segment
from .certificate_ellipse_sites import same_ellipse
from .certificate_ellipse_tails import frame_coords
from .certificate_envelope import Undecided
from .certificate_hull import envelope_ties, infinite_key
from .certificate_sites import ELLIPSE, POINT, SEGMENT, SiteTable

__all__ = ["frame_infinite_ends"]


def _frame_table(T: SiteTable, E) -> SiteTable:
    """The sites' images under F (module docstring), same indices and end codes."""
    img = []
    for k, s in enumerate(T.sites):
        if T.kind[k] == POINT:
            img.append(Point(*frame_coords(E, T.a[k])))
        elif T.kind[k] == SEGMENT:
            img.append(Segment(frame_coords(E, T.a[k]), frame_coords(E, T.b[k])))
        elif T.kind[k] == ELLIPSE and same_ellipse(s, E):
            img.append(Arc((0, 0), 1, s.ua, s.ub))
        else:
            raise Undecided(f"site {k} has no exact image in the frame of the ellipse of the pieces")
    F = SiteTable(img)
    if F.ends != T.ends or [p for p, _ in F.joints] != [frame_coords(E, p) for p, _ in T.joints]:
        raise Undecided("the images in the ellipse's frame do not keep the sites' ends")
    return F


def _back(E, w, rational: bool):
    """u = A⁻ᵀ w: the direction whose image Aᵀu is w (exact, or arb balls)."""
    (Mx, My), (Nx, Ny) = E.M, E.N
    if not rational:
        Mx, My, Nx, Ny = (to_arb(Fraction(q)) for q in (Mx, My, Nx, Ny))
    det = Mx * Ny - My * Nx
    return (w[0] * Ny - My * w[1]) / det, (Mx * w[1] - Nx * w[0]) / det


def frame_infinite_ends(T: SiteTable):
    """The (sorted site pair, key) of every unbounded end of the true diagram of points,
    segments and pieces of one ellipse, with multiplicity (module docstring); a message (str)
    when it is not decided (a limit)."""
    try:
        E = T.sites[min(T.piece)]
        F = _frame_table(T, E)
        out = []
        for pairs, w, rational in envelope_ties(F):
            u = _back(E, w, rational)
            for (i, j), _ in pairs:
                key = infinite_key(T, i, j, u, rational)
                if key is None:
                    raise Undecided(f"the key of the unbounded end of sites {i} and {j} is not decided")
                out.append(((i, j), key))
        return out
    except Undecided as exc:
        return f"the unbounded ends are not decided: {exc}"
