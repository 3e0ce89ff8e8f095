import os
import sys

# One BLAS thread unless the user says otherwise: on 2-core machines OpenBLAS with two threads
# made the null-space stage ~80x slower (0.06 s -> 5 s, bench/results/locator.md).  Must be set
# before numpy/scipy are imported.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from .cli import main  # noqa: E402

sys.exit(main())
