"""The ``diagram`` command: ``python -m curvedvoronoi diagram SITES.json [--json OUT.json]
[--png OUT.png] [--geojson OUT.geojson] [--quiet] [--time-limit S] [--no-certify] [--empty-circles]``.

SITES.json is ``{"sites": [...]}`` with the records of :func:`runtime.sites.reader.parse_site`
(``{"point": [x, y]}``, ``{"circle": {"centre": [x, y], "radius": r}}``,
``{"coefficients": [a, b, c, d, e, f]}``) or the older ``{"conics": [{"coefficients": ...}]}``.
Prints a summary (the diagram JSON on stdout when no ``--json`` is given and not ``--quiet``).
Bad input: one line on stderr, exit status 2.  Ctrl-C: the construction stops and the partial
result is written, marked not certified.

Public API: :func:`diagram_main` (sites files are read by :func:`runtime.sites.reader.read_sites`).
"""
from __future__ import annotations

import argparse
import json
import sys

from ..sites.reader import read_sites

__all__ = ["diagram_main"]

EXIT_BAD_INPUT = 2


def _parser():
    p = argparse.ArgumentParser(prog="curvedvoronoi diagram",
                                description="Voronoi diagram / Delaunay graph of disjoint circles, points and "
                                            "conics (thesis §1.2), certified by an independent verifier.")
    p.add_argument("sites", help='JSON file {"sites": [...]} or {"conics": [{"coefficients": [...]}, ...]}')
    p.add_argument("--json", dest="json_out", help="write the diagram (curvedvoronoi.diagram/1) here")
    p.add_argument("--png", help="write a picture here")
    p.add_argument("--geojson", help="write the edges and vertices as GeoJSON here")
    p.add_argument("--empty-circles", action="store_true", help="draw the vertices' empty circles")
    p.add_argument("--quiet", action="store_true", help="no summary, no progress bar")
    p.add_argument("--time-limit", type=float, default=None, help="stop after S seconds (partial result)")
    p.add_argument("--no-certify", action="store_true", help="skip the verifier (never certified)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    return p


def diagram_main(argv=None) -> int:
    args = _parser().parse_args(argv)
    from .construction import voronoi

    try:
        sites = read_sites(args.sites)
        progress = None if not (args.quiet or args.no_progress) else False
        try:
            d = voronoi(sites, certify=not args.no_certify, progress=progress, time_limit=args.time_limit)
        except KeyboardInterrupt:
            from .structure import Diagram

            d = Diagram(sites, [], [], False, ["interrupted (Ctrl-C): no diagram computed"], {})
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    doc = d.to_json()
    if args.json_out:
        with open(args.json_out, "w") as fh:
            json.dump(doc, fh, indent=1)
    if args.geojson:
        with open(args.geojson, "w") as fh:
            json.dump(d.to_geojson(), fh)
    if args.png:
        d.plot(args.png, empty_circles=args.empty_circles)
    if not args.quiet:
        if not args.json_out:
            print(json.dumps(doc, indent=1))
        print(f"{len(d.sites)} sites, {len(d.vertices)} vertices, {len(d.edges)} edges, "
              f"{len(d.delaunay_edges())} Delaunay edges, certified={d.certified}"
              + (f"; {len(d.problems)} problems, first: {d.problems[0]}" if d.problems else ""), file=sys.stderr)
    return 0
