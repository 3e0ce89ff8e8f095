"""The Voronoi diagram of many sites as data: vertices, curved edges, the Delaunay graph.

Thesis §1.2 (Prop. 1.2.1) and §5.1–5.2: a *Voronoi vertex* is the centre of a circle touching
k ≥ 3 sites and empty of all sites (k = 3 in general position; grids, co-circular points and
symmetric conics give k > 3, decided exactly on the input's rational values); a *Voronoi edge* (i, j) is a connected
arc of points whose two nearest sites are exactly i and j.  An edge ends at vertices or at
infinity; an edge around a site nested inside another has no vertex and is a closed curve
(Prop. 1.2.1).  The Delaunay graph joins i and j when they share an edge of positive length: at a vertex of
degree k only the k pairs consecutive around it share an edge (a square of co-circular points has
no diagonal in its Delaunay graph).

JSON schema ``curvedvoronoi.diagram/2`` (site indices are 0-based positions in the input list,
distances are Euclidean distances, not squared)::

    {"format": "curvedvoronoi.diagram/2",
     "sites": [site_to_json(s), ...],
     "vertices": [{"id", "sites": [s_0, ..., s_{k-1}], "x", "y", "radius", "certified"}],
     "edges": [{"id", "sites": [i, j], "ends": [v | null, v | null], "closed",
                "polyline": [[x, y], ...], "tolerance", "certified"}],
     "delaunay_edges": [[i, j], ...], "certified", "problems": [...], "stats": {...}}

A vertex lists its k ≥ 3 sites counter-clockwise by the angle of their contact points with the
empty circle, seen from the vertex, starting with the smallest index; its edges are those of the
consecutive pairs (s_t, s_{t+1 mod k}).  Version 1 (``curvedvoronoi.diagram/1``) listed exactly
three sorted sites per vertex; :meth:`Diagram.from_json` reads it (a triple's cyclic order is
immaterial: all three pairs are consecutive).

Public API: :class:`DiagramVertex`, :class:`DiagramEdge`, :class:`Diagram`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:                      # annotations only: the data module imports no heavy module
    from .cells import DiagramFrames
    from .queries import NearestResult

__all__ = ["DiagramVertex", "DiagramEdge", "Diagram", "FORMAT", "READABLE_FORMATS"]

FORMAT = "curvedvoronoi.diagram/2"
#: formats :meth:`Diagram.from_json` reads
READABLE_FORMATS = ("curvedvoronoi.diagram/1", FORMAT)


@dataclass
class DiagramVertex:
    """A Voronoi vertex: equidistant (``radius``) from its k ≥ 3 ``sites``, no site closer.
    ``sites`` lists them counter-clockwise by their contact points with the empty circle, the
    smallest index first; the vertex's edges are those of cyclically consecutive pairs.
    ``certified`` is True only when existence and emptiness were proved."""

    id: int
    sites: tuple[int, ...]
    x: float
    y: float
    radius: float
    certified: bool = False

    @property
    def degree(self) -> int:
        """The number of sites (and of edges) at the vertex: 3 in general position."""
        return len(self.sites)

    def site_pairs(self) -> list[tuple[int, int]]:
        """The sorted pairs of cyclically consecutive sites: the pairs of the vertex's edges."""
        k = len(self.sites)
        return [tuple(sorted((int(self.sites[t]), int(self.sites[(t + 1) % k])))) for t in range(k)]

    def to_json(self) -> dict:
        return {"id": self.id, "sites": list(self.sites), "x": self.x, "y": self.y,
                "radius": self.radius, "certified": self.certified}


@dataclass(eq=False)
class DiagramEdge:
    """A Voronoi edge between ``sites`` (i < j).

    ``ends`` are vertex ids (None: the edge goes to infinity); ``closed`` marks a vertex-less
    closed curve (then ``polyline[0] == polyline[-1]``).  ``polyline`` runs from ``ends[0]`` to
    ``ends[1]``.  ``tolerance``: for circle and point sites, a bound on the Hausdorff distance
    between the polyline (its segments, not only its points) and the edge's arc, which the
    verifier proves (:mod:`runtime.voronoi.verify.polyline_bound`, up to 1e-9 of the coordinates);
    with a conic site, the measured deviation (the verifier proves every polyline point within it
    and the arc inside strips along the polyline).  The arc's ends are the end vertices as
    certified: the polyline starts and ends within tol + 2h of their proved centres, the test that
    accepts the reported vertices (:mod:`runtime.voronoi.verify.vertices`).
    """

    id: int
    sites: tuple[int, int]
    ends: tuple[int | None, int | None]
    closed: bool
    polyline: np.ndarray
    tolerance: float
    certified: bool = False

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, DiagramEdge):
            return NotImplemented
        return (self.id == other.id and tuple(self.sites) == tuple(other.sites) and tuple(self.ends) == tuple(other.ends)
                and self.closed == other.closed and self.certified == other.certified
                and np.array_equal(np.asarray(self.polyline, float), np.asarray(other.polyline, float))
                and (self.tolerance == other.tolerance or (self.tolerance != self.tolerance and other.tolerance != other.tolerance)))

    __hash__ = None

    def __repr__(self) -> str:
        ends = "closed" if self.closed else f"ends={tuple(self.ends)}"
        return (f"DiagramEdge(id={self.id}, sites={tuple(self.sites)}, {ends}, {len(self.polyline)} points, "
                f"tolerance={self.tolerance:.3g}, certified={self.certified})")

    def to_json(self) -> dict:
        return {"id": self.id, "sites": list(self.sites), "ends": list(self.ends),
                "closed": self.closed,
                "polyline": np.asarray(self.polyline, dtype=float).tolist(),
                "tolerance": self.tolerance, "certified": self.certified}


@dataclass
class Diagram:
    """The Voronoi diagram of ``sites`` (exact :class:`runtime.sites.circle.Circle` /
    :class:`runtime.sites.circle.Point` / :class:`runtime.sites.conic.Conic`).

    ``certified`` is True only when an independent verification proved the whole diagram;
    ``problems`` lists what is not proved (one line each, naming the sites).
    """

    sites: list
    vertices: list[DiagramVertex] = field(default_factory=list)
    edges: list[DiagramEdge] = field(default_factory=list)
    certified: bool = False
    problems: list[str] = field(default_factory=list)
    stats: dict = field(default_factory=dict)
    #: the construction's sampling state (not serialised), used by :meth:`delete_site`
    construction: object = field(default=None, repr=False, compare=False)
    #: for elementary sites of points and segments (thesis §2.2): the index of the input piece
    #: each site comes from (JSON: the ``"source"`` member of each site record); None otherwise
    sources: list | None = field(default=None, repr=False)

    # ------------------------------------------------------------------ updates
    def delete_site(self, i: int, *, certify: bool = True, renumber: str = "shift", inplace: bool = False) -> "Diagram":
        """The diagram of the other sites, renumbered (``renumber="shift"``: site j > i becomes
        j − 1; ``"last"``: the last site takes index i, which keeps a deletion local); this diagram
        is left unchanged (``inplace=True``: this diagram is updated and returned, without copying its
        lists: the part of a local update linear in N).  Needs the construction state of a diagram built by ``voronoi`` (not one
        read from JSON).  See :func:`runtime.voronoi.deletion.delete_site` (reached through the
        construction state, so that this data module imports nothing of the construction).  In a
        diagram of segments (and points, arcs), ``i`` is the index of an *input piece*
        (``sources[k]`` of site k): the segment goes with its endpoints unless another piece still
        has them (:class:`runtime.segments.edits.SegmentEdits`)."""
        if self.construction is None:
            _no_pieces(self.sites, "deletion")
            raise ValueError("this diagram has no construction state (read from JSON?): build the diagram of "
                             "the remaining sites with voronoi(...)")
        return self.construction.delete(self, i, certify=certify, renumber=renumber, inplace=inplace)

    def insert(self, site, *, certify: bool = True, inplace: bool = False) -> "Diagram":
        """The diagram with ``site`` added as site N; this diagram is
        left unchanged (``inplace=True``: it is updated and returned, as :meth:`delete_site`).  Only the part of the diagram the new site touches is rebuilt and proved
        (thesis §1.2); ``certified`` needs this diagram certified.  See
        :func:`runtime.voronoi.insertion.insert_site` (parabolas, hyperbolas: rebuilt from scratch), reached
        through the construction state like :meth:`delete_site`.  In a diagram of segments the new
        piece (a segment, a point, an arc, a circle) is input piece N; it is inserted locally
        when the new regions are bounded, otherwise the diagram is rebuilt and certified whole
        (:class:`runtime.segments.edits.SegmentEdits`); a piece crossing another is refused with
        the batch build's ``SiteError``."""
        if self.construction is None:
            _no_pieces(list(self.sites) + [site], "insertion")
            raise ValueError("this diagram has no construction state (read from JSON, or collinear points?): "
                             "build the diagram of the new list of sites with voronoi(...)")
        return self.construction.insert(self, site, certify=certify, inplace=inplace)

    def insert_many(self, sites, *, certify: bool = True) -> "Diagram":
        """:meth:`insert` each of ``sites`` (any iterable) in turn; this diagram is left unchanged
        (the first insertion makes a new diagram, which the others update in place)."""
        d = self
        for k, s in enumerate(sites):
            d = d.insert(s, certify=certify, inplace=k > 0)
        return d

    # ------------------------------------------------------------------ graph views
    def delaunay_edges(self) -> list[tuple[int, int]]:
        """The Delaunay graph: sorted pairs (i, j), i < j, of sites sharing a Voronoi edge."""
        return sorted({tuple(e.sites) for e in self.edges})

    def to_networkx(self) -> Any:
        """A :class:`networkx.MultiGraph`: nodes = site indices (attribute ``site``), one edge per
        Voronoi edge (attributes ``id``, ``ends``, ``closed``, ``polyline``, ``tolerance``,
        ``certified``)."""
        import networkx as nx

        G = nx.MultiGraph()
        for i, s in enumerate(self.sites):
            G.add_node(i, site=s)
        for e in self.edges:
            G.add_edge(e.sites[0], e.sites[1], key=e.id, id=e.id, ends=e.ends, closed=e.closed,
                       polyline=e.polyline, tolerance=e.tolerance, certified=e.certified)
        return G

    # ------------------------------------------------------------------ JSON
    def to_json(self) -> dict:
        """The document ``curvedvoronoi.diagram/2`` (sites exactly, vertices, edges with their
        polylines, the Delaunay graph, the verdict, problems and statistics) as a dict;
        :meth:`write_json` writes the same document without building it."""
        from .geojson import Records

        return {key: list(value) if isinstance(value, Records) else value for key, value in self._json_members()}

    def write_json(self, file: Any, *, indent: int | None = 1) -> None:
        """Write :meth:`to_json`'s document to ``file`` (a path or a text file object) with the text
        of ``json.dump(self.to_json(), file, indent=indent)``, one site, vertex and edge record at a
        time (:func:`runtime.voronoi.geojson.write_json_object`): the document is never held in
        memory as Python lists (for 3·10⁴ circles: 9·10⁵ polyline points, ~150 bytes each as lists
        of floats)."""
        from .geojson import write_json_object

        if isinstance(file, (str, bytes)) or hasattr(file, "__fspath__"):
            with open(file, "w") as fh:
                write_json_object(fh, self._json_members(), indent)
        else:
            write_json_object(file, self._json_members(), indent)

    def _json_members(self) -> list:
        from ..sites.reader import site_to_json
        from .geojson import Records

        sources = self.sources
        return [("format", FORMAT),
                ("sites", Records(lambda: (site_to_json(s, source=None if sources is None else sources[i])
                                           for i, s in enumerate(self.sites)))),
                ("vertices", Records(lambda: (v.to_json() for v in self.vertices))),
                ("edges", Records(lambda: (e.to_json() for e in self.edges))),
                ("delaunay_edges", [list(p) for p in self.delaunay_edges()]),
                ("certified", bool(self.certified)),
                ("problems", list(self.problems)),
                ("stats", _jsonable(self.stats))]

    @classmethod
    def from_json(cls, doc: dict) -> "Diagram":
        """Read :meth:`to_json` output back (sites exactly).  ValueError on a malformed document."""
        from ..sites.reader import parse_site

        if not isinstance(doc, dict) or doc.get("format") not in READABLE_FORMATS:
            raise ValueError(f'not a diagram document: expected "format": "{FORMAT}" '
                             f'(or {READABLE_FORMATS[0]})')
        try:
            sites = [parse_site(s, f"site {i}") for i, s in enumerate(doc["sites"])]
            verts = [DiagramVertex(int(v["id"]), tuple(int(t) for t in v["sites"]), float(v["x"]),
                                   float(v["y"]), float(v["radius"]), bool(v["certified"]))
                     for v in doc["vertices"]]
            edges = [DiagramEdge(int(e["id"]), tuple(int(t) for t in e["sites"]),
                                 tuple(None if t is None else int(t) for t in e["ends"]),
                                 bool(e["closed"]),
                                 np.asarray(e["polyline"], dtype=float).reshape(-1, 2),
                                 float(e["tolerance"]), bool(e["certified"]))
                     for e in doc["edges"]]
        except (KeyError, TypeError) as exc:
            raise ValueError(f"malformed diagram document: {exc!r}") from None
        sources = None
        if any(isinstance(s, dict) and "source" in s for s in doc["sites"]):
            sources = [s.get("source") if isinstance(s, dict) else None for s in doc["sites"]]
        return cls(sites, verts, edges, bool(doc.get("certified", False)),
                   list(doc.get("problems", [])), dict(doc.get("stats", {})), sources=sources)

    def to_geojson(self, crs: Any = None, *, sites: bool = True) -> dict:
        """A GeoJSON FeatureCollection: one LineString per edge (properties ``kind="edge"``,
        ``number``, ``sites``, ``ends``, ``closed``, ``tolerance``, ``certified``), one Point per
        vertex (``kind="vertex"``, ``number``, ``sites``, ``radius``, ``certified``) and one feature
        per site (``kind="site"``, ``number``, ``shape``, ``label``; a Point, or the curve sampled
        as a LineString).  Feature ids are unique (``"edge-3"``, ``"vertex-3"``, ``"site-3"``).
        ``crs``: the coordinate reference system of the sites (e.g. ``"EPSG:32633"``), written as
        the collection's ``crs`` member (the form GDAL reads); by default a planar engineering CRS,
        so that GIS tools do not take the coordinates for longitude and latitude; ``False``: no
        member.  See :mod:`runtime.voronoi.geojson`."""
        from .geojson import diagram_geojson

        return diagram_geojson(self, crs, sites=sites)

    def to_shapely(self) -> list:
        """The edges as a list of :class:`shapely.geometry.LineString` (needs shapely)."""
        try:
            from shapely.geometry import LineString
        except ImportError:
            raise ImportError("Diagram.to_shapely needs shapely (pip install shapely)") from None
        return [LineString(np.asarray(e.polyline, float)) for e in self.edges]

    def plot(self, path_or_ax: Any = None, *, empty_circles: bool = False, **kw: Any) -> Any:
        """Draw the diagram (sites, curved edges, vertices, dashed Delaunay graph); save to a path
        or draw on a matplotlib Axes.  Returns the Figure."""
        from .plot import plot_diagram

        return plot_diagram(self, path_or_ax, empty_circles=empty_circles, **kw)

    # ------------------------------------------------------------------ queries and cells
    def site_distance(self, points: Any, sites: Any = None, *,
                      bounds: bool = False) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
        """(n, m) float distances from the n query points (an (n, 2) array) to the sites (or to
        the listed ``sites``), every site kind; ``bounds=True`` gives a pair (lo, hi) of such
        arrays, rigorous.  The result takes n·m·8 bytes (10⁴ × 10⁴: 800 MB): query in blocks
        or pass ``sites``.  See :mod:`runtime.voronoi.queries`."""
        from .queries import site_index

        return site_index(self).distance(points, sites, bounds=bounds)

    def nearest(self, points: Any, *, prove: bool = True) -> NearestResult:
        """The nearest site of each query point (an (n, 2) array): a
        :class:`runtime.voronoi.queries.NearestResult` (``index``, ``distance``, ``proved``,
        ``ties``, ``exact``).  With ``prove`` the answer is proved with rigorous distance bounds
        and near ties decided exactly (points and circles); a tie is reported in ``ties`` with
        ``index`` −1, never as a guessed winner.  ``prove=False``: float distances only."""
        from .queries import site_index

        return site_index(self).nearest(points, prove=prove)

    @property
    def vertex_array(self) -> np.ndarray:
        """The vertices' coordinates, an (n, 2) float array (row t: ``vertices[t]``), as scipy's
        ``Voronoi.vertices``."""
        return np.array([[v.x, v.y] for v in self.vertices], dtype=float).reshape(-1, 2)

    @property
    def ridge_sites(self) -> np.ndarray:
        """The two sites of each edge, an (m, 2) int array (row t: ``edges[t].sites``), as scipy's
        ``Voronoi.ridge_points``."""
        return np.array([e.sites for e in self.edges], dtype=np.int64).reshape(-1, 2)

    @property
    def ridge_vertices(self) -> np.ndarray:
        """The end vertices of each edge as rows of :attr:`vertex_array`, an (m, 2) int array,
        −1 for an end at infinity (as scipy's ``Voronoi.ridge_vertices``).  A closed edge (the
        vertex-less loop around a nested site) is also [−1, −1]: tell it from an edge infinite at
        both ends by ``edges[t].closed``."""
        pos = {v.id: t for t, v in enumerate(self.vertices)}
        return np.array([[-1 if u is None else pos[u] for u in e.ends] for e in self.edges],
                        dtype=np.int64).reshape(-1, 2)

    def cells(self, clip: Any = None) -> list:
        """One shapely geometry per site: its Voronoi region (boundary from the edges' polylines,
        within their tolerance) clipped to ``clip``, a box (xmin, ymin, xmax, ymax) or any shapely
        polygon (default: the sites' bounding box with a 10 % margin).  A nested site's region
        is a hole in its container's cell; a cell that misses the clip region is an empty Polygon.
        Needs shapely.  See :mod:`runtime.voronoi.cells`."""
        from .cells import diagram_cells

        return diagram_cells(self, clip)

    def to_geopandas(self, crs: Any = None, clip: Any = None) -> DiagramFrames:
        """Three GeoDataFrames (``cells``, ``edges``, ``sites``) in a named tuple, with ``crs``
        passed through; ``clip`` as for :meth:`cells`.  Needs geopandas (ImportError otherwise)."""
        from .cells import diagram_geopandas

        return diagram_geopandas(self, crs=crs, clip=clip)

    def __repr__(self) -> str:
        return (f"Diagram({len(self.sites)} sites, {len(self.vertices)} vertices, {len(self.edges)} edges, "
                f"certified={self.certified}, {len(self.problems)} problems)")


def _jsonable(x):
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return x


def _no_pieces(sites, what) -> None:
    """A diagram of segments or arcs (thesis §2.2) without construction state (read from JSON, or
    built with explicit ``sources``) does not know its input pieces: ValueError naming the kind."""
    kinds = sorted({type(s).__name__ for s in sites if type(s).__name__ in ("Segment", "Arc", "EllipticArc")})
    if kinds:
        raise ValueError(f"{what} in a diagram of {' and '.join(k.lower() + ' sites' for k in kinds)} needs its "
                         "input pieces, which a diagram read from JSON does not keep: build the diagram of the "
                         "new list of pieces with voronoi(...)")
