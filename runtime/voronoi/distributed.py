"""The Voronoi diagram built tile by tile, in one process or on a Dask cluster.

:func:`tiled_voronoi` cuts the plane into tiles, gives each a halo of neighbouring sites large
enough by the locality lemma of :mod:`runtime.voronoi.tiling` (checked before the tile is built,
and again at every vertex the tile reports; a halo too small is doubled and the tile rebuilt, as
Peterka, Morozov and Phillips grow their ghost zones, SC14), builds the tiles' diagrams with
:func:`runtime.voronoi.construction.voronoi` -- one Dask task per tile when a
``distributed.Client`` is given, else one after the other in this process -- stitches them
(:func:`runtime.voronoi.stitch.stitch`) and proves the stitched diagram with the independent
verifier (:func:`runtime.voronoi.verify.certificate.verify`) once on the whole diagram here, or
(``certificate="chunks"``, with a client) its vertex and edge proofs chunk by chunk on the
workers and the closure and the ends at infinity here (:mod:`runtime.voronoi.chunked_certificate`).  When the verifier finds faults, the tiles holding the sites it names are rebuilt
with their own verifier, whose problems refine their construction (as
:func:`runtime.voronoi.construction.voronoi` does), and the stitch is verified again.  The
result is a :class:`runtime.voronoi.structure.Diagram` on the input's site indices,
``certified`` only when the verifier proves it.

Scenes the tiling does not cover are built by :func:`runtime.voronoi.construction.voronoi` in one
process, and ``stats["tiling"]["single_process"]`` says why: fewer sites than two tiles hold, a
site inside another (nesting), an unbounded site, segments or arcs, or a tile whose diagram has
an edge without vertex (sites in a row).  Interrupted (Ctrl-C), the finished tiles are stitched
and returned, not certified.

Public API: :func:`tiled_voronoi`.
"""
from __future__ import annotations

import time

import numpy as np

from ..threads import one_blas_thread
from .site_input import as_site, check_disjoint
from .chunked_certificate import chunked_verify
from .stitch import StitchError, build_tile, stitch
from .tiling import MARGIN, Rim, grow_halo, nested_pair, site_discs, tile_grid, tile_input
from .verify.problems import faulted_sites

__all__ = ["tiled_voronoi"]

#: rebuilds of one tile with a grown halo before the tiling gives up on it
MAX_REBUILDS = 8
#: verifications of the stitched diagram (the tiles its faults name are rebuilt in between)
VERIFY_ROUNDS = 2
#: at most about this many edges in one chunk of ``certificate="chunks"`` (about 7·10⁴ circle sites)
CHUNK_EDGES = 200_000


def _single(sites, reason, certify, progress, t0):
    from .construction import voronoi

    d = voronoi(sites, certify=certify, progress=progress)
    d.stats["tiling"] = {"single_process": reason}
    d.stats.setdefault("seconds", {})["tiled_total"] = round(time.perf_counter() - t0, 4)
    return d


def _tasks(client, jobs, bar):
    """Yield (job key, report) as the tile builds finish: Dask futures gathered as completed, or
    the jobs run one by one here."""
    if client is None:
        for key, args in jobs:
            rep = build_tile(*args)
            if bar is not None:
                bar.update(1)
            yield key, rep
        return
    from distributed import as_completed

    futures = {client.submit(build_tile, *args, pure=False, key=f"curvedvoronoi-tile-{key}-{time.time_ns()}"): key
               for key, args in jobs}
    try:
        for fut in as_completed(list(futures)):
            rep = fut.result()
            if bar is not None:
                bar.update(1)
            yield futures[fut], rep
    finally:
        for fut in futures:
            if not fut.done():
                fut.cancel()


@one_blas_thread
def tiled_voronoi(sites, *, client=None, sites_per_tile: int = 2000, halo: float | None = None,
                  certify: bool = True, progress=None, tile_certify: bool = False, certificate: str = "whole"):
    """The Voronoi diagram of ``sites`` (thesis §1.2) built tile by tile.

    Parameters
    ----------
    sites : list
        Points, circles, ellipses (any form :func:`runtime.voronoi.construction.voronoi` takes).
    client : distributed.Client, optional
        One task per tile on its workers; None: the tiles are built here, one after the other.
    sites_per_tile : int
        About how many sites a tile holds (its halo adds more).
    halo : float, optional
        The initial halo (default: three times the mean spacing of the sites); each tile's is
        doubled until the locality lemma holds (``stats["tiling"]["halo_growths"]``).
    certify : bool
        Prove the stitched diagram with the verifier; ``certified`` is its verdict.
    tile_certify : bool
        Also run the verifier on each tile's own diagram (its problems drive the construction's
        refinement); the stitched diagram's proof is the global verification either way.
    progress : bool or None
        A tqdm bar over the tiles (None: for more than 2000 sites).
    certificate : {"whole", "chunks"}
        ``"whole"``: the verifier runs on the whole stitched diagram here.  ``"chunks"``: its
        vertex and edge proofs run chunk by chunk (on the workers with a client, else here one
        chunk at a time: the verifier's memory is one chunk's, at most :data:`CHUNK_EDGES` edges),
        the unbounded edges and the ends at infinity in one chunk of their own, and the closure
        here (:func:`runtime.voronoi.chunked_certificate.chunked_verify`), and the whole verifier
        only when that refuses; a chunk of circles and points gets only the sites near it
        (bench/results/scale.md).
        ``stats["tiling"]["certificate"]`` says which proved it.

    Examples
    --------
    >>> import curvedvoronoi as cv
    >>> import random
    >>> rng = random.Random(1)
    >>> sites = [(10 * i + rng.uniform(0, 5), 10 * j + rng.uniform(0, 5), rng.uniform(0.5, 2))
    ...          for i in range(8) for j in range(8)]
    >>> d = cv.tiled_voronoi(sites, sites_per_tile=20)
    >>> d.certified, d.stats["tiling"]["tiles"]
    (True, 4)
    """
    t0 = time.perf_counter()
    plan = _plan(sites, sites_per_tile, halo)
    if isinstance(plan, str):
        return _single(sites, plan, certify, progress, t0)
    sites, D, tiles = plan
    if progress is None:
        progress = len(sites) > 2000
    run = _Regions(sites, D, tiles, client, tile_certify, _progress_bar(progress, len(tiles) + 1))
    seconds: dict = {"tiles": 0.0, "stitch": 0.0, "verify": 0.0}
    interrupted = False
    pending = [run.rim, *tiles]
    cert = None
    for _ in range(VERIFY_ROUNDS):
        t1 = time.perf_counter()
        try:
            run.build(pending)
        except _Vertexless as exc:
            run.close()
            return _single(sites, exc.reason, certify, progress, t0)
        except KeyboardInterrupt:
            interrupted = True
        t2 = time.perf_counter()
        try:
            diagram, info = stitch(sites, list(run.reports.values()), D.scale)
        except StitchError as exc:
            return _single(sites, f"stitch refused: {exc}", certify, progress, t0)
        t3 = time.perf_counter()
        seconds["tiles"] += t2 - t1
        seconds["stitch"] += t3 - t2
        if interrupted or not certify:
            break
        cert = _prove(diagram, info, client, certificate, tiles, progress)
        seconds["verify"] += time.perf_counter() - t3
        named = faulted_sites(cert.problems, diagram) if not cert.ok else set()
        if cert.ok or not named:
            break
        pending = run.refine(named)
    run.close()
    info.update(run.summary())
    diagram.stats.update({"sites": len(sites), "tiling": info})
    diagram.construction = _editing_state(sites)
    _record_verdict(diagram, cert, interrupted, f"{len(run.reports)} of {len(tiles) + 1} regions stitched")
    seconds["total"] = time.perf_counter() - t0
    diagram.stats["seconds"] = {k: round(v, 4) for k, v in seconds.items()}
    return diagram


def _plan(sites, sites_per_tile: int, halo):
    """The sites as site objects, their discs and the tiles with halos grown a priori by the
    locality lemma; or, for a scene the tiling does not cover, the reason (a string)."""
    sites = list(sites)
    if any(type(s).__name__ in ("Segment", "Arc") for s in sites):
        return "segments or arcs"
    sites = [as_site(s) for s in sites]
    if len(sites) < 2 * sites_per_tile:
        return f"{len(sites)} sites: fewer than two tiles of {sites_per_tile}"
    try:
        D = site_discs(sites)
    except ValueError as exc:
        return str(exc)
    check_disjoint(sites)
    nest = nested_pair(D)
    if nest is not None:
        return f"site {nest[1]} may lie inside site {nest[0]} (nesting)"
    tiles = tile_grid(D, sites_per_tile, halo)
    for t in tiles:
        grow_halo(D, t, MARGIN * D.scale)
    return sites, D, tiles


def _progress_bar(progress: bool, total: int):
    if not progress:
        return None
    try:
        from tqdm import tqdm
    except ImportError:
        return None
    return tqdm(total=total, desc="voronoi tiles", unit="tile", leave=False)


class _Regions:
    """The tiles and the rim of one tiled build: their inputs (the sites of each region with its
    halo), their reports, and the halo growths and rebuilds (:meth:`build`, :meth:`refine`)."""

    def __init__(self, sites, D, tiles, client, tile_certify: bool, bar):
        self.sites, self.D, self.tiles, self.client, self.bar = sites, D, tiles, client, bar
        self.margin = MARGIN * D.scale
        self.a_priori = sum(t.growths for t in tiles)
        self.rim = Rim(D.bound(), min(t.halo for t in tiles))
        self.regions = {t.index: t for t in tiles}
        self.regions[self.rim.index] = self.rim
        self.inputs: dict = {}
        self.proving = {key: tile_certify for key in self.regions}   # regions built with their own verifier
        self.reports: dict = {}
        self.rebuilds = 0
        self.refined = 0
        self.by_region: dict = {}

    def job(self, t):
        idx = t.sites(self.D) if t is self.rim else tile_input(self.D, t)
        self.inputs[t.index] = idx
        return t.index, ([self.sites[i] for i in idx.tolist()], idx, t, self.margin, self.proving[t.index])

    def build(self, pending) -> None:
        """Build the regions, growing and rebuilding those whose vertices leave their halo."""
        while pending:
            again = []
            for key, rep in _tasks(self.client, [self.job(t) for t in pending], self.bar):
                if rep["vertexless"]:
                    raise _Vertexless(key)
                if rep["grow"] > 0:                  # an empty circle leaves T_h: grow the halo, rebuild
                    again.append(self.grow(key, rep["grow"]))
                    continue
                self.reports[key] = rep
            pending = again

    def grow(self, key, out: float):
        region = self.regions[key]
        if self.by_region.get(key, 0) >= MAX_REBUILDS:
            raise _Vertexless(key, "halo keeps growing")
        self.by_region[key] = self.by_region.get(key, 0) + 1
        if region is self.rim:
            self.rim.width = max(2 * self.rim.width, self.rim.width + out)
            self.rim.growths += 1
        else:
            grow_halo(self.D, region, self.margin, at_least=region.halo + out)
        self.rebuilds += 1
        if self.bar is not None:
            self.bar.total += 1
        return region

    def refine(self, named) -> list:
        """The verifier names what a tile's sampling missed: the regions holding those sites, to
        be rebuilt with their own verifier, whose problems refine the construction (as
        :func:`runtime.voronoi.construction.voronoi` does)."""
        hit = np.zeros(len(self.sites), dtype=bool)
        hit[sorted(named)] = True
        pending = [self.regions[k] for k, idx in self.inputs.items() if hit[idx].any()]
        for t in pending:
            self.proving[t.index] = True
        self.refined += len(pending)
        if self.bar is not None:
            self.bar.total += len(pending)
        return pending

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()

    def summary(self) -> dict:
        reports, rim, tiles = self.reports, self.rim, self.tiles
        return {"tiles": len(tiles), "tiles_built": len(reports) - (rim.index in reports),
                "rim_width": rim.width, "rim_sites": reports[rim.index]["sites"] if rim.index in reports else None,
                "halo_growths": sum(t.growths for t in tiles), "halo_growths_a_priori": self.a_priori,
                "rebuilds": self.rebuilds, "refined_by_verifier": self.refined,
                "halos": [t.halo for t in tiles], "tile_sites": [reports[k]["sites"] for k in sorted(reports) if k >= 0],
                "tile_seconds": [round(reports[k]["seconds"], 3) for k in sorted(reports)],
                "client": None if self.client is None else str(self.client.scheduler.address)}


def _prove(diagram, info, client, certificate: str, tiles, progress):
    """The verifier's certificate of the stitched diagram: chunk by chunk on the workers first
    when asked (``certificate="chunks"``), the whole verifier here otherwise or when that refuses."""
    from .verify.certificate import verify

    if certificate == "chunks":
        workers = 1 if client is None else max(1, len(client.scheduler_info().get("workers", {})))
        count = max(2 * workers, -(-len(diagram.edges) // CHUNK_EDGES))
        t0 = time.perf_counter()
        cc = chunked_verify(diagram, _chunks(diagram, tiles, count), client)
        info["certificate"] = "chunks"
        info["chunk_seconds"] = {k: round(v, 3) for k, v in cc.seconds.items()}
        if cc.ok:
            return cc
        info["chunks_refused"] = [str(p) for p in cc.problems[:5]]
        info["chunks_refused_seconds"] = round(time.perf_counter() - t0, 3)
    info["certificate"] = "whole"
    return verify(diagram, progress=progress)


def _editing_state(sites):
    """The state :meth:`runtime.voronoi.structure.Diagram.insert` and ``delete_site`` need (the
    sites' arrays; no samples): the local updates of :mod:`runtime.voronoi.insertion` and
    :mod:`runtime.voronoi.deletion` rebuild the changed region from its sites, so a stitched
    diagram is edited as one built in one process."""
    from .conic_geometry import site_geometry
    from .construction import ConstructionState
    from .site_arrays import SiteArrays

    return ConstructionState(SiteArrays(sites, [site_geometry(s) for s in sites]), None, {})


def _record_verdict(diagram, cert, interrupted: bool, done: str) -> None:
    """Carry the certificate's verdicts onto the diagram (``certified`` only when proved)."""
    if interrupted:
        diagram.problems.append(f"interrupted (Ctrl-C): {done}, partial diagram")
    elif cert is not None:
        diagram.problems.extend(cert.problems)
        for e, ok in zip(diagram.edges, cert.edges):
            e.certified = bool(ok)
        for v, ok in zip(diagram.vertices, cert.vertices):
            v.certified = bool(ok)
        diagram.certified = bool(cert.ok) and not diagram.problems
    else:
        diagram.problems.append("not verified (certify=False)")


def _chunks(diagram, tiles, count: int) -> list[list[int]]:
    """The edges grouped by the tile whose cell holds their first finite end, the tiles (in grid
    order) merged into at most ``count`` chunks of about equal size: the spatial chunks of
    :func:`runtime.voronoi.chunked_certificate.chunked_verify` (each chunk's verifier run has a
    cost in the number of sites, so a few chunks per worker)."""
    xs = np.unique([t.box[0] for t in tiles])[1:]
    ys = np.unique([t.box[1] for t in tiles])[1:]
    cells: dict = {}
    for e in diagram.edges:
        v = diagram.vertices[e.ends[0] if e.ends[0] is not None else e.ends[1]]
        key = (int(np.searchsorted(ys, v.y, side="right")), int(np.searchsorted(xs, v.x, side="right")))
        cells.setdefault(key, []).append(e.id)
    size = -(-len(diagram.edges) // max(1, count))
    out: list = [[]]
    for k in sorted(cells):
        if len(out[-1]) >= size:
            out.append([])
        out[-1].extend(cells[k])
    return out


class _Vertexless(Exception):
    """A region the tiling does not handle: the scene is built in one process."""

    def __init__(self, key, why="an edge without vertex (sites in a row)"):
        super().__init__(why)
        self.reason = f"tile {key}: {why}"

