"""Command line: ``curvedvoronoi COMMAND ...`` (the same program as ``python -m curvedvoronoi``).

* ``locate FILE.json`` -- the Delaunay-graph conflict locator (thesis ch. 5, §3.1 for circles) on
  four sites C1..C4 = sites 0..3 of a sites file (schema: :mod:`runtime.sites.reader`); JSON out.
* ``diagram SITES.json`` -- the Voronoi diagram / Delaunay graph of any number of sites (§1.2);
  also ``diagram part.dxf`` / ``shapes.geojson``: the diagram of a drawing's segments and points
  (§2.2, :mod:`runtime.segments.command`).
* ``medial-axis SHAPE`` -- the medial axis of a polygon with holes from a DXF, GeoJSON or sites
  file (§2.3, :mod:`runtime.segments.command`).
* ``demo`` -- the locator on a built-in four-ellipse configuration (a rigid-motion version of
  thesis Fig. 5.5.1).
* ``offsets`` -- the table of generalised offsets (thesis Table 4.1 and App. B), from the
  verified artefacts.

Sites are numbered from 0 in every message.  Bad input gives a one-line message on stderr and
exit status 2; a locator that cannot answer exits 1 with a one-line message; ``--quiet``
silences the informational lines on stderr but never the errors.
"""
from __future__ import annotations

import argparse
import json
import sys
import time

EXIT_BAD_INPUT = 2
EXIT_FAILED = 1


def _offsets_table(args) -> int:
    if args.curve:                      # any plane algebraic curve (thesis ch. 4)
        from .algebra.degree_formula import offset_report

        print(offset_report(args.curve, as_json=args.json))
        return 0
    from .artefacts import load_manifest, load_offset

    manifest = load_manifest()
    rows = []
    for rel in sorted(manifest["artefacts"]):
        if not rel.startswith("offsets/"):
            continue
        fam = rel.split("/", 1)[1].removesuffix(".json")
        off = load_offset(fam)
        degs = {v: max(e[i] for e, _ in off.terms) for i, v in enumerate(off.variables)}
        rows.append((fam, len(off.terms), off.degree_uv, degs["u"], degs["v"], degs["R"],
                     ", ".join(off.parameters)))
    if args.json:
        print(json.dumps([dict(zip(("family", "terms", "degree_uv", "deg_u", "deg_v", "deg_R", "params"), r))
                          for r in rows], indent=2))
        return 0
    print("Generalised offsets of conics (thesis Table 4.1, App. B); R = squared offset distance")
    print(f"{'family':<20} {'terms':>6} {'deg(u,v)':>9} {'deg u':>6} {'deg v':>6} {'deg R':>6}  parameters")
    for r in rows:
        print(f"{r[0]:<20} {r[1]:>6} {r[2]:>9} {r[3]:>6} {r[4]:>6} {r[5]:>6}  {r[6]}")
    return 0


def _zero_based(msg: str) -> str:
    """The locator names the sites C1..C4 (thesis notation); the command line numbers them 0..3."""
    import re

    return re.sub(r"\bC([1-4])\b", lambda m: f"site {int(m.group(1)) - 1}", msg)


def _renamed(obj):
    """--details: the locator's ``R`` is the squared radius of the empty circle; name it so."""
    if isinstance(obj, dict):
        return {("radius_squared" if k == "R" else k): _renamed(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_renamed(v) for v in obj]
    return obj


def _summary(result, seconds: float) -> str:
    n = len(result.vertices)
    k = sum(1 for v in result.vertices if v.in_conflict)
    und = sum(1 for v in result.vertices if v.in_conflict is None)
    s = (f"{n} true Voronoi vertex{'es' if n != 1 else ''} of sites 0, 1, 2; {k} in conflict with site 3"
         + (f", {und} undecided" if und else "")
         + f"; conflict={str(result.conflict).lower()} certified={str(result.certified).lower()} "
         f"complete={str(result.complete).lower()} ({result.method}, {seconds:.2f} s)")
    return s


def _emit(result, args, seconds: float) -> int:
    d = result.to_dict(details=args.details)
    if args.details:
        d = _renamed(d)
    text = json.dumps(d, indent=2)
    if getattr(args, "output", None):
        try:
            with open(args.output, "w") as fh:
                fh.write(text + "\n")
        except OSError as exc:
            raise ValueError(f"cannot write {args.output}: {exc.strerror}") from None
    else:
        print(text)
    if not args.quiet:
        print(_summary(result, seconds), file=sys.stderr)
    return 0


def _locate(args) -> int:
    from .sites.reader import read_sites

    sites = read_sites(args.file, expected=4)
    t0 = time.perf_counter()
    from .predicates.locator import locate_conflicts

    result = locate_conflicts(*sites, method=args.method)
    return _emit(result, args, time.perf_counter() - t0)


def _demo(args) -> int:
    from .predicates import locator

    conics = locator.demo_configuration()
    if not args.quiet:
        print("Demo: four ellipses (a rigid-motion version of thesis Fig. 5.5.1)", file=sys.stderr)
        for i, c in enumerate(conics):
            print(f"  site {i}: {c}", file=sys.stderr)
    t0 = time.perf_counter()
    result = locator.locate_conflicts(*conics, method=args.method)
    return _emit(result, args, time.perf_counter() - t0)


def _diagram(args) -> int:
    from .segments.command import diagram_main     # DXF / GeoJSON here, sites files to runtime.voronoi.command

    return diagram_main(args.rest)


def _medial_axis(args) -> int:
    from .segments.command import medial_axis_main

    return medial_axis_main(args.rest)


def _add_common(s, methods) -> None:
    s.add_argument("--method", choices=methods, default="auto",
                   help="auto (default): exact circle locator for four circles/points, otherwise the "
                        "triple route with certification; triple, quadruple (the thesis' four-offset "
                        "system), circles (exact, circles and points only), interval (branch-and-prune, ch. 6)")
    s.add_argument("--details", action="store_true",
                   help="add per-vertex diagnostics and certificates (radius_squared = squared radius "
                        "of the empty circle)")
    s.add_argument("-o", "--output", metavar="OUT.json", help="write the JSON there instead of stdout")
    s.add_argument("-q", "--quiet", action="store_true",
                   help="no informational lines on stderr (errors are still reported)")


def _version() -> str:
    try:
        from .. import __version__  # imported as curvedvoronoi.runtime (installed or source tree)
    except ImportError:             # ``python -m runtime`` in a checkout: runtime is top-level
        from importlib.metadata import PackageNotFoundError, version

        try:
            return version("curvedvoronoi")
        except PackageNotFoundError:
            return "(source tree)"
    return __version__


def _verify_summary(cert, seconds: float) -> str:
    st = cert.stats
    if cert.ok:
        return f"proved: {st.get('vertices', len(cert.vertices))} vertices, {st.get('edges', len(cert.edges))} edges, {seconds:.2f} s"
    n = len(cert.problems)
    first = cert.problems[0] if cert.problems else "the certificate is not complete"
    return (f"NOT proved: {n} problem{'s' if n != 1 else ''}, first: {first} "
            f"({sum(cert.vertices)}/{len(cert.vertices)} vertices, {sum(cert.edges)}/{len(cert.edges)} edges proved, "
            f"{seconds:.2f} s)")


#: diagrams with more edges than this get a progress bar over the verifier's stages (stderr)
VERIFY_ANNOUNCE_EDGES = 2000


def _verify(args) -> int:
    """``verify DIAGRAM.json [SITES.json] [-v] [-o OUT.json]``: exit 0 proved, 1 not proved, 2 bad input.

    Prints one summary line; ``-v`` prints the whole certificate (JSON) on stdout and the summary on
    stderr; ``-o`` writes the certificate there."""
    from .voronoi.verify.certificate import verify_files

    t0 = time.perf_counter()
    if not args.quiet:
        try:
            with open(args.diagram) as fh:
                n_edges = len(json.load(fh).get("edges", []))
        except (OSError, ValueError, AttributeError, TypeError):
            n_edges = 0                    # verify_files reports what is wrong with the file
    else:
        n_edges = 0
    try:
        cert = verify_files(args.diagram, args.sites, progress=n_edges > VERIFY_ANNOUNCE_EDGES)
    except (ValueError, KeyboardInterrupt, MemoryError):
        raise
    except (IndexError, KeyError, TypeError, AttributeError) as exc:   # a document that parses but is not a diagram
        raise ValueError(f"{args.diagram}: malformed diagram document ({type(exc).__name__}: {exc})") from None
    seconds = time.perf_counter() - t0
    doc = cert.to_json()
    if args.output:
        try:
            with open(args.output, "w") as fh:
                fh.write(json.dumps(doc, indent=2) + "\n")
        except OSError as exc:
            print(f"error: cannot write {args.output}: {exc.strerror}", file=sys.stderr)
            return EXIT_FAILED
    summary = _verify_summary(cert, seconds)
    if args.verbose:
        print(json.dumps(doc, indent=2))
        if not args.quiet:
            print(summary, file=sys.stderr)
    elif not args.quiet:
        print(summary)
    return 0 if cert.ok else EXIT_FAILED


def build_parser() -> argparse.ArgumentParser:
    __version__ = _version()

    from .voronoi.command import OneLineParser

    p = OneLineParser(
        prog="curvedvoronoi",
        description="Certified Voronoi diagrams and Delaunay-graph conflict locator for conics "
                    "(F. Anton, Voronoi diagrams of semi-algebraic sets, 2003).",
        epilog="Sites are numbered from 0.  Input schema and examples: docs/index.md.  "
               "`curvedvoronoi COMMAND --help` for each command.")
    p.add_argument("--version", action="version", version=f"curvedvoronoi {__version__}")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    methods = ["auto", "triple", "quadruple", "circles", "interval"]
    s = sub.add_parser("locate", help="conflict locator on four sites (FILE.json); JSON out",
                       description="Which true Voronoi vertices of sites 0, 1, 2 (centres of empty circles "
                                   "tangent to the three) does site 3 enter?  Thesis ch. 5 (conics), §3.1 "
                                   "(circles and points).")
    s.add_argument("file", help='JSON sites file with four sites: {"sites": [SITE, SITE, SITE, SITE]} '
                                '(see docs/index.md for the forms of SITE)')
    _add_common(s, methods)
    s.set_defaults(func=_locate)
    s = sub.add_parser("diagram", help="Voronoi diagram / Delaunay graph of any number of sites (SITES.json)",
                       add_help=False)
    s.add_argument("rest", nargs=argparse.REMAINDER)
    s.set_defaults(func=_diagram)
    s = sub.add_parser("medial-axis", help="medial axis of a polygon with holes (SHAPE.dxf, .geojson or .json)",
                       add_help=False)
    s.add_argument("rest", nargs=argparse.REMAINDER)
    s.set_defaults(func=_medial_axis)
    s = sub.add_parser("demo", help="the locator on a built-in four-ellipse configuration (thesis Fig. 5.5.1)",
                       description="Runs `locate` on four ellipses placed like thesis Fig. 5.5.1 "
                                   "(the sites are listed on stderr).")
    _add_common(s, methods)
    s.set_defaults(func=_demo)
    s = sub.add_parser("verify", help="prove a diagram (DIAGRAM.json): exit 0 proved, 1 not proved",
                       description="Independent certificate that DIAGRAM.json (curvedvoronoi.diagram/1) is the "
                                   "Voronoi diagram of its sites (or of SITES.json); prints one summary line "
                                   "(-v: the whole certificate).  Exit status: 0 proved, 1 not proved, 2 bad input.")
    s.add_argument("diagram", help="diagram JSON written by `diagram --json` or Diagram.to_json()")
    s.add_argument("sites", nargs="?", default=None, help="optional sites file; default: the diagram's sites")
    s.add_argument("-v", "--verbose", action="store_true",
                   help="print the whole certificate (JSON) on stdout, the summary on stderr")
    s.add_argument("-o", "--output", metavar="OUT.json", help="write the certificate (JSON) there")
    s.add_argument("-q", "--quiet", action="store_true", help="no summary line (the exit status says it)")
    s.set_defaults(func=_verify)
    s = sub.add_parser("offsets", help="table of generalised offsets (thesis Table 4.1, App. B)",
                       description="Sizes of the generalised offsets of each conic family, read from the "
                                   "verified artefacts; R is the squared offset distance.")
    s.add_argument("--json", action="store_true", help="machine-readable output")
    s.add_argument("--curve", metavar="F", help='offset of the curve F(x, y) = 0, e.g. "y^2 - x^2 - x^3", '
                   "with the degree formula of thesis Theorem 4.2.18")
    s.set_defaults(func=_offsets_table)
    return p


def main(argv=None) -> int:
    """Entry point of the ``curvedvoronoi`` script and ``python -m curvedvoronoi``: every command,
    with a one-line message (no traceback) for a missing package or an interruption."""
    try:
        return _dispatch(argv)
    except ImportError as exc:
        from .optional import MissingDependencyError, missing_message

        name = getattr(exc, "name", None)
        msg = str(exc) if isinstance(exc, MissingDependencyError) or not name else missing_message(name)
        print(f"error: {msg}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


def _dispatch(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["diagram"]:          # its own parser (runtime.voronoi.command), incl. --help
        from .segments.command import diagram_main     # DXF / GeoJSON drawings; sites files go on

        return diagram_main(argv[1:])
    if argv[:1] == ["medial-axis"]:      # its own parser (runtime.segments.command), incl. --help
        from .segments.command import medial_axis_main

        return medial_axis_main(argv[1:])
    args = build_parser().parse_args(argv)
    from .result import InvalidConicError, LocatorError

    try:
        return args.func(args)
    except LocatorError as exc:  # the input is fine but the locator cannot answer it reliably
        bad_input = isinstance(exc, InvalidConicError)
        print(f"error: {_zero_based(str(exc))}", file=sys.stderr)
        if type(exc).__name__ == "NumericalRefusal":   # valid input, numeric routes refused: exit 3
            return 3
        return EXIT_BAD_INPUT if bad_input else EXIT_FAILED
    except ValueError as exc:    # bad input
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except (RuntimeError, OverflowError, MemoryError) as exc:  # e.g. ArtefactError
        print(f"error: {type(exc).__name__}: {exc}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:      # output piped into `head` etc.
        sys.stderr.close()
        return 0


if __name__ == "__main__":
    sys.exit(main())
