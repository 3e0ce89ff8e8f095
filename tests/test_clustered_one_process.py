"""One-process diagrams of clustered circles whose samples lie far from the centre of their box.

The sample Delaunay triangulation (runtime/voronoi/sample_delaunay.py) of more than 20 000 samples
was qhull's joggled one (``QJ``): after precision errors qhull joggles again, up to 10⁻² of the
extent, and on the samples of ``clustered_circles(20000, 31, cluster=0.1)`` (tests/scenes.py) it
returned triangles whose circumdisks hold other samples; the refinement rounds chased their 3-label
triangles for 8 rounds and the one-process diagram missed 6 065 of CGAL's 52 690 edges.  The scene
here is the 2 000-site member of that family plus one far circle, which puts the cluster 1.4·10⁴
from the centre of the samples' box (the same effect at a tenth of the size; before the fix its
construction did not finish in 500 s).

References: the empty-circumcircle definition of the Delaunay triangulation, checked with a k-d
tree of the samples (not qhull); CGAL's Apollonius graph (tests/cgal/, exact predicates)."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).with_name("cgal")))
import cgal_peer  # noqa: E402
from scenes import clustered_circles  # noqa: E402

from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry  # noqa: E402
from curvedvoronoi.runtime.voronoi.construction import voronoi  # noqa: E402
from curvedvoronoi.runtime.voronoi.sample_delaunay import SampleTriangulation  # noqa: E402
from curvedvoronoi.runtime.voronoi.sampling import initial_spacing, sample_sites  # noqa: E402
from curvedvoronoi.runtime.voronoi.site_arrays import SiteArrays  # noqa: E402
from curvedvoronoi.runtime.voronoi.site_input import as_site  # noqa: E402


def far_clustered_scene():
    """clustered_circles(2000, 31, cluster=0.1) (1 744 circles, radii 0.02 to 89) and a unit
    circle at (10⁴, 10⁴): 23 464 first-round samples."""
    return clustered_circles(2000, 31, cluster=0.1) + [(1e4, 1e4, 1.0)]


def test_sample_triangulation_is_delaunay():
    """No sample lies inside the circumcircle of a triangle (up to 10⁻⁹ of its radius); every
    sample is a corner.  qhull's joggled triangulation of these samples broke this for 15 637
    triangles."""
    sites = [as_site(c) for c in far_clustered_scene()]
    S = SiteArrays(sites, [site_geometry(s) for s in sites])
    P, lab = sample_sites(S, initial_spacing(S))
    assert len(P) > 20000                      # the perturbed route of sample_delaunay.delaunay
    T = SampleTriangulation(P, lab)
    assert len(np.unique(T.simp)) == len(P)
    A, B, C = (P[T.simp[:, k]] for k in range(3))
    area2 = (B[:, 0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (B[:, 1] - A[:, 1]) * (C[:, 0] - A[:, 0])
    assert (area2 != 0).all()
    rad = np.hypot(*(A - T.cc).T)
    near, _ = cKDTree(P).query(T.cc)
    inside = near < rad * (1 - 1e-9)
    assert not inside.any(), (int(inside.sum()), T.L[inside][:5].tolist())


def test_far_clustered_scene_equals_cgal_and_is_certified(cgal_peer_program):
    circles = far_clustered_scene()
    expected, _, hidden = cgal_peer.delaunay_edges(circles)       # the independent peer first
    assert hidden == 0
    d = voronoi(circles, certify=True, progress=False)
    assert d.certified, d.problems[:5]
    assert d.delaunay_edges() == expected
    assert d.stats["rounds"] <= 3
