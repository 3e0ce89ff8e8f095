"""The Delaunay triangulation strip by strip (runtime/voronoi/strip_delaunay.py) against the exact
check of runtime/voronoi/exact_delaunay.py (rational predicates: every triangle counter-clockwise,
Delaunay's lemma on every side, the hull tiled) and against scipy's qhull on all points at once:
random points, points whose hull slivers span many strips (the repair of missed triangles),
the samples of disjoint circles as the construction perturbs them, and inputs it must refuse."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import Delaunay

import scenes
from curvedvoronoi.runtime.voronoi import strip_delaunay as SD
from curvedvoronoi.runtime.voronoi.construction import as_site, site_geometry
from curvedvoronoi.runtime.voronoi.exact_delaunay import is_delaunay
from curvedvoronoi.runtime.voronoi.sample_delaunay import perturbed
from curvedvoronoi.runtime.voronoi.sampling import initial_spacing, sample_sites
from curvedvoronoi.runtime.voronoi.site_arrays import SiteArrays


def ccw(Q, simp, nb):
    """The triangles turned counter-clockwise (is_delaunay's layout), neighbours with them."""
    a, b, c = (Q[simp[:, k]] for k in range(3))
    cw = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]) < 0
    simp, nb = simp.copy(), nb.copy()
    simp[cw] = simp[cw][:, [0, 2, 1]]
    nb[cw] = nb[cw][:, [0, 2, 1]]
    return simp, nb


def triangles(simp):
    return {tuple(t) for t in np.sort(simp, axis=1).tolist()}


def test_random_points_exact_and_equal_to_qhull():
    Q = np.random.default_rng(5).uniform(-1, 1, (6000, 2))
    out = SD.strip_delaunay(Q, np.arange(len(Q)), 700)
    assert out is not None
    simp, nb = out
    assert simp.dtype == np.int32 and nb.dtype == np.int32
    assert is_delaunay(Q, *ccw(Q, simp, nb))
    assert triangles(simp) == triangles(Delaunay(Q).simplices)


def test_hull_slivers_across_strips_are_repaired(monkeypatch):
    # a shallow arc of a circle of radius 50 over x in [-1, 1] on top, random points below: the
    # triangles under the arc have circumdisks of radius up to ~50, whose corners lie in strips
    # far from the one owning the circumcentre
    rng = np.random.default_rng(7)
    x = np.sort(rng.uniform(-1, 1, 1500))
    top = np.column_stack([x, np.sqrt(50.0 ** 2 - x ** 2) - 50.0])
    low = np.column_stack([rng.uniform(-1, 1, 3000), rng.uniform(-0.5, -0.03, 3000)])
    Q = np.vstack([top, low])
    calls = []
    real = SD.Delaunay

    def counted(P, **kw):
        calls.append(len(P))
        return real(P, **kw)

    monkeypatch.setattr(SD, "Delaunay", counted)
    out = SD.strip_delaunay(Q, np.arange(len(Q)), 500)
    assert out is not None
    k = len(Q) // 500
    assert len(calls) == k + 1                  # the strips, then the repair of missed triangles
    assert is_delaunay(Q, *ccw(Q, *out))
    assert triangles(out[0]) == triangles(real(Q).simplices)


@pytest.mark.parametrize("seed, strip", [(1, 600), (2, 600), (3, 600)])
def test_circle_samples_as_the_construction_perturbs_them(seed, strip):
    sites = [as_site(s) for s in scenes.random_disjoint_circles(300, seed)]
    S = SiteArrays(sites, [site_geometry(s) for s in sites])
    P, lab = sample_sites(S, initial_spacing(S))
    Q = perturbed(P - (P.min(axis=0) + P.max(axis=0)) / 2)
    out = SD.strip_delaunay(Q, lab, strip)
    assert out is not None
    whole = Delaunay(Q, qhull_options="Qbb Qc Qz Q12").simplices

    def labelled(simp):         # triangles with two or three sites: what the walks and vertices read
        L = lab[simp]
        return triangles(simp[(L[:, 0] != L[:, 1]) | (L[:, 1] != L[:, 2])])
    assert labelled(out[0]) == labelled(whole)
    assert len(out[0]) == len(whole)            # Euler: the same count, 2n − 2 − hull


def test_refusals():
    rng = np.random.default_rng(3)
    Q = rng.uniform(-1, 1, (3000, 2))
    assert SD.strip_delaunay(Q, np.arange(len(Q)), 2000) is None    # fewer than two strips: qhull on all
    Q[1500] = Q[10]                              # a repeated point: qhull leaves it out
    assert SD.strip_delaunay(Q, np.arange(len(Q)), 500) is None
