"""Insertion and deletion of input pieces in a Voronoi diagram of points and segments (thesis §1.2, §2.2).

**Indices.**  The sites of a segment diagram are *elementary* (:mod:`runtime.segments.elementary`:
every distinct endpoint and isolated point one point site, every segment its open interior), and
``Diagram.sources[k]`` is the input piece elementary site k comes from.  Edits speak of the
**input pieces**, the list the user passed to ``voronoi`` (a :class:`runtime.sites.segment.Segment`,
a point, an arc, a circle): ``insert(piece)`` appends it as input piece N (N = the number of input
pieces so far), and ``delete_site(i)`` removes input piece i — a segment with its interior and its
endpoints, except an endpoint that another remaining piece still has (decomposition of the
remaining pieces, thesis §2.2).  ``renumber="shift"``: input piece j > i becomes j − 1, so the
result is the diagram of ``pieces[:i] + pieces[i+1:]``; ``renumber="last"``: the last piece takes
index i.  A rebuilt diagram numbers its elementary sites as a batch build of the new list does
(points first, in order of first appearance, then curve interiors): site for site the diagram
``voronoi`` builds from that list.  A local insertion keeps the old sites' numbers and appends the
new ones (:mod:`runtime.segments.local_insertion`).

**Routes.**  Inserting a segment or a point into a certified diagram of points and segments is
local (:func:`runtime.segments.local_insertion.insert_locally`: conflict region, local diagram,
splice, the changed part proved with the certificate's routines; its docstring says why the
untouched part's proof carries over).  Otherwise — a deletion, an arc or circle piece, arcs in the
diagram, ``certify=False``, or a local update that does not close or is not proved (a new region
reaching the convex hull, a piece continuing a segment straight through its end, ...) — the diagram
of the new list of pieces is built with :func:`runtime.segments.construction.segment_voronoi`
(passed in as ``build``, so that this module imports nothing of the construction) and proved with
the whole segment certificate, so ``certified`` means what it means for a batch build.
``stats["update"]`` is ``"local"`` or ``"rebuild (why)"``.  A new piece that crosses, touches the
interior of, or overlaps an existing piece is refused by the build with the
:class:`runtime.voronoi.site_input.SiteError` of a batch build, naming the input indices.

Public API: :class:`SegmentEdits`.
"""
from __future__ import annotations

import dataclasses

from ..predicates.circles import Point
from ..sites.segment import Segment, as_point_pair
from .local_insertion import insert_locally

__all__ = ["SegmentEdits"]

#: why an edit of a segment diagram is a rebuild (``stats["update"]``)
REBUILD = "rebuild (deletion from a segment diagram: no local route yet)"


class SegmentEdits:
    """The construction state of a segment diagram: its input ``pieces`` (as passed to the build,
    in input order) and ``build(pieces, certify=...)``, the construction that made it.  Reached by
    :meth:`runtime.voronoi.structure.Diagram.insert` and :meth:`~runtime.voronoi.structure.
    Diagram.delete_site` through ``Diagram.construction``."""

    def __init__(self, pieces, build):
        self.pieces = list(pieces)
        self.build = build

    def insert(self, D, site, *, certify: bool = True, inplace: bool = False):
        """The diagram of ``pieces + [site]`` (module docstring); ``site`` is input piece N."""
        pieces = self.pieces + [site]
        piece = _elementary_piece(site)
        why = "a certify=False update" if not certify else (
            f"a {type(site).__name__} piece" if piece is None else None)
        out = why or insert_locally(D, piece, len(self.pieces), self.build)
        if isinstance(out, str):
            out = self._rebuild(pieces, certify, out)
        else:
            out.construction = SegmentEdits(pieces, self.build)
        out.stats["update_input"] = len(self.pieces)
        return _deliver(D, out, inplace)

    def delete(self, D, i: int, *, certify: bool = True, renumber: str = "shift", inplace: bool = False):
        """The diagram without input piece ``i`` (module docstring for ``renumber``)."""
        if renumber not in ("shift", "last"):
            raise ValueError(f'renumber must be "shift" or "last", not {renumber!r}')
        n = len(self.pieces)
        if isinstance(i, bool) or not isinstance(i, int) or not -n <= i < n:
            raise IndexError(f"input piece {i!r} out of range: the diagram has {n} input pieces "
                             "(delete_site takes the index of an input piece, Diagram.sources[k] for site k)")
        i %= n
        rest = list(self.pieces)
        if renumber == "last" and i < n - 1:
            rest[i] = rest.pop()
        else:
            del rest[i]
        out = self._rebuild(rest, certify)
        out.stats["update_input"] = i
        return _deliver(D, out, inplace)

    def _rebuild(self, pieces, certify, why=None):
        out = self.build(pieces, certify=certify)
        out.stats["update"] = REBUILD if why is None else f"rebuild ({why})"
        return out


def _elementary_piece(site):
    """``site`` as a Segment or a Point when it is one (an (x, y) pair a Point), else None."""
    if isinstance(site, Segment) or (isinstance(site, Point) and site.r2 == 0):
        return site
    if isinstance(site, (tuple, list)) and len(site) == 2:
        try:
            return Point(*as_point_pair(site, "the new site"))
        except (TypeError, ValueError):
            return None
    return None


def _deliver(D, out, inplace: bool):
    """``out``, or ``D`` updated to it (``inplace``)."""
    if not inplace:
        return out
    for f in dataclasses.fields(D):
        setattr(D, f.name, getattr(out, f.name))
    D.elementary = getattr(out, "elementary", None)
    return D
