"""The segment commands: ``diagram`` on DXF / GeoJSON drawings, and ``medial-axis``.

``curvedvoronoi diagram part.dxf`` (or ``shapes.geojson``) -- the Voronoi diagram of the drawing's
segments and points (thesis §2.2), with the options, outputs and exit codes of the ``diagram``
command (:mod:`runtime.voronoi.command`), plus ``--skip TYPES`` (DXF entity types to ignore, e.g.
``TEXT,MTEXT,DIMENSION``).  A sites file (``.json`` with ``{"sites": [...]}``, segment records
included) goes to :func:`runtime.voronoi.command.diagram_main` unchanged; a ``.json`` file that
holds GeoJSON (a top-level ``"type"``) is read as GeoJSON.

``curvedvoronoi medial-axis shape.{dxf,geojson,json} [--png OUT.png] [--geojson OUT.geojson]
[--json OUT.json]`` -- the medial axis of a polygonal domain with holes (thesis §2.3,
:func:`runtime.segments.medial_axis.medial_axis`), one summary line on stdout.  The domain:

* **GeoJSON**: every Polygon of the document (a Polygon, a MultiPolygon, Features, collections):
  its first ring is the outer boundary, the others its holes.  Several polygons give the union
  of their medial axes; they must not overlap or touch.  Other geometry types are refused.
* **DXF** and **sites JSON** (segment records): the segments are joined end to end into closed
  loops (a closed LWPOLYLINE / POLYLINE is one loop; LINEs joined end to end also make one).  The
  rule: **the loop that contains all the others is the outer boundary, the others are holes.**
  Refused, with one line naming the entities: an open end (a segment end not joined to another
  segment), three or more segments at one point (loops touching), a POINT, several loops none of
  which contains all the others (two domains side by side), and a loop inside a hole (an island:
  a second domain) -- put each domain in its own file.

Exit status of ``medial-axis``: 0 certified (with ``--no-certify``: ran to its end, not verified
on request), 1 not certified, 2 bad input (one line on stderr), 3 numerical refusal, 130
interrupted.  ``--json`` writes ``{"format": "curvedvoronoi.medial_axis/1", "certified",
"problems", "largest_inscribed_circle": {"centre", "radius"}, "sites" (the boundary's elementary
sites, with the input ``source`` of each), "vertices", "edges" (polyline and radius at each point,
tolerance, certified)}``.

Length: the two commands share the drawing readers with their entity names, the domain rule and
the output writers, hence one module over 400 lines.

Public API: :func:`diagram_main`, :func:`medial_axis_main`, :func:`read_shape`,
:func:`read_domain`, :func:`medial_axis_document`, :data:`SHAPE_SUFFIXES`.
"""
from __future__ import annotations

import json
import re
import signal
import sys
from pathlib import Path

import numpy as np

from ..result import InvalidConicError, NumericalRefusal
from ..sites.segment import Segment
from ..sites.shapes import ShapeError
from ..voronoi.command import (EXIT_BAD_INPUT, EXIT_CERTIFIED, EXIT_INTERRUPTED, EXIT_NOT_CERTIFIED,
                               EXIT_NUMERICAL_REFUSAL, OneLineParser, diagram_main as sites_diagram_main,
                               parse_window)

__all__ = ["diagram_main", "medial_axis_main", "read_shape", "read_domain", "medial_axis_document",
           "SHAPE_SUFFIXES", "MEDIAL_AXIS_FORMAT"]

#: file name endings read as drawings (anything else is a sites file, unless it holds GeoJSON)
SHAPE_SUFFIXES = (".dxf", ".geojson")
MEDIAL_AXIS_FORMAT = "curvedvoronoi.medial_axis/1"


# =====================================================================================
# Reading drawings: pieces, sources, and a name for each piece (for one-line errors)
# =====================================================================================

def _kind_of(path: str) -> str:
    """"dxf", "geojson" or "sites" (a .json holding GeoJSON is "geojson")."""
    suffix = Path(path).suffix.lower()
    if suffix == ".dxf":
        return "dxf"
    if suffix == ".geojson":
        return "geojson"
    try:
        with open(path) as fh:
            head = fh.read(1 << 16)
    except OSError:
        return "sites"                  # the sites reader reports it
    m = re.match(r'\s*\{\s*"type"\s*:', head)
    return "geojson" if m else "sites"


def _load_json(path: str):
    try:
        with open(path) as fh:
            return json.load(fh)
    except OSError as exc:
        raise ShapeError(f"cannot read {path}: {exc.strerror or exc}") from None
    except ValueError as exc:
        raise ShapeError(f"{path} is not valid JSON: {exc}") from None


def _entity_name(e) -> str:
    return f"{e.dxftype()} (handle {e.dxf.get('handle', '?')}, layer {e.dxf.get('layer', '0')!r})"


class _Names:
    """``names(k)``: the input piece k named for a message -- the DXF entity (type, handle, layer)
    or GeoJSON member it came from and its segment number there, or ``site k``."""

    def __init__(self, kind: str, path: str, pieces, sources, skip=(), doc=None):
        self.kind, self.path, self.pieces, self.sources, self.skip = kind, path, pieces, sources, skip
        self.doc = doc
        self._members = None

    def member(self, src: int) -> str:
        if self._members is None:
            self._members = self._member_names()
        return self._members[src] if 0 <= src < len(self._members) else f"member {src}"

    def _member_names(self) -> list[str]:
        if self.kind == "dxf":
            from ..sites.dxf import SUPPORTED
            import ezdxf

            skip = {str(t).upper() for t in self.skip}
            doc = ezdxf.readfile(self.path)
            return [_entity_name(e) for e in doc.modelspace() if e.dxftype() not in skip and e.dxftype() in SUPPORTED]
        doc = self.doc if isinstance(self.doc, dict) else {}
        kind = doc.get("type")
        if kind == "FeatureCollection":
            return [f"feature {i} ({(f.get('geometry') or {}).get('type')})"
                    for i, f in enumerate(doc.get("features", []))]
        if kind == "GeometryCollection":
            return [f"geometry {i} ({g.get('type')})" for i, g in enumerate(doc.get("geometries", []))]
        if kind in ("MultiPolygon", "MultiLineString", "MultiPoint"):
            return [f"{kind[5:]} {i}" for i in range(len(doc.get("coordinates", [])))]
        if kind == "Feature":
            return [f"the feature ({(doc.get('geometry') or {}).get('type')})"]
        return [f"the {kind}"]

    def __call__(self, k: int) -> str:
        if self.kind == "sites":
            return f"site {k} ({type(self.pieces[k]).__name__.lower()})"
        src = self.sources[k]
        nth = sum(1 for j in range(k) if self.sources[j] == src)
        same = sum(1 for s in self.sources if s == src)
        what = "segment" if isinstance(self.pieces[k], Segment) else "point"
        return self.member(src) + (f" {what} {nth}" if same > 1 else "")


def read_shape(path: str, *, skip=()) -> tuple[list, list[int], object]:
    """``(pieces, sources, names)`` of a DXF drawing, a GeoJSON document or a sites file:
    :func:`runtime.sites.dxf.read_dxf`, :func:`runtime.sites.shapes.pieces_from_geometry` or
    :func:`runtime.sites.reader.read_sites`; ``names(k)`` names piece k for a message."""
    kind = _kind_of(path)
    if kind == "dxf":
        from ..sites.dxf import read_dxf

        pieces, sources, _ = read_dxf(path, skip=skip)
        return pieces, sources, _Names(kind, path, pieces, sources, skip)
    if kind == "geojson":
        from ..sites.shapes import pieces_from_geometry

        doc = _load_json(path)
        try:
            pieces, sources = pieces_from_geometry(doc)
        except ShapeError as exc:
            raise ShapeError(f"{path}: {exc}") from None
        return pieces, sources, _Names(kind, path, pieces, sources, doc=doc)
    from ..sites.reader import read_sites

    pieces = read_sites(path)
    sources = list(range(len(pieces)))
    return pieces, sources, _Names(kind, path, pieces, sources)


def _check(pieces, names, path: str) -> None:
    """:func:`runtime.segments.crossings.check_pieces` with the pieces named as in the input."""
    from .crossings import check_pieces

    try:
        check_pieces(pieces)
    except InvalidConicError as exc:
        msg = str(exc)
        m = re.match(r"sites (\d+) and (\d+): (.*)$", msg, re.S)
        if m:
            a, b, rest = int(m.group(1)), int(m.group(2)), m.group(3)
            rest = re.sub(r"\b(?:site|segment) (\d+)\b", lambda mm: names(int(mm.group(1))), rest)
            msg = f"{names(a)} and {names(b)}: {rest}"
        else:
            msg = re.sub(r"^site (\d+):", lambda mm: names(int(mm.group(1))) + ":", msg)
        raise ShapeError(f"{path}: {msg}") from None


# =====================================================================================
# The domain of the medial axis
# =====================================================================================

def _ring_array(segs) -> np.ndarray:
    return np.array([[s.float_endpoints()[0], s.float_endpoints()[1]] for s in segs], dtype=float)


def _inside_ring(ring: np.ndarray, q) -> bool:
    """Even-odd rule: q strictly inside the closed polygon of the segments ``ring`` (k x 2 x 2)."""
    A, B = ring[:, 0], ring[:, 1]
    x, y = float(q[0]), float(q[1])
    cond = (A[:, 1] > y) != (B[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = A[:, 0] + (y - A[:, 1]) * (B[:, 0] - A[:, 0]) / (B[:, 1] - A[:, 1])
    return bool(np.sum(cond & (x < xc)) % 2)


def _probe(segs):
    """A point of the loop that is on no other loop: the midpoint of its first segment."""
    (x0, y0), (x1, y1) = segs[0].float_endpoints()
    return ((x0 + x1) / 2, (y0 + y1) / 2)


def _loops(pieces, names, path: str) -> list[list[int]]:
    """The pieces joined end to end into closed loops (lists of piece indices, in order)."""
    at: dict = {}
    for k, p in enumerate(pieces):
        if not isinstance(p, Segment):
            if hasattr(p, "r2"):        # a Point
                raise ShapeError(f"{path}: {names(k)}: a point is not part of a closed boundary (the medial axis "
                                 "needs closed polygons)")
            raise ShapeError(f"{path}: {names(k)}: {type(p).__name__.lower()}s in the boundary are not supported "
                             "by the medial axis yet (line segments only)")
        for end in (p.p, p.q):
            at.setdefault(tuple(end), []).append(k)
    for pt, ks in at.items():
        xy = f"({pt[0]}, {pt[1]})"
        if len(ks) == 1:
            raise ShapeError(f"{path}: {names(ks[0])}: its end {xy} is not joined to another segment (the medial "
                             "axis needs closed boundaries: closed polylines, or segments joined end to end)")
        if len(ks) > 2:
            raise ShapeError(f"{path}: {len(ks)} segments meet at {xy} ({', '.join(names(k) for k in ks[:3])}"
                             f"{', ...' if len(ks) > 3 else ''}): the boundary must be disjoint simple closed "
                             "loops (loops touching at a corner are not allowed)")
    seen = [False] * len(pieces)
    loops = []
    for k0 in range(len(pieces)):
        if seen[k0]:
            continue
        loop, k, pt = [], k0, tuple(pieces[k0].q)
        while not seen[k]:
            seen[k] = True
            loop.append(k)
            a, b = at[pt]
            k = b if a == k else a
            pt = tuple(pieces[k].q) if tuple(pieces[k].p) == pt else tuple(pieces[k].p)
        loops.append(loop)
    return loops


def _loop_name(loop, names, sources) -> str:
    srcs = {sources[k] for k in loop}
    if len(srcs) == 1 and names.kind != "sites":
        return names.member(next(iter(srcs)))
    return f"the loop through {names(loop[0])}"


def _nest(loops_segs, loop_names, path: str) -> tuple[int, list[int]]:
    """(outer, holes) by the rule: the loop containing all the others is the outer boundary."""
    rings = [_ring_array(s) for s in loops_segs]
    probes = [_probe(s) for s in loops_segs]
    n = len(rings)
    inside = [[i != j and _inside_ring(rings[j], probes[i]) for j in range(n)] for i in range(n)]  # i in j
    outer = [j for j in range(n) if all(inside[i][j] for i in range(n) if i != j)]
    if not outer:
        tops = [i for i in range(n) if not any(inside[i])]
        pair = " and ".join(loop_names[i] for i in tops[:2])
        raise ShapeError(f"{path}: {n} closed boundaries and none contains all the others ({pair} lie side by "
                         "side): the outer boundary must contain every hole; put each domain in its own file")
    o = outer[0]
    for i in range(n):
        for j in range(n):
            if i != o and j != o and inside[i][j]:
                raise ShapeError(f"{path}: {loop_names[i]} lies inside the hole {loop_names[j]} (an island in a "
                                 "hole is a second domain): put it in its own file")
    return o, [i for i in range(n) if i != o]


def _polygons(doc, path: str) -> list[tuple[str, list]]:
    """(name, rings) of every Polygon of a GeoJSON document; other geometry types refused."""
    out: list = []

    def walk(g, where):
        if not isinstance(g, dict):
            raise ShapeError(f"{path}: {where}: expected a GeoJSON object")
        t = g.get("type")
        if t == "FeatureCollection":
            for i, f in enumerate(g.get("features") or []):
                walk(f, f"feature {i}")
        elif t == "Feature":
            if g.get("geometry") is None:
                raise ShapeError(f"{path}: {where}: the feature has no geometry (null)")
            walk(g["geometry"], where)
        elif t == "GeometryCollection":
            for i, m in enumerate(g.get("geometries") or []):
                walk(m, f"{where} member {i}")
        elif t == "MultiPolygon":
            for i, c in enumerate(g.get("coordinates") or []):
                out.append((f"{where} polygon {i}", c))
        elif t == "Polygon":
            out.append((f"{where} (Polygon)", g.get("coordinates") or []))
        else:
            raise ShapeError(f"{path}: {where} ({t}): the medial axis needs polygons (Polygon or MultiPolygon); "
                             "remove it")

    walk(doc, "geometry")
    if not out:
        raise ShapeError(f"{path}: no polygon (the medial axis needs a Polygon or MultiPolygon)")
    return out


def read_domain(path: str, *, skip=()) -> tuple[list, list, list, list]:
    """``(outer, holes, pieces, sources)`` of the domain in a GeoJSON, DXF or sites file (see the
    module docstring for the rule); ``outer`` and each hole are lists of Segments.  With several
    GeoJSON polygons, ``outer`` is the first shell and ``holes`` every other ring (the medial
    axis of the union is the union of the medial axes)."""
    kind = _kind_of(path)
    if kind == "geojson":
        from ..sites.shapes import pieces_from_geometry

        doc = _load_json(path)
        rings, rnames, owner = [], [], []
        for p, (where, coords) in enumerate(_polygons(doc, path)):
            if not isinstance(coords, list) or not coords:
                raise ShapeError(f"{path}: {where}: empty polygon")
            for r, ring in enumerate(coords):
                name = f"{where} {'shell' if r == 0 else f'hole {r - 1}'}"
                try:
                    segs, _ = pieces_from_geometry({"type": "Polygon", "coordinates": [ring]})
                except ShapeError as exc:
                    raise ShapeError(f"{path}: {name}: {str(exc).split(': ', 1)[-1]}") from None
                rings.append(segs)
                rnames.append(name)
                owner.append(p)
        pieces = [s for r in rings for s in r]
        sources = [owner[k] for k, r in enumerate(rings) for _ in r]
        piece_names = [f"{rnames[k]} segment {i}" for k, r in enumerate(rings) for i in range(len(r))]
        _check(pieces, lambda k: piece_names[k], path)
        _touching(rings, rnames, path)
        _check_polygons(rings, rnames, owner, path)
        return rings[0], rings[1:], pieces, sources
    pieces, sources, names = read_shape(path, skip=skip)
    if not pieces:
        raise ShapeError(f"{path}: no segments")
    _check(pieces, names, path)
    loops = _loops(pieces, names, path)
    segs = [[pieces[k] for k in loop] for loop in loops]
    o, holes = _nest(segs, [_loop_name(lp, names, sources) for lp in loops], path)
    order = [k for loop in [loops[o]] + [loops[h] for h in holes] for k in loop]
    return segs[o], [segs[h] for h in holes], [pieces[k] for k in order], [sources[k] for k in order]


def _touching(rings, rnames, path: str) -> None:
    seen: dict = {}
    for r, segs in enumerate(rings):
        for s in segs:
            for end in (tuple(s.p),):
                if end in seen and seen[end] != r:
                    raise ShapeError(f"{path}: {rnames[seen[end]]} and {rnames[r]} touch at ({end[0]}, {end[1]}): "
                                     "rings must be disjoint")
                seen[end] = r


def _check_polygons(rings, rnames, owner, path: str) -> None:
    """Holes inside their shell and not inside each other; polygons not inside each other's area."""
    arrs = [_ring_array(s) for s in rings]
    probes = [_probe(s) for s in rings]
    shells = [k for k in range(len(rings)) if k == 0 or owner[k] != owner[k - 1]]
    for k in range(len(rings)):
        if k in shells:
            continue
        sh = max(s for s in shells if s <= k)
        if not _inside_ring(arrs[sh], probes[k]):
            raise ShapeError(f"{path}: {rnames[k]} is not inside its shell")
        for j in range(sh + 1, len(rings)):
            if j != k and owner[j] == owner[k] and _inside_ring(arrs[j], probes[k]):
                raise ShapeError(f"{path}: {rnames[k]} lies inside {rnames[j]} (holes must not nest)")
    for a in shells:
        for b in shells:
            if a != b and _inside_ring(arrs[b], probes[a]):
                in_hole = any(owner[h] == owner[b] and h != b and _inside_ring(arrs[h], probes[a])
                              for h in range(len(rings)))
                if not in_hole:
                    raise ShapeError(f"{path}: {rnames[a]} lies inside the polygon of {rnames[b]} (polygons must "
                                     "not overlap)")


# =====================================================================================
# Output documents
# =====================================================================================

def medial_axis_document(m, sources=None) -> dict:
    """The ``--json`` document of a :class:`runtime.segments.medial_axis.MedialAxis` (see the
    module docstring); ``sources``: per elementary site, the input piece it came from."""
    from ..sites.reader import site_to_json

    D = m.diagram
    src = sources if sources is not None else getattr(D, "sources", None)
    lic = m.largest_inscribed_circle
    return {"format": MEDIAL_AXIS_FORMAT,
            "certified": bool(m.certified),
            "problems": list(m.problems),
            "largest_inscribed_circle": None if lic is None else {"centre": [lic[0], lic[1]], "radius": lic[2]},
            "sites": [site_to_json(s, source=None if src is None else src[i]) for i, s in enumerate(D.sites)],
            "vertices": [{"id": v.id, "sites": list(v.sites), "x": v.x, "y": v.y, "radius": v.radius,
                          "certified": bool(v.certified)} for v in m.vertices],
            "edges": [{"id": e.id, "sites": list(e.sites), "ends": list(e.ends),
                       "polyline": np.asarray(e.polyline, float).tolist(),
                       "radius": np.asarray(e.radius, float).tolist(),
                       "tolerance": float(e.tolerance), "certified": bool(e.certified)} for e in m.edges]}


def _write(path, text, what) -> None:
    try:
        with open(path, "w") as fh:
            fh.write(text)
    except OSError as exc:
        raise OSError(f"cannot write the {what} {path}: {exc.strerror}") from None


def _draw(obj, path, **kw) -> None:
    try:
        obj.plot(path, **kw)
    except (ImportError, KeyboardInterrupt):
        raise
    except OSError as exc:
        raise OSError(f"cannot write the picture {path}: {exc.strerror or exc}") from None
    except Exception as exc:  # noqa: BLE001 - the JSON outputs are written; say what the picture hit
        raise OSError(f"cannot draw the picture {path}: {type(exc).__name__}: {exc}") from None


# =====================================================================================
# diagram DRAWING
# =====================================================================================

def _diagram_parser() -> OneLineParser:
    p = OneLineParser(prog="curvedvoronoi diagram",
                      description="Voronoi diagram / Delaunay graph of disjoint circles, points and conics, or of "
                                  "the segments and points of a DXF drawing or GeoJSON document (thesis §1.2, "
                                  "§2.2), certified by an independent verifier.",
                      epilog="Exit status: 0 certified (with --no-certify: ran to the end, not verified on "
                             "request), 1 not certified or failed, 2 bad input, 3 numerical refusal, "
                             "130 interrupted.")
    p.add_argument("sites", help='sites file {"sites": [...]} (.json), a DXF drawing (.dxf) or GeoJSON (.geojson)')
    p.add_argument("--json", dest="json_out", help="write the diagram (curvedvoronoi.diagram/1) here")
    p.add_argument("--png", help="write a picture here")
    p.add_argument("--window", type=parse_window, metavar="XMIN,XMAX,YMIN,YMAX",
                   help="the picture's window (default: fitted to the sites); write --window=-1,1,-1,1 "
                        "when the first number is negative")
    p.add_argument("--geojson", help="write the edges and vertices as GeoJSON here")
    p.add_argument("--empty-circles", action="store_true", help="draw the vertices' empty circles")
    p.add_argument("--quiet", action="store_true", help="no summary, no progress bar")
    p.add_argument("--time-limit", type=float, default=None,
                   help="stop after S seconds (partial result; not used by segment diagrams yet)")
    p.add_argument("--no-certify", action="store_true",
                   help="skip the verifier (never certified; exit 0 when the construction ran to its end)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--skip", default="", metavar="TYPES",
                   help="DXF entity types to ignore, comma-separated (e.g. TEXT,MTEXT,DIMENSION)")
    return p


def _cli_message(exc) -> str:
    """The reader's advice in command-line terms (``skip={'TEXT'}`` is ``--skip TEXT`` here)."""
    return re.sub(r"pass skip=\{'([^']*)'\}", r"pass --skip \1", str(exc))


def _skip_types(text: str) -> tuple:
    return tuple(t.strip().upper() for t in text.split(",") if t.strip())


def diagram_main(argv=None) -> int:
    """``diagram FILE``: a DXF / GeoJSON drawing here, a sites file by
    :func:`runtime.voronoi.command.diagram_main` (same options and exit codes)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = _diagram_parser()
    args, unknown = parser.parse_known_args(argv)      # sites files: the options are checked there
    if _kind_of(args.sites) == "sites":
        if args.skip:
            print("error: --skip applies to DXF drawings only", file=sys.stderr)
            return EXIT_BAD_INPUT
        return sites_diagram_main(argv)
    if unknown:
        parser.error(f"unrecognized arguments: {' '.join(unknown)}")
    try:
        pieces, sources, names = read_shape(args.sites, skip=_skip_types(args.skip))
        if len(pieces) < 2:
            raise ShapeError(f"{args.sites}: the Voronoi diagram needs at least 2 sites, got {len(pieces)}")
        _check(pieces, names, args.sites)
    except ValueError as exc:           # ShapeError, SiteError: one line naming the entity
        print(f"error: {_cli_message(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    from ..voronoi.structure import Diagram
    from .construction import segment_voronoi

    if args.time_limit is not None and not args.quiet:
        print("note: --time-limit is not used by segment diagrams yet", file=sys.stderr)
    interrupted = False
    try:
        progress = None if not (args.quiet or args.no_progress) else False
        d = segment_voronoi(pieces, sources, certify=not args.no_certify, progress=progress)
    except KeyboardInterrupt:
        interrupted = True
        d = Diagram(pieces, [], [], False, ["interrupted (Ctrl-C): no diagram computed"], {})
    except NumericalRefusal as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_NUMERICAL_REFUSAL
    except InvalidConicError as exc:
        print(f"error: {args.sites}: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except (ImportError, MemoryError):
        raise
    except Exception as exc:  # noqa: BLE001 - valid input the construction failed on: one line, exit 1
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
        print(f"error: the construction failed on this input ({type(exc).__name__}"
              + (f": {msg}" if msg else "") + "); please report it", file=sys.stderr)
        return EXIT_NOT_CERTIFIED
    previous = _ignore_sigint()
    try:
        doc = d.to_json()
        if args.json_out:
            _write(args.json_out, json.dumps(doc, indent=1), "diagram JSON")
        if args.geojson:
            _write(args.geojson, json.dumps(d.to_geojson()), "GeoJSON")
        if args.png:
            _draw(d, args.png, empty_circles=args.empty_circles, window=args.window)
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_NOT_CERTIFIED
    finally:
        _restore_sigint(previous)
    if not args.quiet:
        if not args.json_out:
            print(json.dumps(doc, indent=1))
        print(f"{len(d.sites)} sites, {len(d.vertices)} vertices, {len(d.edges)} edges, "
              f"{len(d.delaunay_edges())} Delaunay edges, certified={d.certified}"
              + (f"; {len(d.problems)} problems, first: {d.problems[0]}" if d.problems else ""), file=sys.stderr)
    if interrupted:
        return EXIT_INTERRUPTED
    if d.certified or args.no_certify:
        return EXIT_CERTIFIED
    return EXIT_NOT_CERTIFIED


def _ignore_sigint():
    """Writing the outputs is not interrupted half-way (the previous handler is returned)."""
    try:
        return signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:                  # not the main thread
        return None


def _restore_sigint(previous) -> None:
    if previous is not None:
        signal.signal(signal.SIGINT, previous)


# =====================================================================================
# medial-axis SHAPE
# =====================================================================================

def _medial_parser() -> OneLineParser:
    p = OneLineParser(prog="curvedvoronoi medial-axis",
                      description="The medial axis of a polygon with holes (thesis §2.3): the part inside the "
                                  "domain of the Voronoi diagram of its boundary, with the inscribed radius. "
                                  "GeoJSON: each Polygon's first ring is its outer boundary, the others holes. "
                                  "DXF / sites JSON: closed loops of segments; the loop containing all the "
                                  "others is the outer boundary, the others are holes.",
                      epilog="Prints one summary line.  Exit status: 0 certified (with --no-certify: ran to "
                             "the end), 1 not certified or failed, 2 bad input, 3 numerical refusal, "
                             "130 interrupted.")
    p.add_argument("shape", help="the domain: a DXF drawing (.dxf), GeoJSON (.geojson, or .json with a "
                                 "top-level \"type\") or a sites file with segment records (.json)")
    p.add_argument("--png", help="write a picture here (boundary, medial axis, largest inscribed circle)")
    p.add_argument("--geojson", help="write the medial axis as GeoJSON here (radius along each edge)")
    p.add_argument("--json", dest="json_out", help=f"write the medial axis ({MEDIAL_AXIS_FORMAT}) here")
    p.add_argument("--no-certify", action="store_true",
                   help="skip the certificate (never certified; exit 0 when the construction ran to its end)")
    p.add_argument("--skip", default="", metavar="TYPES",
                   help="DXF entity types to ignore, comma-separated (e.g. TEXT,MTEXT,DIMENSION)")
    p.add_argument("-q", "--quiet", action="store_true", help="no summary line (the exit status says it)")
    return p


def medial_axis_summary(m) -> str:
    """The one summary line of ``medial-axis``."""
    lic = m.largest_inscribed_circle
    circle = ("none" if lic is None else
              f"centre ({lic[0]:.6g}, {lic[1]:.6g}) radius {lic[2]:.6g}")
    return (f"medial axis: {len(m.edges)} edges, {len(m.vertices)} vertices, largest inscribed circle {circle}, "
            f"certified={m.certified}"
            + (f"; {len(m.problems)} problems, first: {m.problems[0]}" if m.problems else ""))


def medial_axis_main(argv=None) -> int:
    """``medial-axis SHAPE [--png OUT.png] [--geojson OUT.geojson] [--json OUT.json]``."""
    args = _medial_parser().parse_args(argv)
    try:
        outer, holes, _, sources = read_domain(args.shape, skip=_skip_types(args.skip))
    except ValueError as exc:
        print(f"error: {_cli_message(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    from .medial_axis import medial_axis

    try:
        m = medial_axis(outer, holes, certify=not args.no_certify)
    except NumericalRefusal as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_NUMERICAL_REFUSAL
    except InvalidConicError as exc:
        print(f"error: {args.shape}: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except (ImportError, MemoryError, KeyboardInterrupt):
        raise
    except Exception as exc:  # noqa: BLE001 - valid input the construction failed on: one line, exit 1
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
        print(f"error: the medial axis failed on this input ({type(exc).__name__}"
              + (f": {msg}" if msg else "") + "); please report it", file=sys.stderr)
        return EXIT_NOT_CERTIFIED
    previous = _ignore_sigint()
    try:
        if args.json_out:
            src = getattr(m.diagram, "sources", None)        # elementary site -> boundary piece
            src = None if src is None else [sources[k] for k in src]
            _write(args.json_out, json.dumps(medial_axis_document(m, src), indent=1), "medial axis JSON")
        if args.geojson:
            _write(args.geojson, json.dumps(m.to_geojson()), "GeoJSON")
        if args.png:
            _draw(m, args.png)
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_NOT_CERTIFIED
    finally:
        _restore_sigint(previous)
    if not args.quiet:
        print(medial_axis_summary(m))
    return EXIT_CERTIFIED if (m.certified or args.no_certify) else EXIT_NOT_CERTIFIED
