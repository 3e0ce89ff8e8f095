"""``python -m curvedvoronoi``: the same program as the ``curvedvoronoi`` script."""
import sys

from .runtime.cli import main

sys.exit(main())
