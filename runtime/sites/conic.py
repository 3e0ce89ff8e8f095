"""Exact real conics and their canonical (Euclidean) frames.

A conic site is the zero set of ``a x² + b xy + c y² + d x + e y + f`` (thesis §3.1 and
§5.1: the sites of the Voronoi diagram are real algebraic curves, here non-degenerate real
conics).  The coefficients are stored *exactly* as :class:`fractions.Fraction`; every
decision (kind, degeneracy, reality, orientation of the canonical frame) is taken with
exact rational arithmetic.  Floating point numbers are produced only for the canonical frame
(:attr:`Conic.frame`), which is computed from the exact data with a correctly enclosing
ball arithmetic (python-flint ``arb``) and rounded once.

Canonical frame convention (also that of ``tests/data/validation_cases.json``)::

    (X, Y) = (cos (x − tx) + sin (y − ty),  −sin (x − tx) + cos (y − ty))
    ellipse   X²/A2 + Y²/B2 = 1      (this module puts the major axis on X: A2 ≥ B2)
    hyperbola X²/A2 − Y²/B2 = 1      (opens along X)
    parabola  Y² = 2 p X,  p > 0     (opens towards +X, vertex at (tx, ty))
    circle    X² + Y² = r2           (cos = 1, sin = 0)

Classification (thesis §3.1; classical invariants of the 3×3 matrix M of the conic):
``disc = b² − 4ac`` (< 0 ellipse, = 0 parabola, > 0 hyperbola), ``det M = 0`` degenerate,
an ellipse is real iff ``(a + c)·det M < 0``.

Length: the exact conic type with its constructors, classification and frame conversions.
"""
from __future__ import annotations

import math
import numbers
from decimal import Decimal
from fractions import Fraction
from functools import cached_property
from typing import Any, Iterable

import flint

from .frame import FRAME_PREC, CanonicalFrame, ExactField, canonical_frame, fraction_sqrt, to_arb_ball
from .rationals import to_fraction  # noqa: F401  (re-exported: part of this module's API)
from ..result import InvalidConicError

__all__ = ["Conic", "CanonicalFrame", "KINDS", "to_fraction", "fraction_sqrt", "rotation_from_degrees",
           "rotation_from_radians"]

KINDS = ("ellipse", "circle", "hyperbola", "parabola")
_PARAM_NAMES = {"ellipse": ("A2", "B2"), "hyperbola": ("A2", "B2"), "parabola": ("p",), "circle": ("r2",)}

#: centre coordinates and sizes (semi-axes, parabola parameter) of a conic must lie within
#: [1/SCALE_LIMIT, SCALE_LIMIT] in magnitude: the float routes square them and form offset
#: coefficients of degree up to 8 in them (thesis App. B).
SCALE_LIMIT = 1e30

#: a pair of numbers (int, Fraction, rational string, float: see :func:`to_fraction`)
Pair = tuple[Any, Any]
#: ``rotation=``: a (cos, sin) pair, or a bare angle in radians of at most 2π, or None
Rotation = tuple[Any, Any] | float | None


# --------------------------------------------------------------------------- conic

class Conic:
    """A non-degenerate real conic ``a x² + b xy + c y² + d x + e y + f = 0`` with exact coefficients.

    Build with :meth:`from_coefficients` or the geometric constructors; see the module
    docstring for the canonical frame convention.  Instances are immutable and hashable;
    two conics compare equal iff their coefficient vectors are proportional (same curve).
    Every constructor takes an optional ``label`` (a string kept through the diagram's JSON and
    GeoJSON; not part of equality).
    """

    __slots__ = ("_coefficients", "_kind", "_det", "__dict__")

    # ---------------------------------------------------------------- construction
    def __init__(self, coefficients: tuple[Fraction, ...], kind: str, det: Fraction, label: str | None = None):
        self._coefficients = coefficients
        self._kind = kind
        self._det = det
        self.label = label

    @classmethod
    def from_coefficients(cls, a: Any, b: Any, c: Any, d: Any, e: Any, f: Any, *,
                          label: str | None = None) -> "Conic":
        """Validate and classify ``a x² + b xy + c y² + d x + e y + f = 0``.

        Raises :class:`InvalidConicError` (a ValueError) naming the reason: non-finite or
        unreadable input, not a conic (a = b = c = 0), degenerate (det M = 0: line pair,
        double line, single point), imaginary ellipse (no real point), or a canonical frame
        outside the float range (overflow/underflow of centre, axes or parameter).
        """
        names = "abcdef"
        co = tuple(to_fraction(v, f"coefficient {names[i]}") for i, v in enumerate((a, b, c, d, e, f)))
        a, b, c, d, e, f = co
        if a == 0 and b == 0 and c == 0:
            raise InvalidConicError("not a conic: the quadratic part a x² + b xy + c y² is zero (a line or nothing)")
        det = (a * c * f + (b * e * d) / 4 - (a * e * e + c * d * d + f * b * b) / 4)
        disc = b * b - 4 * a * c
        if det == 0:
            if disc < 0:
                what = "a single real point (or two conjugate imaginary lines)"
            elif disc > 0:
                what = "a pair of intersecting lines"
            else:
                what = "a pair of parallel lines, a double line or nothing real"
            raise InvalidConicError(f"degenerate conic (det of the 3x3 matrix is 0): {what}")
        if disc < 0:
            if (a + c) * det > 0:
                raise InvalidConicError("imaginary ellipse: the equation has no real point")
            kind = "circle" if (a == c and b == 0) else "ellipse"
        elif disc == 0:
            kind = "parabola"
        else:
            kind = "hyperbola"
        obj = cls(co, kind, det, label)
        obj._check_float_range()
        return obj

    @classmethod
    def from_canonical(cls, kind: str, cos: Any = 1, sin: Any = 0, tx: Any = 0, ty: Any = 0, *,
                       label: str | None = None, **params: Any) -> "Conic":
        """Conic with canonical frame (cos, sin, tx, ty) and parameters A2, B2 / p / r2.

        Exact inputs (int, Fraction, rational strings) give exact, primitive integer
        coefficients, a positive multiple of the canonical equation.  The rotation must then
        satisfy cos² + sin² = 1 exactly.  Float cos/sin are accepted when
        |cos² + sin² − 1| ≤ 1e-12 and are used at their exact binary value (the conic is then
        the image of the canonical one under that almost-orthogonal matrix; its kind is
        preserved exactly).
        """
        if kind not in KINDS:
            raise InvalidConicError(f"unknown conic kind {kind!r} (expected one of {KINDS})")
        need = set(_PARAM_NAMES[kind])
        if set(params) != need:
            raise InvalidConicError(f"{kind} needs parameters {sorted(need)}, got {sorted(params)}")
        cs, sn = cls._rotation(cos, sin)
        txq, tyq = to_fraction(tx, "tx"), to_fraction(ty, "ty")
        prm = {k: to_fraction(v, k) for k, v in params.items()}
        for k, v in prm.items():
            if v <= 0:
                raise InvalidConicError(f"{kind} parameter {k} must be > 0, got {v}")
        g = -(cs * txq + sn * tyq)
        h = sn * txq - cs * tyq
        LX = (cs, sn, g)      # X = cs x + sn y + g
        LY = (-sn, cs, h)     # Y = -sn x + cs y + h
        if kind == "ellipse":
            terms = [(prm["B2"], LX), (prm["A2"], LY)]
            lin, const = None, -prm["A2"] * prm["B2"]
        elif kind == "hyperbola":
            terms = [(prm["B2"], LX), (-prm["A2"], LY)]
            lin, const = None, -prm["A2"] * prm["B2"]
        elif kind == "parabola":
            terms = [(Fraction(1), LY)]
            lin, const = (-2 * prm["p"], LX), Fraction(0)
        else:
            terms = [(Fraction(1), LX), (Fraction(1), LY)]
            lin, const = None, -prm["r2"]
        co = [Fraction(0)] * 6
        for w, (p_, q_, r_) in terms:
            co[0] += w * p_ * p_
            co[1] += w * 2 * p_ * q_
            co[2] += w * q_ * q_
            co[3] += w * 2 * p_ * r_
            co[4] += w * 2 * q_ * r_
            co[5] += w * r_ * r_
        if lin is not None:
            w, (p_, q_, r_) = lin
            co[3] += w * p_
            co[4] += w * q_
            co[5] += w * r_
        co[5] += const
        return cls.from_coefficients(*_primitive(co), label=label)

    @staticmethod
    def _rotation(cos, sin) -> tuple[Fraction, Fraction]:
        is_float = any(isinstance(v, float) or (isinstance(v, numbers.Real) and not isinstance(v, (numbers.Rational, Decimal)))
                       for v in (cos, sin))
        cs, sn = to_fraction(cos, "cos"), to_fraction(sin, "sin")
        n = cs * cs + sn * sn
        if is_float:
            if abs(float(n) - 1.0) > 1e-12:
                raise InvalidConicError(f"rotation (cos, sin) = ({cos!r}, {sin!r}) is not a unit vector")
        elif n != 1:
            raise InvalidConicError(
                f"rotation (cos, sin) = ({cos}, {sin}) is not exactly a unit vector (cos²+sin² = {n}); "
                "use a rational point of the unit circle (Pythagorean triple) or a float angle")
        return cs, sn

    @classmethod
    def _rotation_arg(cls, rotation=None, degrees=None, radians=None) -> tuple[Any, Any]:
        given = [k for k, v in (("rotation", rotation), ("degrees", degrees), ("radians", radians)) if v is not None]
        if len(given) > 1:
            raise InvalidConicError(f"give one of rotation=(cos, sin), degrees= or radians=, got {' and '.join(given)}")
        if degrees is not None:
            return rotation_from_degrees(degrees)
        if radians is not None:
            return rotation_from_radians(radians)
        if rotation is None:
            return 1, 0
        if isinstance(rotation, (tuple, list)):
            if len(rotation) != 2:
                raise InvalidConicError("rotation must be a (cos, sin) pair; give angles as degrees= or radians=")
            return rotation[0], rotation[1]
        if isinstance(rotation, numbers.Real) and not isinstance(rotation, bool):
            th = float(rotation)
            if math.isfinite(th) and abs(th) > 2 * math.pi:
                raise InvalidConicError(
                    f"rotation={rotation!r} is a bare angle above 2π: pass degrees={rotation!r} for an angle in "
                    f"degrees or radians={rotation!r} for one in radians (rotation= takes a (cos, sin) pair)")
            return rotation_from_radians(rotation)
        raise InvalidConicError(f"rotation must be a (cos, sin) pair (or give degrees= or radians=), got {rotation!r}")

    @classmethod
    def ellipse(cls, centre: Pair = (0, 0), axes: Pair = (1, 1), rotation: Rotation = None, *,
                degrees: Any = None, radians: Any = None, label: str | None = None) -> "Conic":
        """Ellipse X²/A² + Y²/B² = 1 with semi-axes ``axes = (A, B)`` (A along the rotated X axis).

        The rotation turns the X axis counter-clockwise from the x axis; give at most one of

        * ``rotation=(cos, sin)``, a unit vector: rationals such as ``("3/5", "4/5")`` keep the
          conic exact; floats must satisfy cos² + sin² = 1 to 1e-12;
        * ``degrees=`` an angle in degrees (multiples of 90 are exact, as in the JSON sites
          format of :mod:`runtime.sites.reader`);
        * ``radians=`` an angle in radians.

        A float angle's cos and sin are taken at their exact binary values, which gives long
        integer coefficients.  A bare number as ``rotation`` is read as radians when
        |θ| ≤ 2π (``rotation=90`` raises a ValueError asking for ``degrees=`` or ``radians=``).
        No rotation by default.  Equal semi-axes give a circle.

        >>> Conic.ellipse(centre=(0, 0), axes=(2, 1), rotation=("3/5", "4/5"))
        Conic(ellipse: 73, -72, 52, 0, 0, -100)
        >>> Conic.ellipse(centre=(0, 0), axes=(2, 1), degrees=90)
        Conic(ellipse: 4, 0, 1, 0, 0, -4)
        """
        A, B = (to_fraction(v, "semi-axis") for v in axes)
        if A <= 0 or B <= 0:
            raise InvalidConicError(f"semi-axes must be > 0, got {axes!r}")
        cs, sn = cls._rotation_arg(rotation, degrees, radians)
        kind = "circle" if A == B else "ellipse"
        if kind == "circle":
            return cls.from_canonical("circle", 1, 0, centre[0], centre[1], r2=A * A, label=label)
        return cls.from_canonical("ellipse", cs, sn, centre[0], centre[1], A2=A * A, B2=B * B, label=label)

    @classmethod
    def hyperbola(cls, centre: Pair = (0, 0), axes: Pair = (1, 1), rotation: Rotation = None, *,
                  degrees: Any = None, radians: Any = None, label: str | None = None) -> "Conic":
        """Hyperbola X²/A² − Y²/B² = 1 with ``axes = (A, B)``, opening along the rotated X axis;
        the rotation as in :meth:`ellipse` (``rotation=(cos, sin)``, ``degrees=`` or ``radians=``)."""
        A, B = (to_fraction(v, "semi-axis") for v in axes)
        if A <= 0 or B <= 0:
            raise InvalidConicError(f"semi-axes must be > 0, got {axes!r}")
        cs, sn = cls._rotation_arg(rotation, degrees, radians)
        return cls.from_canonical("hyperbola", cs, sn, centre[0], centre[1], A2=A * A, B2=B * B, label=label)

    @classmethod
    def parabola(cls, vertex: Pair = (0, 0), p: Any = 1, rotation: Rotation = None, *,
                 degrees: Any = None, radians: Any = None, label: str | None = None) -> "Conic":
        """Parabola Y² = 2pX (opening along the rotated +X axis) with vertex ``vertex`` and
        parameter ``p > 0`` (the focus is at distance p/2 from the vertex); the rotation as in
        :meth:`ellipse` (``rotation=(cos, sin)``, ``degrees=`` or ``radians=``)."""
        cs, sn = cls._rotation_arg(rotation, degrees, radians)
        return cls.from_canonical("parabola", cs, sn, vertex[0], vertex[1], p=p, label=label)

    @classmethod
    def circle(cls, centre: Pair = (0, 0), radius: Any = None, r2: Any = None, *,
               label: str | None = None) -> "Conic":
        """Circle of centre ``centre`` and radius ``radius`` (or squared radius ``r2``)."""
        if (radius is None) == (r2 is None):
            raise InvalidConicError("give exactly one of radius= or r2=")
        if radius is not None:
            rq = to_fraction(radius, "radius")
            if rq <= 0:
                raise InvalidConicError(f"radius must be > 0, got {radius!r}")
            r2 = rq * rq
        return cls.from_canonical("circle", 1, 0, centre[0], centre[1], r2=r2, label=label)

    # ---------------------------------------------------------------- properties
    @property
    def coefficients(self) -> tuple[Fraction, ...]:
        """(a, b, c, d, e, f) exactly as given (not normalised)."""
        return self._coefficients

    @property
    def kind(self) -> str:
        return self._kind

    @property
    def determinant(self) -> Fraction:
        """det of the 3×3 symmetric matrix of the conic (non-zero)."""
        return self._det

    @property
    def discriminant(self) -> Fraction:
        a, b, c = self._coefficients[:3]
        return b * b - 4 * a * c

    @cached_property
    def matrix(self) -> tuple[tuple[Fraction, ...], ...]:
        a, b, c, d, e, f = self._coefficients
        return ((a, b / 2, d / 2), (b / 2, c, e / 2), (d / 2, e / 2, f))

    @cached_property
    def primitive_coefficients(self) -> tuple[int, ...]:
        """Coefficients scaled to coprime integers, first non-zero coefficient positive
        (a canonical representative of the curve; used for equality and hashing)."""
        co = _primitive(self._coefficients)
        first = next(v for v in co if v != 0)
        return tuple(-v for v in co) if first < 0 else tuple(co)

    @cached_property
    def normalized_coefficients(self) -> tuple[Fraction, ...]:
        """Coefficients scaled by a power of two so that max |coefficient| lies in [1, 2)
        (exact; safe to convert to float for coefficients of any size)."""
        m = max(abs(v) for v in self._coefficients)
        k = _floor_log2(m)
        s = Fraction(1, 2 ** k) if k >= 0 else Fraction(2 ** (-k))
        return tuple(v * s for v in self._coefficients)

    @cached_property
    def exact_frame(self) -> CanonicalFrame | None:
        """Canonical frame with Fraction fields when the rotation (hence every field) is rational, else None."""
        try:
            return canonical_frame(self._coefficients, self._kind, ExactField.num, ExactField.sqrt)
        except ExactField.NotRational:
            return None

    def frame_arb(self, prec: int = 128) -> CanonicalFrame:
        """Canonical frame as rigorous flint ``arb`` balls computed at ``prec`` bits."""
        with flint.ctx.workprec(prec):
            ex = self.exact_frame
            if ex is not None:
                return CanonicalFrame(to_arb_ball(ex.cos), to_arb_ball(ex.sin), to_arb_ball(ex.tx), to_arb_ball(ex.ty), ex.kind,
                                      {k: to_arb_ball(v) for k, v in ex.params.items()})
            return canonical_frame(self._coefficients, self._kind, to_arb_ball, lambda q: to_arb_ball(q).sqrt())

    def frame_mp(self, dps: int = 30) -> CanonicalFrame:
        """Canonical frame with mpmath ``mpf`` fields accurate to about ``dps`` digits
        (mpf values created in the current mpmath context)."""
        import mpmath

        prec = int(dps * 3.33) + 64
        fr = self.frame_arb(prec)

        def conv(x: flint.arb):
            m, e = x.mid().man_exp()
            return mpmath.ldexp(mpmath.mpf(int(m)), int(e))

        return CanonicalFrame(conv(fr.cos), conv(fr.sin), conv(fr.tx), conv(fr.ty), fr.kind,
                              {k: conv(v) for k, v in fr.params.items()})

    @cached_property
    def frame(self) -> CanonicalFrame:
        """Canonical frame with float fields (rounded once from a 128-bit ball computation)."""
        fr = self.frame_arb(FRAME_PREC)

        def conv(x: flint.arb) -> float:
            return float(x.mid())

        return CanonicalFrame(conv(fr.cos), conv(fr.sin), conv(fr.tx), conv(fr.ty), fr.kind,
                              {k: conv(v) for k, v in fr.params.items()})

    def _check_float_range(self) -> None:
        """The numeric routes work in floating point on the canonical frame: its centre and sizes
        (semi-axes, parabola parameter) must lie within :data:`SCALE_LIMIT` (squares and offset
        coefficients of degree ≤ 8 in them then stay far from overflow and underflow)."""
        fr = self.frame
        for name, v in (("tx", fr.tx), ("ty", fr.ty), *fr.params.items()):
            if not math.isfinite(v):
                raise InvalidConicError(f"{self._kind}: canonical {name} overflows the float range")
        for name, v in (("centre x", fr.tx), ("centre y", fr.ty)):
            if abs(v) > SCALE_LIMIT:
                raise InvalidConicError(f"{self._kind} {name} = {v:.3g} is outside the supported range "
                                        f"|value| <= {SCALE_LIMIT:g} (rescale the input)")
        for name, v in fr.params.items():
            size = math.sqrt(v) if name != "p" and v > 0 else v
            if v > 0 and not (1 / SCALE_LIMIT <= size <= SCALE_LIMIT):
                raise InvalidConicError(f"{self._kind} size {size:.3g} (semi-axis or parameter) is outside the "
                                        f"supported range [{1 / SCALE_LIMIT:g}, {SCALE_LIMIT:g}] (rescale the input)")
        for name, v in fr.params.items():
            if not (v > 0) or v < 1e-300:
                raise InvalidConicError(f"{self._kind}: canonical parameter {name} underflows the float range")
            if v > 1e300:
                raise InvalidConicError(f"{self._kind}: canonical parameter {name} overflows the float range")

    # ---------------------------------------------------------------- evaluation
    def __call__(self, x, y):
        """Value of the quadratic form at (x, y): exact for int/Fraction inputs, float otherwise."""
        a, b, c, d, e, f = self._coefficients
        if isinstance(x, (int, Fraction)) and isinstance(y, (int, Fraction)) and not isinstance(x, bool):
            return a * x * x + b * x * y + c * y * y + d * x + e * y + f
        a, b, c, d, e, f = (float(v) for v in self._coefficients)
        return a * x * x + b * x * y + c * y * y + d * x + e * y + f

    def sample(self, n: int, extent: float | None = None) -> "list[tuple[float, float]]":
        """``n`` points on the curve (floats), evenly spread in a natural parameter.

        Hyperbolas: both branches (n//2 each), parameter |Y| ≤ ``extent`` (default 4·max(√A2, √B2)).
        Parabolas: |Y| ≤ ``extent`` (default 8p).
        """
        import numpy as np

        if n <= 0:
            return []
        fr = self.frame
        if fr.kind in ("ellipse", "circle"):
            A = math.sqrt(fr.params["A2"] if fr.kind == "ellipse" else fr.params["r2"])
            B = math.sqrt(fr.params["B2"] if fr.kind == "ellipse" else fr.params["r2"])
            th = np.linspace(0, 2 * np.pi, n, endpoint=False)
            X, Y = A * np.cos(th), B * np.sin(th)
        elif fr.kind == "hyperbola":
            A, B = math.sqrt(fr.params["A2"]), math.sqrt(fr.params["B2"])
            L = extent if extent is not None else 4 * max(A, B)
            tmax = math.asinh(L / B)
            n1 = n // 2
            t = np.linspace(-tmax, tmax, max(n1, 1))
            t2 = np.linspace(-tmax, tmax, n - n1) if n - n1 > 0 else np.array([])
            X = np.concatenate([A * np.cosh(t), -A * np.cosh(t2)])[:n]
            Y = np.concatenate([B * np.sinh(t), B * np.sinh(t2)])[:n]
        else:
            p = fr.params["p"]
            L = extent if extent is not None else 8 * p
            Y = np.linspace(-L, L, n)
            X = Y * Y / (2 * p)
        x, y = fr.from_canonical(X, Y)
        return list(zip(map(float, x), map(float, y)))

    # ---------------------------------------------------------------- misc
    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Conic):
            return NotImplemented
        return self.primitive_coefficients == other.primitive_coefficients

    def __hash__(self) -> int:
        return hash(self.primitive_coefficients)

    def __repr__(self) -> str:
        """Exact coefficients when they are short; otherwise (e.g. a float rotation, whose exact
        binary cos/sin give 30-digit integers) the coefficients divided by the largest one, to
        6 significant digits, marked with ``≈``."""
        strs = [str(v) for v in self._coefficients]
        if max(len(t) for t in strs) <= 20:
            return f"Conic({self._kind}: {', '.join(strs)})"
        m = max(abs(v) for v in self._coefficients)
        approx = ", ".join(f"{float(v / m):.6g}" for v in self._coefficients)
        return f"Conic({self._kind} ≈ {approx})"

    def to_dict(self) -> dict:
        """JSON-friendly description: exact coefficient strings, kind, float frame."""
        fr = self.frame
        return {"coefficients": [str(v) for v in self._coefficients], "kind": self._kind,
                "frame": fr.as_dict()}


def _floor_log2(q: Fraction) -> int:
    """floor(log2(q)) for q > 0, exactly."""
    k = q.numerator.bit_length() - q.denominator.bit_length()
    if Fraction(2) ** k > q:
        k -= 1
    elif Fraction(2) ** (k + 1) <= q:
        k += 1
    return k


def _primitive(co: Iterable[Fraction]) -> list[int]:
    co = [Fraction(v) for v in co]
    den = 1
    for v in co:
        den = den * v.denominator // math.gcd(den, v.denominator)
    ints = [int(v * den) for v in co]
    g = 0
    for v in ints:
        g = math.gcd(g, v)
    return [v // g for v in ints] if g else ints


def rotation_from_degrees(angle) -> tuple[Any, Any]:
    """(cos, sin) of an angle in degrees: exact for multiples of 90 (an int, a rational string or
    a float with an integer value), otherwise the floats ``cos``/``sin`` of ``math.radians``."""
    q = to_fraction(angle, "degrees")
    if q.denominator == 1 and q.numerator % 90 == 0:
        return ((1, 0), (0, 1), (-1, 0), (0, -1))[(q.numerator // 90) % 4]
    th = math.radians(float(q))
    return math.cos(th), math.sin(th)


def rotation_from_radians(angle) -> tuple[Any, Any]:
    """(cos, sin) of an angle in radians (0 exact, otherwise floats)."""
    th = float(to_fraction(angle, "radians"))
    if th == 0:
        return 1, 0
    return math.cos(th), math.sin(th)
