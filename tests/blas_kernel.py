"""The OpenBLAS kernel the tests run on (threadpoolctl's ``architecture``: Haswell, SkylakeX,
Sandybridge, …; chosen by OpenBLAS from the CPU, or by ``OPENBLAS_CORETYPE``).

The toric null space's eigenvalue problems (runtime/solve/toric.py) round differently with each
kernel, and on the hardest held-out clusters the numeric list is proved with some kernels while
with others it is not and the exact route (msolve) answers.  The answer must be the same either
way, and the tests assert that everywhere; which route answered is asserted only on the kernels
where it was measured (tests/test_toric.py, tests/test_nongeneric.py)."""
from __future__ import annotations

import importlib

from threadpoolctl import threadpool_info


def openblas_kernel() -> str:
    """The architecture of the first OpenBLAS loaded (numpy's and scipy's), '' when none is."""
    for module in ("numpy", "scipy.linalg"):          # load their OpenBLAS before asking
        importlib.import_module(module)

    return next((d.get("architecture") or "" for d in threadpool_info() if d.get("internal_api") == "openblas"), "")
