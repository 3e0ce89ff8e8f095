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
index i.  The elementary sites are then numbered as a batch build of the new list numbers them
(points first, in order of first appearance, then curve interiors), so an edited diagram is, site
for site, the diagram ``voronoi`` builds from the new list.

**Route.**  Each edit builds the diagram of the new list of pieces with
:func:`runtime.segments.construction.segment_voronoi` (passed in as ``build``, so that this module
imports nothing of the construction) and proves it with the whole segment certificate
(:func:`runtime.segments.certificate.verify_segments`), so ``certified`` means exactly what it means
for a batch build.  ``stats["update"]`` says so and why: the local route of thesis §1.2 (conflict
region of the new piece, diagram of a neighbourhood, splice, certificate restricted to the sites
that reach the changed part) is not implemented for segment sites yet.  A new segment that
crosses, touches the interior of, or overlaps an existing piece is refused by the build with the
:class:`runtime.voronoi.site_input.SiteError` of a batch build, naming the input indices.

Public API: :class:`SegmentEdits`.
"""
from __future__ import annotations

import dataclasses

__all__ = ["SegmentEdits"]

#: why an edit of a segment diagram is a rebuild (``stats["update"]``)
REBUILD = "rebuild (segment diagrams: the local update of thesis §1.2 is not implemented for segment sites)"


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
        out = self._rebuild(self.pieces + [site], certify)
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

    def _rebuild(self, pieces, certify):
        out = self.build(pieces, certify=certify)
        out.stats["update"] = REBUILD
        return out


def _deliver(D, out, inplace: bool):
    """``out``, or ``D`` updated to it (``inplace``)."""
    if not inplace:
        return out
    for f in dataclasses.fields(D):
        setattr(D, f.name, getattr(out, f.name))
    if hasattr(out, "elementary"):
        D.elementary = out.elementary
    return D
