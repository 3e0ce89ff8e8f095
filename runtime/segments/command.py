"""The segment commands: ``diagram`` on DXF / GeoJSON drawings, and ``medial-axis``.

``curvedvoronoi diagram part.dxf`` (or ``shapes.geojson``) -- the Voronoi diagram of the drawing's
segments, arcs and points (thesis §2.2; DXF ARC entities and polyline bulges are arcs), with the
options, outputs and exit codes of the ``diagram`` command (:mod:`runtime.voronoi.command`: ``--crs CRS``
is the drawing's coordinate reference system, written as GDAL's ``crs`` member of the GeoJSON), plus
``--skip TYPES`` (DXF entity types to ignore, e.g. ``TEXT,MTEXT,DIMENSION``).  A sites file
(``.json`` with ``{"sites": [...]}``, segment and arc records included) goes to
:func:`runtime.voronoi.command.diagram_main` unchanged; a ``.json`` file that holds GeoJSON (a
top-level ``"type"``) is read as GeoJSON.  Still refused, with one line naming the entity: DXF
CIRCLE, ELLIPSE, SPLINE and the other curves (:mod:`runtime.sites.dxf`), pieces that cross.

``curvedvoronoi medial-axis shape.{dxf,geojson,json} [--png OUT.png] [--geojson OUT.geojson]
[--crs CRS] [--json OUT.json]`` -- the medial axis of a domain bounded by closed loops of segments and arcs
(thesis §2.3, :func:`runtime.segments.medial_axis.medial_axis`), one summary line on stdout.  The
domain: GeoJSON polygons (first ring outer, the others holes), or the DXF / sites-JSON pieces
joined end to end into closed loops, **the loop containing all the others being the outer
boundary, the others holes** (:mod:`runtime.segments.loops`: the refusals, and the containment
test with arcs).

Exit status of ``medial-axis``: 0 certified (with ``--no-certify``: ran to its end, not verified
on request), 1 not certified (the summary line names the first problem -- diagrams with arcs are
not certified yet where the certificate does not cover arcs), 2 bad input (one line on stderr),
3 numerical refusal, 130 interrupted.  ``--json`` writes ``{"format":
"curvedvoronoi.medial_axis/1", "certified", "problems", "largest_inscribed_circle": {"centre",
"radius"}, "sites" (the boundary's elementary sites, with the input ``source`` of each),
"vertices", "edges" (polyline and radius at each point, tolerance, certified)}``.

Public API: :func:`diagram_main`, :func:`medial_axis_main`, :func:`medial_axis_document`,
:data:`SHAPE_SUFFIXES`; :func:`read_shape` and :func:`read_domain` (from :mod:`runtime.segments.loops`).
"""
from __future__ import annotations

import json
import re
import signal
import sys

import numpy as np

from ..sites.shapes import ShapeError
from ..voronoi.command import (EXIT_BAD_INPUT, EXIT_CERTIFIED, EXIT_INTERRUPTED, EXIT_NOT_CERTIFIED,
                               OneLineParser, crs_option, diagram_main as sites_diagram_main, diagram_parser,
                               draw_picture, is_geoparquet, print_summary, run_construction, write_text)
from .loops import check_named, read_domain, read_shape, shape_kind

__all__ = ["diagram_main", "medial_axis_main", "read_shape", "read_domain", "medial_axis_document",
           "SHAPE_SUFFIXES", "MEDIAL_AXIS_FORMAT"]

#: file name endings read as drawings (anything else is a sites file, unless it holds GeoJSON)
SHAPE_SUFFIXES = (".dxf", ".geojson")
MEDIAL_AXIS_FORMAT = "curvedvoronoi.medial_axis/1"


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


# =====================================================================================
# diagram DRAWING
# =====================================================================================

def _diagram_parser() -> OneLineParser:
    p = diagram_parser("Voronoi diagram / Delaunay graph of disjoint circles, points and conics, or of "
                       "the segments, arcs and points of a DXF drawing or GeoJSON document (thesis §1.2, "
                       "§2.2), certified by an independent verifier.",
                       'sites file {"sites": [...]} (.json), a DXF drawing (.dxf) or GeoJSON (.geojson)',
                       interrupted="", crs_of="the drawing's",
                       time_limit_help="stop after S seconds (partial result; not used by segment diagrams yet)")
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
    if is_geoparquet(args.sites) or shape_kind(args.sites) == "sites":
        if args.skip:
            print("error: --skip applies to DXF drawings only", file=sys.stderr)
            return EXIT_BAD_INPUT
        return sites_diagram_main(argv)
    if unknown:
        parser.error(f"unrecognized arguments: {' '.join(unknown)}")
    if args.out or args.scheduler or args.sites_per_tile:
        parser.error("--out, --scheduler and --sites-per-tile apply to sites files (JSON, GeoParquet) only")
    try:
        pieces, sources, names = read_shape(args.sites, skip=_skip_types(args.skip))
        if len(pieces) < 2:
            raise ShapeError(f"{args.sites}: the Voronoi diagram needs at least 2 sites, got {len(pieces)}")
        check_named(pieces, names, args.sites)
    except ValueError as exc:           # ShapeError, SiteError: one line naming the entity
        print(f"error: {_cli_message(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    from ..voronoi.structure import Diagram
    from .construction import segment_voronoi

    if args.time_limit is not None and not args.quiet:
        print("note: --time-limit is not used by segment diagrams yet", file=sys.stderr)
    interrupted = False
    progress = None if not (args.quiet or args.no_progress) else False
    try:
        d, status = run_construction(lambda: segment_voronoi(pieces, sources, certify=not args.no_certify,
                                                             progress=progress),
                                     bad_input_prefix=f"{args.sites}: ")
    except KeyboardInterrupt:
        interrupted = True
        d, status = Diagram(pieces, [], [], False, ["interrupted (Ctrl-C): no diagram computed"], {}), None
    if status is not None:
        return status
    previous = _ignore_sigint()
    try:
        doc = d.to_json()
        if args.json_out:
            write_text(args.json_out, json.dumps(doc, indent=1), "diagram JSON")
        if args.geojson:
            write_text(args.geojson, json.dumps(d.to_geojson(crs=crs_option(args.crs))), "GeoJSON")
        if args.png:
            draw_picture(d, args.png, empty_circles=args.empty_circles, window=args.window)
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_NOT_CERTIFIED
    finally:
        _restore_sigint(previous)
    print_summary(d, doc, args)
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
                      description="The medial axis of a domain with holes bounded by segments and arcs (thesis "
                                  "§2.3): the part inside the domain of the Voronoi diagram of its boundary, with "
                                  "the inscribed radius. "
                                  "GeoJSON: each Polygon's first ring is its outer boundary, the others holes. "
                                  "DXF / sites JSON: closed loops of segments and arcs; the loop containing all the "
                                  "others is the outer boundary, the others are holes.",
                      epilog="Prints one summary line.  Exit status: 0 certified (with --no-certify: ran to "
                             "the end), 1 not certified or failed, 2 bad input, 3 numerical refusal, "
                             "130 interrupted.")
    p.add_argument("shape", help="the domain: a DXF drawing (.dxf), GeoJSON (.geojson, or .json with a "
                                 "top-level \"type\") or a sites file with segment and arc records (.json)")
    p.add_argument("--png", help="write a picture here (boundary, medial axis, largest inscribed circle)")
    p.add_argument("--geojson", help="write the medial axis and its boundary sites as GeoJSON here (radius "
                                     "along each edge)")
    p.add_argument("--crs", default=None,
                   help="the drawing's coordinate reference system for --geojson, e.g. EPSG:32633 (default: a "
                        "planar engineering CRS, so that GIS tools do not read longitude/latitude; 'none': "
                        "no crs member)")
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
    """``medial-axis SHAPE [--png OUT.png] [--geojson OUT.geojson] [--crs CRS] [--json OUT.json]``."""
    args = _medial_parser().parse_args(argv)
    try:
        outer, holes, _, sources = read_domain(args.shape, skip=_skip_types(args.skip))
    except ValueError as exc:
        print(f"error: {_cli_message(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    from .medial_axis import medial_axis

    m, status = run_construction(lambda: medial_axis(outer, holes, certify=not args.no_certify),
                                 bad_input_prefix=f"{args.shape}: ", what="the medial axis")
    if status is not None:
        return status
    previous = _ignore_sigint()
    try:
        if args.json_out:
            src = getattr(m.diagram, "sources", None)        # elementary site -> boundary piece
            src = None if src is None else [sources[k] for k in src]
            write_text(args.json_out, json.dumps(medial_axis_document(m, src), indent=1), "medial axis JSON")
        if args.geojson:
            write_text(args.geojson, json.dumps(m.to_geojson(crs=crs_option(args.crs))), "GeoJSON")
        if args.png:
            draw_picture(m, args.png)
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_NOT_CERTIFIED
    finally:
        _restore_sigint(previous)
    if not args.quiet:
        print(medial_axis_summary(m))
    return EXIT_CERTIFIED if (m.certified or args.no_certify) else EXIT_NOT_CERTIFIED
