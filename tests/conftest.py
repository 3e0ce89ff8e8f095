"""Test-session settings: one BLAS thread (OpenBLAS with 2 threads was 14x slower on a dense
eig on the 2-core CI machines), and a fixed hypothesis profile so CI time is predictable."""
from __future__ import annotations

import os

from hypothesis import HealthCheck, settings
from threadpoolctl import threadpool_limits

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
_limits = threadpool_limits(limits=1)

settings.register_profile("ci", deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True)
settings.load_profile("ci")
