"""Optional dependencies: one clear line naming the package and the extra to install.

The default install (``pip install curvedvoronoi``) has everything the documented commands use,
``--png`` pictures included.  A few features need an extra:

====================  ==========  ============================================
package               extra       used by
====================  ==========  ============================================
shapely               ``geo``     ``Diagram.to_shapely`` (edges as LineStrings)
dask.distributed      ``dask``    ``runtime.predicates.batch`` with ``backend="dask"``
pdoc                  ``docs``    ``invoke docs`` (the API reference)
invoke                ``dev``     ``tasks.py``
====================  ==========  ============================================
"""
from __future__ import annotations

from importlib import import_module

__all__ = ["EXTRAS", "MissingDependencyError", "missing_message", "require"]

#: top-level module name -> extra of ``curvedvoronoi`` that installs it (None: a core dependency)
EXTRAS = {"shapely": "geo", "dask": "dask", "distributed": "dask", "pdoc": "docs", "invoke": "dev",
          "matplotlib": None, "jsonschema": None, "tqdm": None, "networkx": None, "mpmath": None,
          "scipy": None, "numpy": None, "flint": None, "sympy": None, "joblib": None,
          "pytest": "test", "hypothesis": "test"}

_PIP_NAME = {"flint": "python-flint", "distributed": "dask[distributed]"}


class MissingDependencyError(ImportError):
    """An optional (or, in a broken install, required) package is not installed."""


def missing_message(module: str, purpose: str | None = None) -> str:
    """``"--png needs matplotlib, which is not installed: pip install matplotlib"`` and the like."""
    top = module.split(".")[0]
    what = f"{purpose} needs {top}" if purpose else f"the package {top} is needed here"
    if top in EXTRAS and EXTRAS[top] is not None:
        return f"{what}, which is not installed: pip install 'curvedvoronoi[{EXTRAS[top]}]'"
    if top in EXTRAS:
        return (f"{what}, a dependency of curvedvoronoi that is not installed (broken install?): "
                f"pip install {_PIP_NAME.get(top, top)}")
    return f"{what}, which is not installed: pip install {top}"


def require(module: str, purpose: str | None = None):
    """Import ``module`` or raise :class:`MissingDependencyError` with :func:`missing_message`."""
    try:
        return import_module(module)
    except ImportError:
        raise MissingDependencyError(missing_message(module, purpose)) from None
