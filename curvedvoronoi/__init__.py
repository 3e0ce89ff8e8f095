"""curvedvoronoi: certified proximity computations on curved sites.

After F. Anton, *Voronoi diagrams of semi-algebraic sets*, PhD thesis, University of British
Columbia, 2003.  One import name re-exports the public API::

    import curvedvoronoi as cv
    cv.Conic, cv.Circle, cv.Point          # sites
    cv.locate_conflicts(c1, c2, c3, c4)    # the Delaunay-graph conflict locator (thesis §1.2, ch. 5)
    cv.voronoi(sites)                      # the Voronoi diagram of many sites (thesis §1.2)
    cv.load_offset("ellipse")              # generalised offsets (thesis ch. 4, App. B)

The three halves of the source tree are sub-packages: ``curvedvoronoi.precompute`` (offline,
exact), ``curvedvoronoi.generated`` (hashed data artefacts) and ``curvedvoronoi.runtime``
(online, certified).  In the repository they are the top-level folders ``precompute/``,
``generated/`` and ``runtime/``; setuptools' ``package-dir`` maps them under this package at
install time, so that an installed copy owns a single top-level name.
"""
from __future__ import annotations

import os
from pathlib import Path

# One BLAS thread unless the user says otherwise: on 2-core machines OpenBLAS with two threads made
# the null-space stage ~80x slower (bench/results/locator.md).  Set before numpy is imported.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

# In a source checkout runtime/, precompute/ and generated/ sit beside this folder: let the
# package find them there (an installed copy has them inside, see pyproject.toml).
_here = Path(__file__).resolve().parent
if not (_here / "runtime").is_dir() and (_here.parent / "runtime" / "__init__.py").is_file():
    __path__.append(str(_here.parent))  # type: ignore[name-defined]  # noqa: F821

__version__ = "0.2.0"

_LAZY = {
    "Conic": ("runtime.conic", "Conic"),
    "Circle": ("runtime.circles", "Circle"),
    "Point": ("runtime.circles", "Point"),
    "voronoi": ("runtime.voronoi.construction", "voronoi"),
    "Diagram": ("runtime.voronoi.structure", "Diagram"),
    "verify": ("runtime.voronoi.verify", "verify"),
    "offset": ("runtime.algebraic_offset", "offset"),
    "locate_conflicts": ("runtime.locator", "locate_conflicts"),
    "voronoi_vertices": ("runtime.locator", "voronoi_vertices"),
    "LocatorResult": ("runtime.result", "LocatorResult"),
    "VoronoiVertex": ("runtime.result", "VoronoiVertex"),
    "LocatorError": ("runtime.result", "LocatorError"),
    "InvalidConicError": ("runtime.result", "InvalidConicError"),
    "load_offset": ("runtime.artefacts", "load_offset"),
    "ArtefactError": ("runtime.artefacts", "ArtefactError"),
}

__all__ = sorted(["__version__", *_LAZY])


def __getattr__(name: str):
    """Import the public names lazily, so that ``curvedvoronoi --help`` stays fast."""
    try:
        module, attr = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module 'curvedvoronoi' has no attribute {name!r}") from None
    from importlib import import_module
    value = getattr(import_module(f"{__name__}.{module}"), attr)
    globals()[name] = value
    return value


def __dir__():
    return __all__
