"""Different shapes resting on one line (runtime/voronoi/verify/tied_tail.py): circles of several
radii and axis-aligned ellipses tangent to y = −1 tie at infinity in the direction −y, and their
parallel unbounded edges are proved.

The reference uses none of the library's geometry: distances to circles and points in closed form,
to an axis-aligned ellipse by dense sampling of its boundary; the Delaunay pairs are read from
the nearest site on a fine grid (pairs of sites nearest at adjacent grid points, with a margin),
and the directions of the unbounded edges from the nearest sites far below the scene."""
from __future__ import annotations

import copy

import numpy as np
import pytest

import curvedvoronoi as cv


def ellipse(cx, cy, a, b):
    return cv.Conic.ellipse(centre=(cx, cy), axes=(a, b))


SCENES = {
    "readme": [("c", 0, 0, 1), ("c", 4, 0, 1), ("p", 2, 4), ("e", 10, 0, 2, 1)],
    "four on a line": [("c", 0, 0, 1), ("c", 5, 1, 2), ("p", 2, 6), ("e", 12, 0, 2, 1), ("e", 20, 1, 3, 2)],
    "ellipses and a circle": [("e", 0, 0, 2, 1), ("e", 6, 0, 3, 1), ("c", 12, 0, 1), ("p", 3, 5)],
}


def to_site(t):
    return {"c": lambda x, y, r: (x, y, r), "p": lambda x, y: (x, y, 0), "e": ellipse}[t[0]](*t[1:])


def distances(scene, X, Y):
    out = []
    th = np.linspace(0, 2 * np.pi, 1500, endpoint=False)
    for t in scene:
        if t[0] == "p":
            out.append(np.hypot(X - t[1], Y - t[2]))
        elif t[0] == "c":
            out.append(np.abs(np.hypot(X - t[1], Y - t[2]) - t[3]))
        else:
            _, cx, cy, a, b = t
            bx, by = cx + a * np.cos(th), cy + b * np.sin(th)
            D = np.full(X.shape, np.inf)
            for k in range(0, len(th), 500):
                D = np.minimum(D, np.hypot(X[..., None] - bx[k:k + 500], Y[..., None] - by[k:k + 500]).min(-1))
            out.append(D)
    return np.stack(out)


def reference_pairs(scene):
    xs = np.linspace(-20, 45, 260)
    ys = np.linspace(-25, 60, 300)
    X, Y = np.meshgrid(xs, ys)
    D = distances(scene, X, Y)
    order = np.argsort(D, axis=0)
    first = order[0]
    pairs = set()
    for a, b in ((first[:, 1:], first[:, :-1]), (first[1:, :], first[:-1, :])):
        for i, j in zip(a[a != b].tolist(), b[a != b].tolist()):
            pairs.add((min(i, j), max(i, j)))
    return pairs


def far_below(scene, xs):
    """The nearest site at points far below the scene (y = −1e4): the order of the tied sites."""
    X = np.asarray(xs, float)
    return distances(scene, X, np.full(X.shape, -1e4)).argmin(0)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_shapes_resting_on_one_line_are_certified_and_match_the_reference(name):
    scene = SCENES[name]
    d = cv.voronoi([to_site(t) for t in scene])
    assert d.certified, d.problems
    ref = reference_pairs(scene)
    assert set(d.delaunay_edges()) == ref
    # unbounded edges going down: between the neighbours along y = −1, at the lateral midpoints
    down = {tuple(e.sites) for e in d.edges
            if None in e.ends and min(np.asarray(e.polyline)[[0, -1], 1]) < -50}
    xs = np.linspace(-8, 30, 800)
    owner = far_below(scene, xs)
    expect = {tuple(sorted((int(a), int(b)))) for a, b in zip(owner[:-1], owner[1:]) if a != b}
    assert down == expect


def test_a_missing_or_relabelled_tied_end_is_rejected():
    d = cv.voronoi([to_site(t) for t in SCENES["readme"]])
    doc = d.to_json()
    for change in ("drop", "relabel"):
        bad = copy.deepcopy(doc)
        k = next(t for t, e in enumerate(bad["edges"]) if e["sites"] == [1, 3])
        if change == "drop":
            del bad["edges"][k]
        else:
            bad["edges"][k]["sites"] = [0, 3]
        for t, e in enumerate(bad["edges"]):
            e["id"] = t
        bad["delaunay_edges"] = sorted({tuple(e["sites"]) for e in bad["edges"]})
        assert not cv.verify(bad).ok


def test_a_near_tie_is_not_taken_for_a_tie():
    """The ellipse lifted by 1e-9: the sites no longer tie exactly; the exact route refuses, and
    the diagram is either proved otherwise or reported not certified -- never proved as a tie."""
    scene = [("c", 0, 0, 1), ("c", 4, 0, 1), ("p", 2, 4), ("e", 10, 1e-9, 2, 1)]
    d = cv.voronoi([to_site(t) for t in scene])
    if d.certified:
        assert set(d.delaunay_edges()) == reference_pairs(scene)
