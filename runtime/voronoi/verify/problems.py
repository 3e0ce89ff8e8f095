"""Problems of a certificate as records: what failed, where, and whether it is a fault of the
reported diagram or a limit of what the verifier proves.

A :class:`Problem` is the one-line message (a ``str``, so problem lists print and compare as
before) with fields: ``kind`` (``"vertex"``, ``"edge"``, ``"site"``, ``"infinity"``, ``"diagram"``),
``sites`` (the sites involved), ``vertex`` and ``edge`` (ids, or None) and ``fault``: True when
the reported diagram is wrong there or a finer construction may fix it (a third site closer or
too close, a missing or doubled edge, ends at infinity that do not match), False for a part the
verifier does not prove (a tail next to a hyperbola, a work limit).  The construction reads these
fields to decide what to refine; plain strings in a problem list are limits.

Public API: :class:`Problem`, :func:`fault`, :func:`records`.
"""
from __future__ import annotations

__all__ = ["Problem", "fault", "records", "faulted_sites"]


class Problem(str):
    """A problem line carrying its fields (module docstring)."""

    kind: str
    sites: tuple
    vertex: int | None
    edge: int | None
    fault: bool

    def __new__(cls, message, *, kind="diagram", sites=(), vertex=None, edge=None, fault=True):
        self = super().__new__(cls, message)
        self.kind, self.sites = kind, tuple(int(s) for s in sites)
        self.vertex = None if vertex is None else int(vertex)
        self.edge = None if edge is None else int(edge)
        self.fault = bool(fault)
        return self

    def to_json(self) -> dict:
        return {"kind": self.kind, "sites": list(self.sites), "vertex": self.vertex, "edge": self.edge,
                "fault": self.fault, "message": str(self)}


def fault(message, *, kind="diagram", sites=(), vertex=None, edge=None) -> Problem:
    """A problem that shows a fault of the reported diagram (module docstring)."""
    return Problem(message, kind=kind, sites=sites, vertex=vertex, edge=edge, fault=True)


def records(problems) -> list[dict]:
    """The problems as JSON records; a plain string is a limit of kind "diagram"."""
    return [p.to_json() if isinstance(p, Problem) else
            {"kind": "diagram", "sites": [], "vertex": None, "edge": None, "fault": False, "message": str(p)}
            for p in problems]


def faulted_sites(problems, diagram) -> set:
    """The sites of the faults among ``problems`` (:class:`Problem` with ``fault``: its sites, and
    those of the edge or vertex it names) — where a construction refines; limits of the proof
    name none."""
    out: set = set()
    for p in problems:
        if not getattr(p, "fault", False):
            continue
        out.update(t for t in p.sites if 0 <= t < len(diagram.sites))
        if p.edge is not None and 0 <= p.edge < len(diagram.edges):
            out.update(diagram.edges[p.edge].sites)
        if p.vertex is not None and 0 <= p.vertex < len(diagram.vertices):
            out.update(diagram.vertices[p.vertex].sites)
    return out
