"""``python -m runtime`` from a source checkout: the same program as ``python -m curvedvoronoi``."""
import os
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from .cli import main  # noqa: E402

sys.exit(main())
