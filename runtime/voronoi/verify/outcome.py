"""The outcome of a certificate: what was proved of a reported diagram, part by part.

One record serves every certificate of the project -- :func:`runtime.voronoi.verify.certificate.verify`
(points and conics) and :func:`runtime.segments.certificate.verify_segments` (points, segments, circular
and elliptic arcs) -- so that a diagram's proof reads the same whatever its sites (thesis §1.2: the
diagram is proved vertex by vertex and edge by edge, then closed up).

Public API: :class:`Certificate`.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from .problems import records

__all__ = ["Certificate"]


@dataclass
class Certificate:
    """Outcome of :func:`runtime.voronoi.verify.certificate.verify` and of
    :func:`runtime.segments.certificate.verify_segments`.

    ``ok`` is True only when the whole diagram is proved (every vertex, every edge, closure and
    the accounting of components).  ``problems`` names each failing vertex / edge / site and why;
    the lines that show a fault of the diagram are :class:`runtime.voronoi.verify.problems.Problem`
    records (fields ``kind``, ``sites``, ``vertex``, ``edge``, ``fault``; ``problem_records`` in JSON).
    ``vertices`` and ``edges`` hold one flag per reported vertex / edge (diagram order).
    """

    ok: bool
    problems: list[str]
    vertices: list[bool]
    edges: list[bool]
    complete: bool
    delaunay_edges: list[tuple[int, int]]
    hypotheses: list[str] = field(default_factory=list)
    stats: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)

    def to_json(self) -> dict:
        return {"ok": bool(self.ok), "complete": bool(self.complete), "problems": [str(p) for p in self.problems],
                "problem_records": records(self.problems),
                "vertices": [bool(v) for v in self.vertices], "edges": [bool(e) for e in self.edges],
                "delaunay_edges": [list(p) for p in self.delaunay_edges],
                "hypotheses": list(self.hypotheses), "stats": self.stats,
                "timings": {k: round(v, 4) for k, v in self.timings.items()}}

    def __repr__(self) -> str:
        """One line: ``Certificate(ok=True, 27/27 vertices, 48/48 edges proved, 0 problems)``."""
        return (f"Certificate(ok={bool(self.ok)}, {sum(map(bool, self.vertices))}/{len(self.vertices)} vertices, "
                f"{sum(map(bool, self.edges))}/{len(self.edges)} edges proved, {len(self.problems)} problems)")
