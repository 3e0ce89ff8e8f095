"""Command line: ``python -m curvedvoronoi {offsets,locate,demo,...}``.

* ``offsets``  -- the table of generalised offsets (thesis Table 4.1 and App. B), from the
  verified artefacts.
* ``locate FILE.json`` -- the conflict locator on four conics given as
  ``{"conics": [{"coefficients": [a, b, c, d, e, f]}, ...]}`` (numbers or rational strings).
* ``demo`` -- the locator on a built-in four-ellipse configuration.

Errors in the input give a one-line message on stderr and exit status 2.
"""
from __future__ import annotations

import argparse
import json
import sys

EXIT_BAD_INPUT = 2


def _offsets_table(args) -> int:
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


def read_conics_file(path: str, expected: int | None = 4):
    """Parse ``{"conics": [{"coefficients": [a,b,c,d,e,f]}, ...]}`` into Conic objects."""
    from .conic import Conic
    from .sites_io import read_coefficient_lists

    out = []
    for i, coeffs in enumerate(read_coefficient_lists(path, expected), 1):
        try:
            out.append(Conic.from_coefficients(*coeffs))
        except ValueError as exc:
            raise ValueError(f"conic {i}: {exc}") from None
    return out


def _locate(args) -> int:
    from . import locator

    conics = read_conics_file(args.file, expected=4)
    result = locator.locate_conflicts(*conics, method=args.method)
    print(json.dumps(result.to_dict(details=args.details), indent=2))
    return 0


def _demo(args) -> int:
    from . import locator

    conics = locator.demo_configuration()
    print("Demo: four ellipses (a rigid-motion version of thesis Fig. 5.5.1)", file=sys.stderr)
    for i, c in enumerate(conics, 1):
        print(f"  C{i}: {c}", file=sys.stderr)
    result = locator.locate_conflicts(*conics, method=args.method)
    print(json.dumps(result.to_dict(details=args.details), indent=2))
    return 0


def _diagram(args) -> int:
    from .diagram import diagram_main

    return diagram_main(args.rest)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="curvedvoronoi",
                                description="Certified Delaunay-graph conflict locator for conics "
                                            "(F. Anton, Voronoi diagrams of semi-algebraic sets, 2003).")
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser("offsets", help="print the table of generalised offsets (Table 4.1, App. B)")
    s.add_argument("--json", action="store_true", help="machine-readable output")
    s.set_defaults(func=_offsets_table)
    methods = ["auto", "triple", "quadruple", "circles", "interval"]
    s = sub.add_parser("locate", help="run the conflict locator on FILE.json (four conics)")
    s.add_argument("file", help='JSON file {"conics": [{"coefficients": [a,b,c,d,e,f]}, x4]}')
    s.add_argument("--method", choices=methods, default="auto",
                   help="auto (default: fastest certified route), triple (per-triple vertices + distances), "
                        "quadruple (the thesis' four-conic system), circles (exact, circles only), "
                        "interval (branch-and-prune, ch. 6)")
    s.add_argument("--details", action="store_true", help="include per-vertex diagnostics and certificates")
    s.set_defaults(func=_locate)
    s = sub.add_parser("diagram", help="Delaunay graph / Voronoi diagram of any number of conics (SITES.json)",
                       add_help=False)
    s.add_argument("rest", nargs=argparse.REMAINDER)
    s.set_defaults(func=_diagram)
    s = sub.add_parser("demo", help="run the locator on a built-in four-ellipse configuration")
    s.add_argument("--method", choices=methods, default="auto")
    s.add_argument("--details", action="store_true", help="include per-vertex diagnostics and certificates")
    s.set_defaults(func=_demo)
    return p


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["diagram"]:          # its own parser (runtime.diagram), incl. --help
        from .diagram import diagram_main

        return diagram_main(argv[1:])
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except ValueError as exc:   # bad input (InvalidConicError and LocatorError are ValueErrors)
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except RuntimeError as exc:  # e.g. ArtefactError
        print(f"error: {exc}", file=sys.stderr)
        return 1
    except BrokenPipeError:      # output piped into `head` etc.
        sys.stderr.close()
        return 0


if __name__ == "__main__":
    sys.exit(main())
