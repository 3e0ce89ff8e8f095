"""The adjacency state kept between local updates (runtime.voronoi.adjacency.DynamicState): its
bounding discs and its two spatial searches after a long random chain of additions and removals
(both numberings), against brute force over the current sites.

The state keeps spare rows in its arrays and a k-d tree that is rebuilt only now and then (sites
added since are scanned apart, removed ones are marked in the tree's slots), so that an update
costs what changes; these tests check that this bookkeeping never loses or misnames a site:
``near(X, r)`` must contain every site whose centre lies within r of X (it may hold more), and
``nearest(X, k)`` must be k sites at the k smallest centre distances.
"""
from __future__ import annotations

import random

import numpy as np

from curvedvoronoi.runtime.voronoi.adjacency import DynamicState
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.site_input import as_site

import curvedvoronoi as cv


def _disc(rng):
    return (rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(0.1, 2.0))


def test_bounding_discs_and_searches_follow_a_random_chain_of_updates():
    rng = random.Random(7)
    start = [(-10.0, 0.0, 1.0), (10.0, 0.0, 1.0), (0.0, 12.0, 1.0), (0.0, -12.0, 1.5), (25.0, 25.0, 0.5)]
    d = cv.voronoi(start, certify=False)
    dyn = DynamicState(d)
    cur = [(x, y, r) for x, y, r in start]            # the expected discs, in the state's numbering
    for step in range(1500):
        if rng.random() < 0.6 or len(cur) < 6:
            c = _disc(rng)
            s = as_site(c)
            dyn.add_site(s, site_geometry(s))
            cur.append(c)
        else:
            i = rng.randrange(len(cur))
            mode = rng.choice(["last", "shift"])
            dyn.remove_site(i, mode)
            if mode == "last":
                cur[i] = cur[-1]
                cur.pop()
            else:
                cur.pop(i)
        if step % 50 == 0 or step > 1450:
            want = np.array(cur, float)
            assert len(dyn.C) == len(cur) and len(dyn.geoms) == len(cur) and len(dyn.site_v) == len(cur)
            assert np.allclose(dyn.C, want[:, :2], rtol=0, atol=1e-12)
            assert np.allclose(dyn.R, want[:, 2], rtol=0, atol=1e-12)
            assert [(g.cx, g.cy) for g in dyn.geoms] == [(x, y) for x, y, _ in cur]
            assert dyn.scale >= float(np.abs(want[:, :2]).max() + want[:, 2].max() + 1.0)
            X = np.array([rng.uniform(-60, 60), rng.uniform(-60, 60)])
            dist = np.hypot(*(want[:, :2] - X).T)
            r = float(np.sort(dist)[min(7, len(dist) - 1)])       # a radius with a site on its circle
            assert set(np.nonzero(dist <= r)[0].tolist()) <= set(dyn.near(X, r))
            k = min(9, len(cur))
            got = dyn.nearest(X, k)
            assert len(got) == k == len(set(got))
            assert np.allclose(np.sort(dist[got]), np.sort(dist)[:k], rtol=1e-12, atol=0)


def test_site_list_views_equal_the_lists_they_stand_for():
    from curvedvoronoi.runtime.voronoi.insertion import SiteList

    base = list("abcdefg")
    for i in range(len(base)):
        want = base[:i] + [base[-1]] + base[i + 1:-1] if i < len(base) - 1 else base[:-1]
        v = SiteList(list(base), swap=i)
        assert len(v) == len(want) and list(v) == want and [v[k] for k in range(-len(want), 0)] == want
        assert v.realize(False) == want
        b = list(base)
        assert SiteList(b, swap=i).realize(True) is b and b == want
    v = SiteList(base, append="z")
    assert list(v) == base + ["z"] and v[-1] == "z" and len(v) == 8
    assert v.realize(False) == base + ["z"] and base == list("abcdefg")
