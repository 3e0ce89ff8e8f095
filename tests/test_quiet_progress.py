"""``progress=False`` silences every progress bar of a build, the verifier's included (a user who
asks for no bar gets none on stderr, whatever the size)."""
from __future__ import annotations

import numpy as np

import curvedvoronoi as cv


def test_no_bar_on_stderr_when_progress_is_false(capfd):
    rng = np.random.default_rng(4)
    pts = [tuple(p) for p in rng.uniform(0, 1000, (2500, 2))]     # > 2000 sites and edges: bars by default
    d = cv.voronoi(pts, progress=False)
    assert d.certified
    assert capfd.readouterr().err == ""
