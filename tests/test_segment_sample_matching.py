"""Matching of the samples of two rounds by their exact coordinates
(:func:`runtime.segments.sampling.exact_matches`, what the local retriangulation of the segment
construction keeps and adds), against a plain reference: Python sets of coordinate tuples."""
import numpy as np
import pytest

import curvedvoronoi.runtime.segments.sampling as sampling
from curvedvoronoi.runtime.segments.sampling import exact_matches


def _reference(old, cur):
    cur_t = [tuple(p) for p in cur.tolist()]
    if len(set(cur_t)) != len(cur_t):
        return None
    where = {p: k for k, p in enumerate(cur_t)}
    old_t = [tuple(p) for p in old.tolist()]
    keep = np.array([p in where for p in old_t], bool)
    add = np.array([p not in set(old_t) for p in cur_t], bool)
    at = np.array([where[p] for p in old_t if p in where], np.int64)
    return keep, add, at


def _scene(rng, n_old=400, n_new=150, n_gone=120):
    old = rng.uniform(-1e4, 1e4, (n_old, 2))
    old[:5] = [[0.0, 1.5], [-0.0, 2.0], [3.0, -0.0], [1e-300, 7.0], [5.0, 5.0]]
    kept = np.delete(old, rng.choice(n_old, n_gone, replace=False), axis=0)
    new = rng.uniform(-1e4, 1e4, (n_new, 2))
    new[:3] = [[5.0, 5.0 + 2 ** -40], [np.nextafter(3.0, 4.0), 0.0], [0.0, -1.5]]   # a hair off old points
    cur = np.vstack([kept, new])
    return old, cur[rng.permutation(len(cur))]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_exact_matches_equal_the_set_reference(seed):
    old, cur = _scene(np.random.default_rng(seed))
    got, want = exact_matches(old, cur), _reference(old, cur)
    for g, w in zip(got, want):
        assert np.array_equal(g, w)
    # -0.0 and 0.0 are the same coordinate
    cur2 = cur.copy()
    cur2[cur2 == 0.0] = -0.0
    got = exact_matches(old, cur2)
    for g, w in zip(got, _reference(old, cur)):
        assert np.array_equal(g, w)


def test_a_repeated_sample_and_colliding_keys(monkeypatch):
    old, cur = _scene(np.random.default_rng(4))
    assert exact_matches(old, np.vstack([cur, cur[7:8]])) is None
    # keys that collide for distinct points (only x counts): the same answer, by the complex sort
    monkeypatch.setattr(sampling, "_exact_keys",
                        lambda P: np.ascontiguousarray(np.asarray(P, float)[:, 0] + 0.0).view(np.uint64))
    rng = np.random.default_rng(5)
    base = rng.uniform(-1e4, 1e4, (500, 2))
    base[:, 0] = np.round(base[:, 0] / 1000)          # many points share their x, none their y
    old, cur = base[:400], np.vstack([base[100:400], base[400:]])[rng.permutation(400)]
    got, want = exact_matches(old, cur), _reference(old, cur)
    for g, w in zip(got, want):
        assert np.array_equal(g, w)


def test_keys_colliding_between_the_rounds_only(monkeypatch):
    # the current samples' keys distinct, an old sample's key equal to a current one of another point
    monkeypatch.setattr(sampling, "_exact_keys",
                        lambda P: np.ascontiguousarray(np.asarray(P, float)[:, 0] + 0.0).view(np.uint64))
    rng = np.random.default_rng(6)
    cur = rng.uniform(-1e4, 1e4, (300, 2))
    old = np.vstack([cur[:200], np.column_stack([cur[200:260, 0], cur[200:260, 1] + 1.0]),
                     np.column_stack([cur[:60, 0], cur[:60, 1] + 1.0])])      # colliding with kept ones
    got, want = exact_matches(old, cur), _reference(old, cur)
    for g, w in zip(got, want):
        assert np.array_equal(g, w)
    old2 = np.vstack([cur[:200], rng.uniform(-1e4, 1e4, (5, 2))])
    cur2 = np.vstack([cur[:250], np.column_stack([old2[200:, 0], old2[200:, 1] - 2.0])])
    got, want = exact_matches(old2, cur2), _reference(old2, cur2)
    for g, w in zip(got, want):
        assert np.array_equal(g, w)
