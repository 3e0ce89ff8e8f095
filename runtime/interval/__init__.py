"""Interval-analysis conflict locator for semi-algebraic curves (thesis chapter 6, §3.3.3, App. D).

Public API::

    from curvedvoronoi.runtime.interval import locate_conflicts_semialgebraic, locate_conflicts_interval

Modules: ``poly`` (exact polynomials, compiled Horner evaluators), ``boxes`` (interval vectors,
outward rounding), ``solver`` (branch and prune, Moore–Krawczyk, 3B), ``offsets`` (generalised
offsets of conics), ``curves`` (sites, arcs, rigorous samples), ``formulations`` (systems (a)
and (b)), ``verify`` (true-vertex and conflict decisions), ``locator`` (the API).
"""
from .locator import default_domain, locate_conflicts_interval, locate_conflicts_semialgebraic
from .solver import Solver, SolverOptions, System, krawczyk, solve

__all__ = ["locate_conflicts_semialgebraic", "locate_conflicts_interval", "default_domain", "Solver",
           "SolverOptions", "System", "krawczyk", "solve"]
