"""Type configurations of a conic triple: solver degrees and generic counts (thesis §5.3, Table 5.1).

The offsets of three conics form a square system in (x, y, R) whose support depends only on the
families of the conics (circle, ellipse or hyperbola, parabola: the *type configuration* of
Table 5.1).  For each configuration this module keeps the Macaulay degree and degree-gap hint of
the null-space solver (:mod:`runtime.solve.macaulay`) and the generic number of complex solutions,
and decides before any solve whether a member is visibly non-generic (two sites of one shape and
orientation) by counting its solutions modulo a prime (msolve, :mod:`runtime.solve.exact`).

Public API: :data:`SOLVER_TABLE`, :data:`CONFIG_TABLE`, :func:`config_entry`,
:func:`shared_shape`, :func:`modular_count`.
"""
from __future__ import annotations

from collections.abc import Mapping

from ..algebra.polyalg import FAMILY_WEIGHTED_DEGREE
from ..result import LocatorError

__all__ = ["SOLVER_TABLE", "CONFIG_TABLE", "ConfigTable", "config_entry", "shared_shape", "modular_count"]

#: (sorted family triple) -> (Macaulay degree, degree-gap hint) of the null-space solver (tuning
#: measured on the validation triples and random rigid configurations; hyperbolas use the ellipse
#: family; three circles go to the exact locator)
SOLVER_TABLE: dict[tuple[str, str, str], tuple[int, int]] = {
    ("ellipse", "ellipse", "ellipse"): (19, 15),
    ("ellipse", "ellipse", "parabola"): (18, 14),
    ("ellipse", "parabola", "parabola"): (17, 13),
    ("parabola", "parabola", "parabola"): (17, 13),
    ("circle", "ellipse", "ellipse"): (15, 11),
    ("circle", "ellipse", "parabola"): (14, 10),
    ("circle", "parabola", "parabola"): (12, 9),
    ("circle", "circle", "ellipse"): (11, 7),
    ("circle", "circle", "parabola"): (10, 6),
    ("circle", "circle", "circle"): (7, 3),
}


class ConfigTable(Mapping):
    """(sorted family triple) -> (Macaulay degree, generic count, degree-gap hint).  The generic
    counts are *not* measured by the solver: they come from the verified artefact
    ``generated/counts/root_counts.json`` (exact parametrisation degrees computed by msolve in the
    precompute, :func:`runtime.artefacts.load_root_counts`), read on first use."""

    def _counts(self):
        from ..artefacts import load_root_counts
        return load_root_counts()

    def __getitem__(self, fams):
        d, hint = SOLVER_TABLE[fams]
        return d, self._counts()[fams], hint

    def __iter__(self):
        return iter(SOLVER_TABLE)

    def __len__(self):
        return len(SOLVER_TABLE)


CONFIG_TABLE = ConfigTable()


def config_entry(fams: tuple[str, ...]) -> tuple[int, int | None, int]:
    """(Macaulay degree, generic count or None, degree-gap hint) for a sorted family triple; a
    triple outside the table gets the degree d1 + d2 + d3 − 5 of its weighted offset degrees and
    no generic count (completeness is then not claimed)."""
    if fams in CONFIG_TABLE:
        return CONFIG_TABLE[fams]
    degs = sorted((FAMILY_WEIGHTED_DEGREE[f] for f in fams), reverse=True)
    d = degs[0] + degs[1] + degs[2] - 5
    return d, None, d - 4


def shared_shape(conics) -> bool:
    """Do two of the non-circle conics have proportional quadratic parts (exactly): the same shape
    and orientation up to scale (ellipses, hyperbolas) or parallel axes (parabolas)?  Such a
    triple is usually a non-generic member of its type configuration (fewer complex solutions than
    the generic count of Table 5.1)."""
    quads = [c.coefficients[:3] for c in conics if c.kind != "circle"]
    for i in range(len(quads)):
        for j in range(i):
            (a1, b1, c1), (a2, b2, c2) = quads[i], quads[j]
            if a1 * b2 == a2 * b1 and a1 * c2 == a2 * c1 and b1 * c2 == b2 * c1:
                return True
    return False


def modular_count(c1, c2, c3) -> int | None:
    """Number of complex solutions of the exact triple system modulo a prime (msolve), None if
    msolve fails or the system is positive-dimensional there (the exact route then decides).  A
    count other than the generic count marks the member as non-generic (the caller then sends it
    to the exact route), which the numeric null space cannot tell from solutions lost at infinity."""
    from .exact import MODULAR_PRIMES, exact_triple_system, parametrisation_degree

    try:
        return parametrisation_degree(exact_triple_system(c1, c2, c3), MODULAR_PRIMES[0], timeout=30)
    except LocatorError:
        return None
