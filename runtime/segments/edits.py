"""Insertion and deletion of input pieces in a Voronoi diagram of points, segments and arcs (thesis §1.2, §2.2).

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

**Routes.**  Inserting a segment, a circular arc or a point into a certified diagram of points,
segments and arcs is local (:func:`runtime.segments.local_insertion.insert_locally`: conflict
region, local diagram, splice, the changed part proved with the certificate's routines; its
docstring says why the untouched part's proof carries over, for arcs too).  Deleting an input
piece (a segment, an arc or a point) from such a diagram is local too
(:func:`runtime.segments.local_deletion.delete_locally`: the elementary sites it alone has are
removed, the hole they leave is filled from the diagram of the sites around it, and the changed
part is proved the same way; its docstring defines the changed part and says why the rest keeps
its proof).  A deleted piece that does not change the sites (a point that is also a curve's
endpoint) changes only ``sources``.  A circle (of rational radius) is inserted and deleted as its
two halves (:func:`runtime.sites.arc.circle_halves`, as the construction splits it): two arc sites
meeting at smooth joints, no point sites.  Otherwise — an elliptic piece, elliptic pieces in the
diagram, ``certify=False``, a segment merged with
another into one elementary segment, a piece ending at a smooth joint, an edit that would join
two curves straight or smoothly at a point or split such a joint, or a local update that does not
close or is not proved (a new region or the hole reaching the convex hull, ...) — the diagram of
the new list of pieces is built with :func:`runtime.segments.construction.segment_voronoi`
(passed in as ``build``, so that this module imports nothing of the construction) and proved with
the whole segment certificate, so ``certified`` means what it means for a batch build.
``stats["update"]`` is ``"local"`` or ``"rebuild (why)"``.  A new piece that crosses, touches the
interior of, or overlaps an existing piece is refused by the build with the
:class:`runtime.voronoi.site_input.SiteError` of a batch build, naming the input indices.
Deleting the last input piece raises ``ValueError`` (a diagram needs two sites), as
:meth:`runtime.voronoi.structure.Diagram.delete_site` does for point sites.

**State.**  Besides the pieces, the state keeps how many pieces use each point (to tell which
endpoints a deletion removes) and the local updates' :class:`runtime.segments.local_update.
EditIndex` (keys, boxes, vertex and edge arrays); both are built at the first edit of a
batch-built diagram (linear in N) and then updated by each local edit.  A local deletion moves the
last remaining elementary sites into the deleted ones' places
(:func:`runtime.segments.local_deletion.site_moves`); ``sources[k]`` is renumbered with the
pieces (``"last"``: the moved piece's few sites; ``"shift"``: every source above i, one numpy pass
over the list, the one step of a deletion linear in N by its definition), and a kept endpoint
whose piece was deleted takes the first remaining piece ending there (read from the curves ending
there when they account for all its uses, else a scan of the pieces).  With ``inplace=True`` the
diagram's lists and the state's point counts and list of pieces are edited once the update is
proved (a local edit does not copy the list of pieces).

Public API: :class:`SegmentEdits`.
"""
from __future__ import annotations

import dataclasses
from collections import Counter
from fractions import Fraction

import numpy as np

from ..predicates.circles import Point
from ..result import InvalidConicError
from ..sites.arc import Arc, circle_halves
from ..sites.segment import Segment, as_point_pair
from .local_deletion import delete_locally, site_moves
from .local_insertion import insert_locally
from .local_update import EditIndex, curve_ends, curves_ending_at, leaving, opposite, point_key, site_key

__all__ = ["SegmentEdits"]


class SegmentEdits:
    """The construction state of a segment diagram: its input ``pieces`` (as passed to the build,
    in input order) and ``build(pieces, certify=...)``, the construction that made it.  Reached by
    :meth:`runtime.voronoi.structure.Diagram.insert` and :meth:`~runtime.voronoi.structure.
    Diagram.delete_site` through ``Diagram.construction``."""

    def __init__(self, pieces, build, index=None, uses=None, own: bool = False):
        self.pieces = pieces if own else list(pieces)      # own: a list of the edit's, kept as it is
        self.build = build
        self.index = index
        self.uses = uses

    def point_uses(self) -> Counter:
        """How many input pieces have each point (key: :func:`runtime.segments.local_update.point_key`)
        as an end or are that point (None when a piece is neither a segment nor a point)."""
        if self.uses is None:
            uses: Counter = Counter()
            for p in self.pieces:
                pts = _points(p)
                if pts is None:
                    return None
                uses.update(pts)
            self.uses = uses
        return self.uses

    def insert(self, D, site, *, certify: bool = True, inplace: bool = False):
        """The diagram of ``pieces + [site]`` (module docstring); ``site`` is input piece N.  A local
        ``inplace`` insertion appends ``site`` to the list of pieces itself (no copy of N pieces)."""
        n = len(self.pieces)
        parts = _elementary_pieces(site)
        why = "a certify=False update" if not certify else (
            f"a {type(site).__name__} piece" if parts is None else None)
        if why is None and self.point_uses() is None:
            why = "an insertion into a diagram with pieces other than points, segments, circular arcs and circles"
        out = why or insert_locally(D, parts, n, self.build, self.index, inplace=inplace)
        if isinstance(out, str):
            out = self._rebuild(self.pieces + [site], certify, out)
        else:
            uses = self.point_uses()
            if uses is not None:
                uses = uses if inplace else uses.copy()
                uses.update(_points(site))
            pieces = self.pieces if inplace else list(self.pieces)
            pieces.append(site)
            out.construction = SegmentEdits(pieces, self.build, getattr(out, "edit_index", None), uses, own=True)
        out.stats["update_input"] = n
        return _deliver(D, out, inplace)

    def delete(self, D, i: int, *, certify: bool = True, renumber: str = "shift", inplace: bool = False):
        """The diagram without input piece ``i`` (module docstring for ``renumber``)."""
        if renumber not in ("shift", "last"):
            raise ValueError(f'renumber must be "shift" or "last", not {renumber!r}')
        n = len(self.pieces)
        if isinstance(i, bool) or not isinstance(i, int) or not -n <= i < n:
            raise IndexError(f"input piece {i!r} out of range: the diagram has {n} input pieces "
                             "(delete_site takes the index of an input piece, Diagram.sources[k] for site k)")
        if n == 1:
            raise ValueError("the Voronoi diagram needs at least 2 sites: deleting the last input piece "
                             "would leave none")
        i %= n
        moved = renumber == "last" and i < n - 1
        out = self._delete_locally(D, i, moved, inplace) if certify else "a certify=False update"
        if isinstance(out, str):
            out = self._rebuild(_without(list(self.pieces), i, moved), certify, out)
        out.stats["update_input"] = i
        return _deliver(D, out, inplace)

    def _delete_locally(self, D, i: int, moved: bool, inplace: bool):
        """The local route of :meth:`delete`: a Diagram, or a str (why not; D untouched).
        ``inplace``: D's lists (sites, vertices, edges, sources) and its list of pieces are edited
        once the change is proved."""
        uses = self.point_uses()
        parts = _elementary_pieces(self.pieces[i])
        if uses is None or parts is None or D.sources is None:
            return "a deletion from a diagram with pieces other than points, segments, circular arcs and circles"
        index = EditIndex.of(D, self.index)
        keys = index.keys
        pts = _points(self.pieces[i])
        deleted = [keys[p] for p in pts if uses[p] == 1 and p in keys]
        curves = [q for q in parts if isinstance(q, (Segment, Arc))]
        own = [k for q in curves for k in [keys.get(site_key(q))]]
        if None in own:
            return "the segment is part of a merged elementary segment"
        own_ends = [e for q in curves for e in curve_ends(q)]
        if any(point_key(e) not in keys and own_ends.count(e) == 1 for e in own_ends):
            return "the piece ends at a smooth joint (its end becomes a site)"
        deleted += own
        for p in set(pts):
            if uses[p] == 3 and _straight_after(D, index, p, own):
                return "the deletion joins two segments straight or two curves smoothly at a point"
        n = len(D.sites)
        last_keys = _site_keys(self.pieces[-1]) if moved else []
        if deleted:
            out = delete_locally(D, deleted, self.build, index, inplace=inplace)
            if isinstance(out, str):
                return out
        elif inplace:                                    # the sites stay: only the sources change
            out = dataclasses.replace(D, construction=None)
            out.stats = dict(D.stats, update="local")
            out.edit_index = index
        else:                       # the same on lists and keys of its own: an edit in place of it leaves D alone
            out = dataclasses.replace(D, construction=None, sites=list(D.sites), vertices=list(D.vertices),
                                      edges=list(D.edges), problems=list(D.problems))
            out.stats = dict(D.stats, update="local")
            out.edit_index = index.copy()
        new_uses = uses if inplace else uses.copy()
        for p in pts:
            new_uses[p] -= 1
            if new_uses[p] <= 0:
                del new_uses[p]
        new_keys = out.edit_index.keys
        n_pieces = len(self.pieces)
        rest = _without(self.pieces if inplace else list(self.pieces), i, moved)
        sources = D.sources if inplace else list(D.sources)
        for a, b in site_moves(n, deleted).items():
            sources[b] = sources[a]
        del sources[n - len(deleted):]
        at_i = [k for k in (new_keys.get(p) for p in pts) if k is not None and sources[k] == i]
        if moved:                                        # the last piece takes index i
            for k in (new_keys.get(q) for q in last_keys):
                if k is not None and sources[k] == n_pieces - 1:
                    sources[k] = i
        elif i < n_pieces - 1:                   # shift: every piece above i moves down (one numpy pass)
            arr = np.asarray(sources, dtype=np.int64)
            arr -= arr > i
            sources[:] = arr.tolist()
        for k in at_i:                                   # a kept endpoint of the deleted piece
            sources[k] = _first_user(rest, out.sites[k], out.edit_index, out.sites, sources, new_uses)
        out.sources = sources
        out.construction = SegmentEdits(rest, self.build, getattr(out, "edit_index", None), new_uses, own=True)
        return out

    def _rebuild(self, pieces, certify, why):
        out = self.build(pieces, certify=certify)
        out.stats["update"] = f"rebuild ({why})"
        return out


def _without(pieces: list, i: int, moved: bool) -> list:
    """``pieces`` (edited in place) without piece i: the last piece takes its place (``moved``,
    renumber="last") or the later ones move down."""
    if moved:
        pieces[i] = pieces.pop()
    else:
        del pieces[i]
    return pieces


def _points(piece):
    """The point keys an input piece has (its two ends, itself, or a circle's two joints), or None
    for another kind of piece."""
    parts = _elementary_pieces(piece)
    if parts is None:
        return None
    if isinstance(parts[0], Point):
        return [site_key(parts[0])]
    return [point_key(e) for e in curve_ends(parts[0])]      # a circle: its first half's ends are the joints


def _straight_after(D, index, p, own) -> bool:
    """After deleting a piece at the point with key ``p`` (used by 3 pieces now, 2 then): do the
    two curve sites not in ``own`` (the deleted piece's) that end at p continue each other
    (opposite tangents: two segments merge, otherwise a smooth joint; either way p stops being a
    site, :mod:`runtime.segments.elementary`)?"""
    P = (Fraction(p[1], p[2]), Fraction(p[3], p[4]))
    near = index.near((float(P[0]), float(P[1])), (float(P[0]), float(P[1])))
    dirs = [leaving(D.sites[s], P) for s in near if s not in own and P in curve_ends(D.sites[s])]
    return len(dirs) == 2 and opposite(*dirs)


def _site_keys(piece) -> list:
    """The keys of the elementary sites an input piece can be the source of: its curves and its points."""
    parts = _elementary_pieces(piece) or []
    return [site_key(q) for q in parts if isinstance(q, (Segment, Arc))] + (_points(piece) or [])


def _first_user(pieces, site, index, sites, sources, uses) -> int:
    """The first of ``pieces`` that has the point site ``site`` (an end of it, or itself).  Read
    from the curves ending there (their ``sources``, through the edit ``index`` of ``sites``) when
    those account for all ``uses`` of the point; else a scan of the pieces."""
    key = site_key(site)
    P = (Fraction(key[1], key[2]), Fraction(key[3], key[4]))
    found = {sources[k] for k in curves_ending_at(index, sites, P)}
    found = {j for j in found if key in (_points(pieces[j]) or ())}
    if found and len(found) == uses.get(key, 0):
        return min(found)
    return next(j for j, q in enumerate(pieces) if key in (_points(q) or ()))


def _elementary_pieces(site):
    """The pieces of an input piece as the construction splits it: ``[site]`` for a Segment, an Arc
    or a Point (an (x, y) pair a Point), a circle of rational radius (a Circle) its two halves
    (:func:`runtime.sites.arc.circle_halves`); None for anything else (an irrational radius too:
    the rebuild then raises the batch build's error)."""
    if isinstance(site, (Segment, Arc)) or (isinstance(site, Point) and site.r2 == 0):
        return [site]
    if hasattr(site, "r2") and hasattr(site, "cx"):
        try:
            return circle_halves((site.cx, site.cy), site.r2, getattr(site, "label", None))
        except (InvalidConicError, TypeError, ValueError):
            return None
    if isinstance(site, (tuple, list)) and len(site) == 2:
        try:
            return [Point(*as_point_pair(site, "the new site"))]
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
