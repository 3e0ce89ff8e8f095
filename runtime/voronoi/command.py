"""The ``diagram`` command: ``python -m curvedvoronoi diagram SITES.json [--json OUT.json]
[--png OUT.png] [--geojson OUT.geojson] [--crs CRS] [--window=XMIN,XMAX,YMIN,YMAX] [--quiet]
[--time-limit S] [--no-certify] [--empty-circles] [--out DIR] [--scheduler ADDRESS]
[--sites-per-tile N] [--certificate whole|chunks]``.

SITES.json is ``{"sites": [...]}`` with the records of :func:`runtime.sites.reader.parse_site`
(``{"point": [x, y]}``, ``{"circle": {"centre": [x, y], "radius": r}}``,
``{"coefficients": [a, b, c, d, e, f]}``) or the older ``{"conics": [{"coefficients": ...}]}``.
Prints a summary (the diagram JSON on stdout when no ``--json`` is given and not ``--quiet``).
``--geojson`` writes the edges, vertices and sites (:mod:`runtime.voronoi.geojson`) with the
``crs`` member GDAL reads: ``--crs`` (e.g. ``EPSG:32633``), by default a planar engineering CRS
(``--crs none``: no member, which GIS tools read as longitude/latitude).

SITES may also be GeoParquet (a ``.parquet`` file or a directory of part files: Points, with an
optional ``radius`` column; :mod:`runtime.voronoi.geoparquet`), whose CRS the outputs carry unless
``--crs`` says otherwise.  ``--out DIR`` writes the diagram as GeoParquet datasets partitioned by
region.  ``--scheduler ADDRESS`` builds the diagram tile by tile on a Dask cluster
(:func:`runtime.voronoi.distributed.tiled_voronoi`; ``local`` or ``local:N`` starts a local
cluster of N worker processes); ``--sites-per-tile N`` sets the tiles' size (alone: tiles built one
after the other here); ``--certificate chunks`` proves the stitched diagram chunk by chunk
(:func:`runtime.voronoi.chunked_certificate.chunked_verify`).

Exit status (the requested outputs are written whenever a diagram exists):

* 0 -- the diagram is certified (proved by the independent verifier,
  :func:`runtime.voronoi.verify.certificate.verify`), or, with ``--no-certify``, the construction
  ran to its end (not verified, on request);
* 1 -- a diagram was written but is not certified (something is not proved, or the time limit
  stopped it), or the program failed on valid input (one line naming the failure);
* 2 -- bad input (one line on stderr starting ``error:``);
* 3 -- a numeric route refused valid input (:class:`runtime.result.NumericalRefusal`);
* 130 -- interrupted (Ctrl-C): the partial result is written, marked not certified.

Public API: :func:`diagram_main` (sites files are read by :func:`runtime.sites.reader.read_sites`).
"""
from __future__ import annotations

import argparse
import json
import math
import signal
import sys
from pathlib import Path

from ..result import InvalidConicError, NumericalRefusal
from ..sites.reader import read_sites

__all__ = ["diagram_main", "parse_window", "OneLineParser", "EXIT_CERTIFIED", "EXIT_NOT_CERTIFIED", "EXIT_BAD_INPUT",
           "EXIT_NUMERICAL_REFUSAL", "EXIT_INTERRUPTED"]

EXIT_CERTIFIED = 0
EXIT_NOT_CERTIFIED = 1
EXIT_BAD_INPUT = 2
EXIT_NUMERICAL_REFUSAL = 3
EXIT_INTERRUPTED = 130

INTERRUPTED_NOTE = "interrupted (Ctrl-C)"


class OneLineParser(argparse.ArgumentParser):
    """argparse with usage errors as one line ``error: ...`` on stderr, exit status 2."""

    def error(self, message):
        print(f"error: {message} (see `{self.prog} --help`)", file=sys.stderr)
        sys.exit(EXIT_BAD_INPUT)


def parse_window(text: str) -> tuple[float, float, float, float]:
    """``"xmin,xmax,ymin,ymax"`` (matplotlib's ``axis`` order) as four finite floats with
    xmin < xmax and ymin < ymax; ``argparse.ArgumentTypeError`` otherwise."""
    parts = text.split(",")
    try:
        vals = tuple(float(p) for p in parts)
    except ValueError:
        vals = ()
    if len(vals) != 4 or not all(math.isfinite(v) for v in vals):
        raise argparse.ArgumentTypeError(f"--window {text!r}: expected four finite numbers xmin,xmax,ymin,ymax")
    if not (vals[0] < vals[1] and vals[2] < vals[3]):
        raise argparse.ArgumentTypeError(f"--window {text!r}: needs xmin < xmax and ymin < ymax")
    return vals


def diagram_parser(description: str, sites_help: str, *, interrupted: str, crs_of: str,
                   time_limit_help: str) -> OneLineParser:
    """The ``curvedvoronoi diagram`` options shared by every site kind (the segment diagram adds its
    DXF options to it)."""
    p = OneLineParser(prog="curvedvoronoi diagram", description=description,
                      epilog="Exit status: 0 certified (with --no-certify: ran to the end, not verified on "
                             "request), 1 not certified or failed, 2 bad input, 3 numerical refusal, "
                             f"130 interrupted{interrupted}.")
    p.add_argument("sites", help=sites_help)
    p.add_argument("--json", dest="json_out", help="write the diagram (curvedvoronoi.diagram/1) here")
    p.add_argument("--png", help="write a picture here")
    p.add_argument("--window", type=parse_window, metavar="XMIN,XMAX,YMIN,YMAX",
                   help="the picture's window (default: fitted to the sites); write --window=-1,1,-1,1 "
                        "when the first number is negative")
    p.add_argument("--geojson", help="write the edges, vertices and sites as GeoJSON here")
    p.add_argument("--crs", default=None,
                   help=f"{crs_of} coordinate reference system for --geojson, e.g. EPSG:32633 (default: a "
                        "planar engineering CRS, so that GIS tools do not read longitude/latitude; 'none': "
                        "no crs member)")
    p.add_argument("--empty-circles", action="store_true", help="draw the vertices' empty circles")
    p.add_argument("--quiet", action="store_true", help="no summary, no progress bar")
    p.add_argument("--time-limit", type=float, default=None, help=time_limit_help)
    p.add_argument("--no-certify", action="store_true",
                   help="skip the verifier (never certified; exit 0 when the construction ran to its end)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--out", metavar="DIR",
                   help="write the edges, vertices, cells and sites as GeoParquet datasets (part files grouped "
                        "by region) and diagram.json here (needs geopandas and pyarrow)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="build tile by tile on this Dask scheduler (tcp://host:port), or 'local' / 'local:N' for "
                        "a local cluster of N worker processes (default 2); needs dask[distributed]")
    p.add_argument("--sites-per-tile", type=int, default=None, metavar="N",
                   help="build tile by tile with about N sites a tile (default with --scheduler: 2000)")
    p.add_argument("--certificate", choices=("whole", "chunks"), default="whole",
                   help="tiled builds: prove the stitched diagram whole, or chunk by chunk (on the workers, or "
                        "here one chunk at a time: the verifier's memory is one chunk's)")
    return p


def _parser():
    return diagram_parser("Voronoi diagram / Delaunay graph of disjoint circles, points and "
                          "conics (thesis §1.2), certified by an independent verifier.",
                          'JSON file {"sites": [...]} or {"conics": [{"coefficients": [...]}, ...]}',
                          interrupted=" (partial result written, not certified)", crs_of="the sites'",
                          time_limit_help="stop after S seconds (partial result)")


def run_construction(build, *, bad_input_prefix: str = "", what: str = "the construction"):
    """``(build(), None)``, or ``(None, exit status)`` after one line on stderr: a numerical refusal
    (3), bad input found by the construction — intersecting or repeated sites, a degenerate conic
    (2) — or any other failure on valid input (1, "please report it").  Ctrl-C, ImportError and
    MemoryError pass through to the caller."""
    try:
        return build(), None
    except NumericalRefusal as exc:
        print(f"error: {exc}", file=sys.stderr)
        return None, EXIT_NUMERICAL_REFUSAL
    except InvalidConicError as exc:
        print(f"error: {bad_input_prefix}{exc}", file=sys.stderr)
        return None, EXIT_BAD_INPUT
    except (ImportError, MemoryError, KeyboardInterrupt):
        raise
    except Exception as exc:  # noqa: BLE001 - valid input the construction failed on: one line, exit 1
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
        print(f"error: {what} failed on this input ({type(exc).__name__}"
              + (f": {msg}" if msg else "") + "); please report it", file=sys.stderr)
        return None, EXIT_NOT_CERTIFIED


def print_summary(d, doc: dict | None, args) -> None:
    """Unless ``--quiet``: the diagram document on stdout (when not written to ``--json``; None:
    :meth:`runtime.voronoi.structure.Diagram.write_json`'s, streamed) and one summary line on
    stderr."""
    if args.quiet:
        return
    if not args.json_out:
        if doc is None:
            d.write_json(sys.stdout)
            print()
        else:
            print(json.dumps(doc, indent=1))
    print(f"{len(d.sites)} sites, {len(d.vertices)} vertices, {len(d.edges)} edges, "
          f"{len(d.delaunay_edges())} Delaunay edges, certified={d.certified}"
          + (f"; {len(d.problems)} problems, first: {d.problems[0]}" if d.problems else ""), file=sys.stderr)


def crs_option(text):
    """``--crs``: the CRS name for :func:`runtime.voronoi.geojson.crs_member` (None: the planar
    engineering CRS; ``none``: False, no member)."""
    return False if (text or "").lower() == "none" else text


def write_text(path, text, what) -> None:
    """Write an output file; an OSError becomes one line naming the output (``what``) and the path."""
    write_stream(path, lambda fh: fh.write(text), what)


def write_stream(path, write, what) -> None:
    """Open the output file ``path`` and call ``write(file)`` (a streaming writer: the document is
    written piece by piece, never held whole); an OSError becomes one line naming the output
    (``what``) and the path."""
    try:
        with open(path, "w") as fh:
            write(fh)
    except OSError as exc:
        raise OSError(f"cannot write the {what} {path}: {exc.strerror}") from None


def draw_picture(obj, path, **kw) -> None:
    """``--png``: any failure of the drawing becomes OSError (one line), except a missing matplotlib
    (ImportError, reported by :func:`runtime.cli.main` with the package to install)."""
    try:
        obj.plot(path, **kw)
    except (ImportError, KeyboardInterrupt):
        raise
    except OSError as exc:
        raise OSError(f"cannot write the picture {path}: {exc.strerror or exc}") from None
    except Exception as exc:  # noqa: BLE001 - the JSON outputs are written; say what the picture hit
        raise OSError(f"cannot draw the picture {path}: {type(exc).__name__}: {exc}") from None


def _write_parquet(d, directory, crs) -> None:
    from .geoparquet import write_geoparquet

    try:
        write_geoparquet(d, directory, crs=None if crs is False else crs)
    except OSError as exc:
        raise OSError(f"cannot write the GeoParquet datasets in {directory}: {exc.strerror or exc}") from None


def _exit_status(d, certify: bool, interrupted: bool) -> int:
    if interrupted:
        return EXIT_INTERRUPTED
    if d.certified:
        return EXIT_CERTIFIED
    if not certify and not any(p.startswith("time limit of") for p in d.problems):
        return EXIT_CERTIFIED            # not verified on request, but the construction ran to its end
    return EXIT_NOT_CERTIFIED


def is_geoparquet(path: str) -> bool:
    """A GeoParquet input: a ``.parquet`` file or a directory of part files."""
    p = Path(path)
    return p.suffix.lower() in (".parquet", ".geoparquet") or (p.is_dir() and any(p.glob("*.parquet")))


def _read_input(args):
    """The sites and the CRS the outputs should carry (``--crs``, else a GeoParquet file's own)."""
    crs = crs_option(args.crs)
    if is_geoparquet(args.sites):
        from .geoparquet import read_geoparquet_sites

        sites, file_crs = read_geoparquet_sites(args.sites)
        return sites, (file_crs if args.crs is None else crs)
    return read_sites(args.sites), crs


def _client(address: str):
    """A ``distributed.Client`` on ``address``; ``local`` / ``local:N``: a LocalCluster of N worker
    processes (one thread each) started here and closed with the client."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise ImportError("--scheduler needs dask[distributed] (pip install \"dask[distributed]\")") from None
    if address == "local" or address.startswith("local:"):
        n = int(address.split(":", 1)[1]) if ":" in address else 2
        import dask

        # the scheduler shares this process with the driver's stitch and serialisation, which can keep a
        # worker's heartbeat waiting past the default worker-ttl (5 min) on large inputs
        with dask.config.set({"distributed.scheduler.worker-ttl": "1h"}):
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None)
        return Client(cluster)
    return Client(address)


def _build(sites, args, progress):
    """The construction the options ask for: tile by tile (``--scheduler``, ``--sites-per-tile``) or
    in one process."""
    certify = not args.no_certify
    if args.scheduler is None and args.sites_per_tile is None:
        from .construction import voronoi

        return voronoi(sites, certify=certify, progress=progress, time_limit=args.time_limit)
    from .distributed import tiled_voronoi

    client = None if args.scheduler is None else _client(args.scheduler)
    try:
        return tiled_voronoi(sites, client=client, certify=certify, progress=progress,
                             sites_per_tile=args.sites_per_tile or 2000, certificate=args.certificate)
    finally:
        if client is not None:
            cluster = client.cluster if args.scheduler.startswith("local") else None
            client.close()
            if cluster is not None:
                cluster.close()


def diagram_main(argv=None) -> int:
    args = _parser().parse_args(argv)
    if args.sites_per_tile is not None and args.sites_per_tile < 1:
        print(f"error: --sites-per-tile {args.sites_per_tile}: expected a positive number", file=sys.stderr)
        return EXIT_BAD_INPUT
    if args.certificate == "chunks" and args.scheduler is None and args.sites_per_tile is None:
        print("error: --certificate chunks proves a tiled build: give --scheduler or --sites-per-tile",
              file=sys.stderr)
        return EXIT_BAD_INPUT
    if args.scheduler is not None and args.time_limit is not None:
        print("error: --time-limit is not available with --scheduler (interrupt with Ctrl-C: the finished tiles "
              "are kept)", file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        sites, crs = _read_input(args)
    except ValueError as exc:          # unreadable file, schema, NaN, repeated sites, ...
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    if len(sites) < 2:
        print(f"error: {args.sites}: the Voronoi diagram needs at least 2 sites, got {len(sites)}", file=sys.stderr)
        return EXIT_BAD_INPUT

    from .geojson import write_geojson
    from .structure import Diagram

    # Ctrl-C: record it, then let the construction stop (it returns its last finished round)
    state = {"interrupted": False}
    previous = signal.getsignal(signal.SIGINT)

    def on_sigint(signum, frame):
        state["interrupted"] = True
        raise KeyboardInterrupt

    try:
        signal.signal(signal.SIGINT, on_sigint)
    except ValueError:                 # not the main thread: keep the default handler
        previous = None
    try:
        progress = None if not (args.quiet or args.no_progress) else False
        try:
            d, status = run_construction(lambda: _build(sites, args, progress))
        except KeyboardInterrupt:
            state["interrupted"] = True
            d, status = Diagram(sites, [], [], False, [f"{INTERRUPTED_NOTE}: no diagram computed"], {}), None
        if status is not None:
            return status
        if state["interrupted"] and not any(p.startswith("interrupted") for p in d.problems):
            d.problems.append(f"{INTERRUPTED_NOTE}: partial diagram")
        if state["interrupted"]:
            d.certified = False
        # the outputs: written even when not certified (and after Ctrl-C, marked)
        try:
            if args.json_out:
                write_stream(args.json_out, d.write_json, "diagram JSON")
            if args.geojson:
                write_stream(args.geojson, lambda fh: write_geojson(d, fh, crs), "GeoJSON")
            if args.png:
                draw_picture(d, args.png, empty_circles=args.empty_circles, window=args.window)
            if args.out:
                _write_parquet(d, args.out, crs)
        except OSError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return EXIT_NOT_CERTIFIED
        except KeyboardInterrupt:
            state["interrupted"] = True
            print("interrupted while writing the outputs", file=sys.stderr)
            return EXIT_INTERRUPTED
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
    print_summary(d, None, args)
    return _exit_status(d, not args.no_certify, state["interrupted"])
