"""Certified Voronoi diagrams and Delaunay graphs of conics.

After F. Anton, *Voronoi diagrams of semi-algebraic sets*, PhD thesis, University of British
Columbia, 2003.  One import name gives the public API.

Sites
-----
Conic
    A non-degenerate real conic ``a x² + b xy + c y² + d x + e y + f = 0`` with exact rational
    coefficients: ``Conic.from_coefficients(a, b, c, d, e, f)``, ``Conic.ellipse(centre, axes,
    rotation)``, ``Conic.hyperbola(...)``, ``Conic.parabola(vertex, p, rotation)``,
    ``Conic.circle(centre, radius)``.  A rotation is ``rotation=(cos, sin)`` (a unit vector,
    exact when rational), ``degrees=`` or ``radians=``; a bare number above 2π as ``rotation``
    is refused (ValueError) as ambiguous.
Circle
    A circle site with exact centre and *squared* radius: build it with
    ``Circle.from_radius(cx, cy, radius)``; ``Circle(cx, cy, r2)`` takes r2 = radius².
Point
    A point site ``Point(x, y)`` (a circle of radius 0, thesis §3.1.2).

Computations
------------
locate_conflicts(c1, c2, c3, c4, method="auto")
    The Delaunay-graph conflict locator (thesis §1.2, ch. 5): the true Voronoi vertices of
    C1, C2, C3 (centres of empty circles tangent to the three) and whether C4 enters them.
    Sites are Conic, Circle or Point objects, (x, y) points or (cx, cy, r) circles: four
    circles or points go to the exact locator of thesis §3.1, a point among conics to the proved
    diagram of C1, C2, C3, anything else to the conic locator.
    Returns a :class:`LocatorResult`; ``certified`` is True only for a proved answer.
voronoi(sites)
    The Voronoi diagram / Delaunay graph of any number of sites (thesis §1.2), a ``Diagram``.
    A site is a Conic, Circle, Point, Segment or Arc, an ``(x, y)`` pair (a point) or an
    ``(cx, cy, r)`` triple (a circle of radius r; r = 0 is a point).
tiled_voronoi(sites, client=None)
    The same diagram built tile by tile (one Dask task per tile with a ``distributed.Client``),
    stitched and proved by the verifier; see docs/distributed.md.
read_geoparquet_sites(path), write_geoparquet(diagram, directory)
    Point and circle sites from GeoParquet; a diagram as GeoParquet datasets partitioned by region.
load_offset(family)
    The generalised offset of a conic family (thesis ch. 4, App. B), from verified artefacts.
read_sites(path)
    Sites from a JSON file (schema in ``curvedvoronoi.runtime.sites.reader``), validated.

Errors are ``ValueError`` subclasses with one-line messages: :class:`InvalidConicError` (the
input is not a proper real conic), :class:`SiteError` (sites that intersect or repeat),
:class:`LocatorError` (no trustworthy answer), :class:`NumericalRefusal` (a numeric route refuses
valid input; :class:`RangeRefusal`: coordinates too far apart for the diagram's local frame);
:class:`ArtefactError` (a generated artefact fails its check) is a ``RuntimeError``.

Result types: :class:`LocatorResult` with :class:`VoronoiVertex`; :class:`Diagram` with
:class:`DiagramVertex`, :class:`DiagramEdge`, :class:`NearestResult` (``Diagram.nearest``) and
:class:`DiagramFrames` (``Diagram.to_geopandas``); :class:`Certificate` (``verify``);
:class:`MedialAxis` with :class:`MedialEdge`; :class:`AlgebraicOffset` (``offset``), :class:`OffsetPolynomial`
(``load_offset``).

Examples
--------
>>> import curvedvoronoi as cv
>>> e = cv.Conic.ellipse(centre=(0, 0), axes=(2, 1))
>>> e
Conic(ellipse: 1, 0, 4, 0, 0, -4)
>>> e.kind, e.frame.params
('ellipse', {'A2': 4.0, 'B2': 1.0})
>>> cv.Circle.from_radius(0, 0, 3).radius_squared
9
>>> cv.Conic.from_coefficients(1, 0, 1, 0, 0, 1)
Traceback (most recent call last):
...
curvedvoronoi.runtime.result.InvalidConicError: imaginary ellipse: the equation has no real point

Four circles: the exact locator of thesis §3.1.3.  The circle of radius 1 centred at (0, 0),
(4, 0) and (0, 4) has one empty circle tangent to the three; a point at (1, 1) is inside it:

>>> sites = [cv.Circle.from_radius(0, 0, 1), cv.Circle.from_radius(4, 0, 1),
...          cv.Circle.from_radius(0, 4, 1), cv.Point(1, 1)]
>>> res = cv.locate_conflicts_circles(*sites)
>>> res.conflict, res.certified, [(float(v.x), float(v.y)) for v in res.vertices]
(True, True, [(2.0, 2.0)])

Four ellipses placed like thesis Fig. 5.5.1 (a certified answer in about a second):

>>> from curvedvoronoi.runtime.predicates.locator import demo_configuration
>>> res = cv.locate_conflicts(*demo_configuration())
>>> res.conflict, res.certified, len(res.vertices)
(True, True, 1)
>>> v = res.vertices[0]
>>> round(v.x, 6), round(v.y, 6), round(v.radius, 6), v.in_conflict
(2.401431, 1.880629, 1.510415, True)

Package layout
--------------
The three halves of the source tree are sub-packages: ``curvedvoronoi.precompute`` (offline,
exact), ``curvedvoronoi.generated`` (hashed data artefacts) and ``curvedvoronoi.runtime``
(online, certified).  In the repository they are the top-level folders ``precompute/``,
``generated/`` and ``runtime/``; setuptools' ``package-dir`` maps them under this package at
install time, so that an installed copy owns a single top-level name.
"""
from __future__ import annotations

from pathlib import Path

# One BLAS thread inside the library's calls (runtime/threads.py, threadpoolctl): importing the
# package leaves the caller's environment untouched.

# In a source checkout runtime/, precompute/ and generated/ sit beside this folder: let the
# package find them there (an installed copy has them inside, see pyproject.toml).
_here = Path(__file__).resolve().parent
if not (_here / "runtime").is_dir() and (_here.parent / "runtime" / "__init__.py").is_file():
    __path__.append(str(_here.parent))  # type: ignore[name-defined]  # noqa: F821

__version__ = "0.2.0"

_LAZY = {
    "Conic": ("runtime.sites.conic", "Conic"),
    "Circle": ("runtime.sites.circle", "Circle"),
    "Point": ("runtime.sites.circle", "Point"),
    "Segment": ("runtime.sites.segment", "Segment"),
    "Arc": ("runtime.sites.arc", "Arc"),
    "EllipticArc": ("runtime.sites.elliptic_arc", "EllipticArc"),
    "medial_axis": ("runtime.segments.medial_axis", "medial_axis"),
    "MedialAxis": ("runtime.segments.medial_axis", "MedialAxis"),
    "read_dxf": ("runtime.sites.dxf", "read_dxf"),
    "pieces_from_geometry": ("runtime.sites.shapes", "pieces_from_geometry"),
    "voronoi": ("runtime.voronoi.construction", "voronoi"),
    "tiled_voronoi": ("runtime.voronoi.distributed", "tiled_voronoi"),
    "read_geoparquet_sites": ("runtime.voronoi.geoparquet", "read_geoparquet_sites"),
    "write_geoparquet": ("runtime.voronoi.geoparquet", "write_geoparquet"),
    "Diagram": ("runtime.voronoi.structure", "Diagram"),
    "verify": ("runtime.voronoi.verify.certificate", "verify"),
    "offset": ("runtime.algebra.algebraic_offset", "offset"),
    "locate_conflicts": ("runtime.predicates.locator", "locate_conflicts"),
    "locate_conflicts_circles": ("runtime.predicates.circles", "locate_conflicts_circles"),
    "read_sites": ("runtime.sites.reader", "read_sites"),
    "parse_site": ("runtime.sites.reader", "parse_site"),
    "voronoi_vertices": ("runtime.predicates.locator", "voronoi_vertices"),
    "LocatorResult": ("runtime.result", "LocatorResult"),
    "VoronoiVertex": ("runtime.result", "VoronoiVertex"),
    "LocatorError": ("runtime.result", "LocatorError"),
    "InvalidConicError": ("runtime.result", "InvalidConicError"),
    "NumericalRefusal": ("runtime.result", "NumericalRefusal"),
    "SiteError": ("runtime.voronoi.site_input", "SiteError"),
    "RangeRefusal": ("runtime.voronoi.frame", "RangeRefusal"),
    "Certificate": ("runtime.voronoi.verify.certificate", "Certificate"),
    "DiagramVertex": ("runtime.voronoi.structure", "DiagramVertex"),
    "DiagramEdge": ("runtime.voronoi.structure", "DiagramEdge"),
    "NearestResult": ("runtime.voronoi.queries", "NearestResult"),
    "DiagramFrames": ("runtime.voronoi.cells", "DiagramFrames"),
    "MedialEdge": ("runtime.segments.medial_axis", "MedialEdge"),
    "AlgebraicOffset": ("runtime.algebra.algebraic_offset", "AlgebraicOffset"),
    "OffsetPolynomial": ("runtime.artefacts", "OffsetPolynomial"),
    "load_offset": ("runtime.artefacts", "load_offset"),
    "ArtefactError": ("runtime.artefacts", "ArtefactError"),
}

__all__ = sorted(["__version__", *_LAZY])


def __getattr__(name: str):
    """Import the public names lazily, so that ``curvedvoronoi --help`` stays fast."""
    try:
        module, attr = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module 'curvedvoronoi' has no attribute {name!r}") from None
    from importlib import import_module
    value = getattr(import_module(f"{__name__}.{module}"), attr)
    globals()[name] = value
    return value


def __dir__():
    return __all__
