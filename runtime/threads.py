"""One BLAS thread inside the library's calls, without touching the caller's environment; and
the cyclic garbage collector paused inside the constructions.

OpenBLAS with two threads made a dense eigen-decomposition 14× and the locator's null-space stage
up to 80× slower on 2-core machines (bench/results/locator.md): the numerical stages run
single-threaded.  The limit is set *inside* each public call with threadpoolctl (the numpy and
scipy OpenBLAS libraries, both loaded here first), and restored when the call returns; importing
the package changes nothing in ``os.environ`` and nothing outside these calls.

The constructions allocate millions of small objects (walks, chains, proofs) and make no reference
cycles; CPython's cyclic collector traverses them again and again (about a quarter of the circle
construction's time at 10⁴ sites, more than the rounds themselves for 10⁴ segments):
:func:`without_cyclic_gc` pauses it for the call and restores it.

Public API: :func:`one_blas_thread`, :func:`without_cyclic_gc`.
"""
from __future__ import annotations

import functools
import gc
import importlib
import os

__all__ = ["one_blas_thread", "without_cyclic_gc"]

_controller = None


def one_blas_thread(fn):
    """Decorator: run ``fn`` with every loaded BLAS library limited to one thread."""
    @functools.wraps(fn)
    def run(*args, **kw):
        global _controller
        if _controller is None:
            had = os.environ.get("KMP_DUPLICATE_LIB_OK")
            try:
                from threadpoolctl import ThreadpoolController
            except ImportError:          # without threadpoolctl the BLAS default applies
                return fn(*args, **kw)
            finally:                     # threadpoolctl's import sets it; the caller's environment stays
                if had is None:
                    os.environ.pop("KMP_DUPLICATE_LIB_OK", None)
            for name in ("numpy", "scipy.linalg"):       # their BLAS libraries, loaded before the look
                importlib.import_module(name)
            _controller = ThreadpoolController()
        with _controller.limit(limits=1, user_api="blas"):
            return fn(*args, **kw)
    return run


def without_cyclic_gc(fn):
    """Decorator: run ``fn`` with CPython's cyclic garbage collector paused (restored after)."""
    @functools.wraps(fn)
    def run(*args, **kw):
        was = gc.isenabled()
        gc.disable()
        try:
            return fn(*args, **kw)
        finally:
            if was:
                gc.enable()
    return run
