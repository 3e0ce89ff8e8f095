"""A local exact frame: the diagram of sites far from the origin is built next to the origin.

The Voronoi diagram commutes with translations (thesis §1.2: it is defined by distances), so the
diagram of sites S is the diagram of S − t moved by t.  Floats lose absolute precision far from
the origin: samples near (10⁶, 10⁶) have 10⁻¹⁰ resolution, their lifted squares 10⁻⁴, and the
float filters and Krawczyk tests of the construction and of the verifier scale their slack with
the coordinates.  :func:`local_frame` picks t **dyadic** (a multiple of a power of two 2^k at
least the extent of the sites), near the centre of the sites' bounding box, and translates the
sites *exactly* (fmpq centres; a conic's coefficients by the substitution x → x + tx,
y → y + ty, :func:`translate_site`).  The scene at the origin is then the same exact scene, and
absolute coordinates cost nothing but the final rounding of x + t to the user's floats.

**Back-translation** (:meth:`LocalFrame.to_global`).  Vertex coordinates and polyline points x'
(floats of the local frame) become fl(x' + t): the only error is the rounding of that sum to
the nearest double, at most half an ulp of the result (2⁻⁵³·|x' + t|), the resolution of the
user's own coordinates there.  The construction's certificate is computed in the local frame
(on the exact translated sites), so it is a certificate of the diagram before this rounding.

**Verification of a far diagram** (:func:`to_local_frame`, used by
:func:`runtime.voronoi.verify.certificate.verify`).  The diagram's floats are translated by −t
and every difference is checked exact (Knuth's TwoSum: fl(x − t) is exact iff its rounding
error, computed exactly from the same floats, is 0; with t a multiple of 2^k and |x − t| within
2^k·2^52 of x's ulp grid this holds for every coordinate near the sites, Sterbenz's lemma being
the special case t/2 ≤ x ≤ 2t).  When every coordinate translates exactly, the translated
diagram of the translated sites is the reported diagram moved by the isometry x ↦ x − t, so a
proof of the one is a proof of the other; the verifier's tolerances are stated relative to
1 + |x| + |y| (:mod:`runtime.voronoi.verify.vertices`) and become stricter, never looser, in the
local frame.  If some coordinate would round (a vertex 2⁵³ ulps away), nothing is translated
and the diagram is verified where it is.

**Dynamic range** (:func:`check_range`).  The float pipeline proves a scene whose extent (the
side of the bounding box of the bounded sites) is at most :data:`MAX_RANGE` = 2²² times its
smallest feature (the smallest positive radius or conic half-width, the smallest distance
between two centres of circles and points).  Measured with one site moved away along x
(ratio = extent / smallest feature): three unit circles, two near the origin, are certified at
2²³ and not at 2²⁴ (at 2³⁰ the verifier's float Krawczyk matrix was singular: the
"LinAlgError" reported as bad input); ten random circles plus a far one at 2²³, not at 2²⁴;
ten points plus a far one at 2²⁴, not at 2²⁵.  2²² keeps a factor 2 of margin.  Scenes with
conics are proved to a smaller range (ten ellipses plus a far one: certified at 2¹⁴, a
diagram not certified beyond); within :data:`MAX_RANGE` they give a diagram, beyond it the
same error.  Beyond the range the input is refused with one line naming the site farthest
from the others (:class:`RangeRefusal`, a numerical refusal: exit status 3 on the command line),
never a numerical exception.

Public API: :class:`LocalFrame`, :func:`local_frame`, :func:`translate_site`,
:func:`to_local_frame`, :func:`check_range`, :data:`MAX_RANGE`, :class:`RangeRefusal`.
"""
from __future__ import annotations

import copy
import math
from fractions import Fraction

import numpy as np
from flint import fmpq
from scipy.spatial import cKDTree

from ..predicates.circles import Circle, Point
from ..sites.conic import Conic
from ..sites.rationals import parse_rational, to_fraction
from .conic_geometry import site_geometry
from ..result import NumericalRefusal
from .site_input import SiteError, as_site

__all__ = ["LocalFrame", "MAX_RANGE", "RangeRefusal", "check_range", "local_frame", "to_local_frame", "translate_site"]

#: largest extent / smallest feature the float construction and verifier prove (module docstring)
MAX_RANGE = 2.0 ** 22
#: the frame moves the sites when their box centre is farther from the origin than this many extents
FAR = 4.0


def translate_site(site, tx, ty):
    """The site moved by (−tx, −ty), exactly (tx, ty rational): a circle's or point's centre, a
    conic's coefficients by substituting x → x + tx, y → y + ty."""
    if isinstance(site, Point):
        return Point(site.cx - parse_rational(tx, "tx"), site.cy - parse_rational(ty, "ty"))
    if isinstance(site, Circle):
        return Circle(site.cx - parse_rational(tx, "tx"), site.cy - parse_rational(ty, "ty"), site.r2)
    if isinstance(site, Conic):
        a, b, c, d, e, f = site.coefficients
        tx, ty = to_fraction(tx, "tx"), to_fraction(ty, "ty")
        return Conic.from_coefficients(a, b, c, 2 * a * tx + b * ty + d, b * tx + 2 * c * ty + e,
                                       a * tx * tx + b * tx * ty + c * ty * ty + d * tx + e * ty + f)
    raise SiteError(f"not a site: {site!r}")


def _boxes(geoms):
    boxes = np.array([g.bounding_box() for g in geoms], dtype=float)
    bounded = np.array([bool(g.bounded) for g in geoms])
    fin = boxes[bounded] if bounded.any() else boxes[np.isfinite(boxes).all(axis=1)]
    return boxes, fin


def check_range(sites, geoms) -> None:
    """Raise :class:`RangeRefusal` (one line, naming a site) when the extent of the sites exceeds
    :data:`MAX_RANGE` times their smallest feature (see the module docstring)."""
    boxes, fin = _boxes(geoms)
    if len(fin) < 2:
        return
    ext = float(max(fin[:, 2].max() - fin[:, 0].min(), fin[:, 3].max() - fin[:, 1].min()))
    if not math.isfinite(ext):
        raise SiteError("the sites' coordinates overflow double precision")
    feats = []
    centres = []
    for g in geoms:
        if g.kind == "circle":
            feats.append(float(g.rho))
            centres.append((g.cx, g.cy))
        elif g.kind == "point":
            centres.append((g.x0, g.y0))
        elif g.bounded:
            b = g.bounding_box()
            feats.append(min(b[2] - b[0], b[3] - b[1]) / 2)
    if len(centres) > 1:
        C = np.array(centres, float)
        dist, _ = cKDTree(C).query(C, k=2)
        pos = dist[:, 1][dist[:, 1] > 0]
        if len(pos):
            feats.append(float(pos.min()))
    feats = [f for f in feats if f > 0]
    if not feats:
        return
    feat = min(feats)
    if ext <= MAX_RANGE * feat:
        return
    mid = np.array([(boxes[:, 0] + boxes[:, 2]) / 2, (boxes[:, 1] + boxes[:, 3]) / 2]).T
    ok = np.isfinite(mid).all(axis=1)
    med = np.median(mid[ok], axis=0)
    far = np.where(ok, np.hypot(*(mid - med).T), -1.0)
    k = int(np.argmax(far))
    raise RangeRefusal(f"site {k} at ({mid[k, 0]:.6g}, {mid[k, 1]:.6g}) is out of range: the sites span {ext:.3g}, "
                    f"{ext / feat:.3g} times their smallest feature ({feat:.3g}); the diagram is proved up to "
                    f"2^{int(math.log2(MAX_RANGE))} = {MAX_RANGE:.3g} (scale the sites or split the input)")


class RangeRefusal(NumericalRefusal):
    """Valid sites spread over more than :data:`MAX_RANGE` times their smallest feature: not bad
    input, a limit of the float proofs (the command line exits with status 3)."""


class LocalFrame:
    """The translation by the dyadic point (tx, ty) (exact fmpq; ``t`` as floats) from the user's
    frame to the local one: local = global − t."""

    def __init__(self, tx: fmpq, ty: fmpq):
        self.tx, self.ty = parse_rational(tx, "tx"), parse_rational(ty, "ty")
        self.t = np.array([float(self.tx), float(self.ty)])

    def local_sites(self, sites):
        return [translate_site(s, self.tx, self.ty) for s in sites]

    def to_global(self, D, sites):
        """``D`` (a diagram of the local sites) moved by +t in place, its ``sites`` the user's
        ``sites``; the construction state, when present, builds later diagrams in the same frame."""
        tx, ty = self.t
        for v in D.vertices:
            v.x, v.y = float(v.x + tx), float(v.y + ty)
        for e in D.edges:
            e.polyline = np.asarray(e.polyline, float) + self.t
            # each point rounded to the user's float: half an ulp of its coordinates
            big = float(np.abs(e.polyline).max()) if len(e.polyline) else 0.0
            e.tolerance = float(e.tolerance) + 2.0 ** -52 * big
        D.sites = list(sites)
        D.stats["frame"] = [float(tx), float(ty)]
        if D.problems:
            D.problems.append(f"coordinates in the lines above are relative to the local frame's origin "
                              f"({tx:.17g}, {ty:.17g})")
        st = D.construction
        if st is not None:
            st.build = self._wrap_build(st.build)
        return D

    def _wrap_build(self, build):
        frame = self

        def build_in_frame(S, *args, **kw):
            user = list(S.sites)
            S.sites = frame.local_sites(user)
            return frame.to_global(build(S, *args, **kw), user)
        build_in_frame.__wrapped__ = build
        return build_in_frame


def local_frame(sites, geoms=None):
    """(frame, local sites) for the user's ``sites`` (``geoms``: their geometries, if known), after
    :func:`check_range`; frame is None (and the sites are returned as exact sites) when the sites'
    box is within :data:`FAR` extents of the origin."""
    sites = [as_site(s) for s in sites]
    if len(sites) < 2:
        return None, sites
    if geoms is None:
        geoms = [site_geometry(s) for s in sites]
    check_range(sites, geoms)
    _, fin = _boxes(geoms)
    if not len(fin):
        return None, sites
    lo, hi = fin[:, :2].min(axis=0), fin[:, 2:].max(axis=0)
    mid = (lo + hi) / 2
    ext = float(max(hi[0] - lo[0], hi[1] - lo[1]))
    if not np.abs(mid).max() > FAR * ext:
        return None, sites
    k = math.ceil(math.log2(ext)) if ext > 0 else math.floor(math.log2(float(np.abs(mid).max()))) - 20
    g = Fraction(2) ** k
    tx, ty = (round(Fraction(float(m)) / g) * g for m in mid)
    frame = LocalFrame(fmpq(tx.numerator, tx.denominator), fmpq(ty.numerator, ty.denominator))
    return frame, frame.local_sites(sites)


def _two_diff(x, t):
    """fl(x − t) and its exact rounding error (Knuth's TwoSum on x and −t)."""
    s = x - t
    bb = s - x
    err = (x - (s - bb)) + (-t - bb)
    return s, err


def to_local_frame(D, sites=None):
    """(diagram, sites) moved into the local frame of the sites (``sites`` or the diagram's own)
    when that frame moves them and every float of the diagram translates exactly; else unchanged.
    The diagram is copied (the caller's is not modified)."""
    base = list(D.sites) if sites is None else list(sites)
    try:
        frame, local = local_frame(base)
    except (SiteError, ValueError, TypeError):
        return D, sites             # out of range or malformed: the verifier reports it where it is
    if frame is None:
        return D, sites
    V = np.array([[v.x, v.y] for v in D.vertices], float).reshape(-1, 2)
    Ps = [np.asarray(e.polyline, float).reshape(-1, 2) for e in D.edges]
    allp = np.vstack([V] + Ps) if len(Ps) or len(V) else np.zeros((0, 2))
    fin = np.isfinite(allp).all(axis=1)
    _, err = _two_diff(allp[fin], frame.t)
    if (err != 0).any():
        return D, sites
    L = copy.copy(D)
    L.vertices = [copy.copy(v) for v in D.vertices]
    L.edges = [copy.copy(e) for e in D.edges]
    for v in L.vertices:
        v.x, v.y = float(v.x - frame.t[0]), float(v.y - frame.t[1])
    for e, P in zip(L.edges, Ps):
        e.polyline = P - frame.t
    L.frame_offset = (float(frame.t[0]), float(frame.t[1]))     # tolerances stay the user's
    try:
        L.sites = local if sites is None else frame.local_sites(list(D.sites))
    except (SiteError, ValueError, TypeError):
        return D, sites
    return L, (None if sites is None else local)
