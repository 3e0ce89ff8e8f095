"""One BLAS thread inside the library's calls, without touching the caller's environment.

OpenBLAS with two threads made a dense eigen-decomposition 14× and the locator's null-space stage
up to 80× slower on 2-core machines (bench/results/locator.md): the numerical stages run
single-threaded.  The limit is set *inside* each public call with threadpoolctl (the numpy and
scipy OpenBLAS libraries, both loaded here first), and restored when the call returns; importing
the package changes nothing in ``os.environ`` and nothing outside these calls.

Public API: :func:`one_blas_thread`.
"""
from __future__ import annotations

import functools
import importlib
import os

__all__ = ["one_blas_thread"]

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
