"""The kinds of site, enumerated once.

A site is a point, a circle, a proper conic (ellipse, hyperbola, parabola: thesis §4.4, App. B) or
an elementary piece of a segment, circular-arc or elliptic-arc site (thesis §2.2: the open interior
of the piece; its endpoints are point sites).  Geometries, readers and
messages spell a kind as a lower-case word (``"ellipse"``: :attr:`SiteKind.label`); flat arrays
of sites store its integer code (an :class:`enum.IntEnum`, as CGAL's predicates return enums
rather than bare integers).  Both spellings come from :class:`SiteKind`, so a kind added here is
added everywhere: see ``docs/architecture.md`` ("Where to add things") for the rest of a new kind.

The codes of the first five kinds (point 0 … parabola 4) are the ones the verifier's flat site
table has always stored; the elementary sites of a segment diagram store point 0, segment 5, arc 6
and elliptic arc 7 (so ``kind >= ARC`` selects the curved pieces).

>>> SiteKind.of("ellipse"), SiteKind.ELLIPSE.label, int(SiteKind.ELLIPSE)
(<SiteKind.ELLIPSE: 2>, 'ellipse', 2)
>>> SiteKind.of("hyperbola").bounded, SiteKind.of("circle").circular
(False, True)
"""
from __future__ import annotations

import enum

__all__ = ["SiteKind", "KeyedSite"]


class SiteKind(enum.IntEnum):
    """The kind of a site; ``int(kind)`` is its code in flat arrays, :attr:`label` its word."""

    POINT = 0
    CIRCLE = 1
    ELLIPSE = 2
    HYPERBOLA = 3
    PARABOLA = 4
    SEGMENT = 5
    ARC = 6
    ELLIPTIC_ARC = 7

    @property
    def label(self) -> str:
        """The lower-case word of the kind (``"circle"``), as geometries and documents spell it."""
        return self.name.lower()

    @classmethod
    def of(cls, kind: str | int) -> SiteKind:
        """The kind spelt ``kind``: a label (``"parabola"``), a code or a :class:`SiteKind`.

        Raises ValueError for anything else."""
        if isinstance(kind, str):
            try:
                return _BY_LABEL[kind]
            except KeyError:
                raise ValueError(f"unknown site kind {kind!r} (one of {', '.join(_BY_LABEL)})") from None
        return cls(kind)

    @property
    def bounded(self) -> bool:
        """Whether a site of this kind is a bounded set (hyperbolas and parabolas are not)."""
        return self not in (SiteKind.HYPERBOLA, SiteKind.PARABOLA)

    @property
    def circular(self) -> bool:
        """A point or a circle: a weighted point of the Apollonius diagram (thesis §3.1), whose
        predicates are decided exactly in :mod:`runtime.predicates.circles`."""
        return self in (SiteKind.POINT, SiteKind.CIRCLE)

    @property
    def conic(self) -> bool:
        """A curve of degree 2 (circle, ellipse, hyperbola, parabola; thesis ch. 4)."""
        return self in (SiteKind.CIRCLE, SiteKind.ELLIPSE, SiteKind.HYPERBOLA, SiteKind.PARABOLA)


_BY_LABEL = {k.label: k for k in SiteKind}


class KeyedSite:
    """Equality and hashing of the exact piece sites (segments, circular and elliptic arcs): two
    are equal when they are of one kind (``KIND``, the label of their :class:`SiteKind`, so a
    subclass equals its base) and their exact keys agree; the hash is that of (KIND, *key).
    A subclass defines ``KIND`` and :meth:`key` (a tuple of exact rationals)."""

    __slots__ = ()
    KIND = ""

    def key(self) -> tuple:
        raise NotImplementedError

    def __eq__(self, other) -> bool:
        return isinstance(other, KeyedSite) and other.KIND == self.KIND and self.key() == other.key()

    def __hash__(self) -> int:
        return hash((self.KIND,) + self.key())
