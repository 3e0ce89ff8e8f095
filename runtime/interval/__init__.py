"""Interval-analysis conflict locator for semi-algebraic curves (thesis chapter 6, §3.3.3, App. D).

Public API::

    from curvedvoronoi.runtime.interval import locate_conflicts_semialgebraic, locate_conflicts_interval

Modules: ``poly`` (exact polynomials, compiled Horner evaluators), ``boxes`` (interval vectors,
outward rounding), ``solver`` (branch and prune, Moore–Krawczyk, 3B), ``offsets`` (generalised
offsets of conics), ``curves`` (sites, arcs, rigorous samples), ``formulations`` (systems (a)
and (b)), ``verify`` (true-vertex and conflict decisions), ``bound`` (a proved bound on the vertices of
bounded sites), ``locator`` (the API).
"""
from .bound import VertexBound, vertex_bound
from .locator import default_domain, locate_conflicts_interval, locate_conflicts_semialgebraic, search_domain
from .solver import Solver, SolverOptions, System, krawczyk, solve

__all__ = ["locate_conflicts_semialgebraic", "locate_conflicts_interval", "default_domain", "search_domain",
           "vertex_bound", "VertexBound", "Solver",
           "SolverOptions", "System", "krawczyk", "solve"]
