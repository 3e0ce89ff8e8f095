"""The vectorised degree check of the segment construction's rounds
(:func:`runtime.segments.walk_checks.degree_mismatches`) against a plain reference: a vertex
passes exactly when the multiset of the pairs of its walks equals the set of pairs of its
cyclically consecutive sites."""
from __future__ import annotations

import random
from collections import Counter

import numpy as np

from curvedvoronoi.runtime.segments.walk_checks import degree_mismatches


def _reference(want, ends):
    have: dict = {}
    for v, k in ends:
        have.setdefault(v, Counter())[k] += 1
    return [v for v, w in enumerate(want) if have.get(v, Counter()) != Counter(w)]


def test_degree_mismatches_equal_the_multiset_reference():
    rng = random.Random(11)
    for _ in range(200):
        nv = rng.randint(1, 12)
        want = [tuple(sorted(rng.sample(range(40), rng.choice([3, 3, 3, 4])))) for _ in range(nv)]
        ends = [(v, k) for v, w in enumerate(want) for k in w]
        for _ in range(rng.randint(0, 3)):          # wrong pairs, missing or doubled ends
            j = rng.randrange(len(ends)) if ends else None
            what = rng.choice(["swap", "drop", "double"])
            if j is None:
                break
            if what == "swap":
                ends[j] = (ends[j][0], rng.randrange(40))
            elif what == "drop":
                ends.pop(j)
            else:
                ends.append(ends[j])
        rng.shuffle(ends)
        hv = np.array([v for v, _ in ends], np.int64)
        hk = np.array([k for _, k in ends], np.int64)
        assert degree_mismatches(want, hv, hk, nv).tolist() == _reference(want, ends)


def test_same_count_other_pairs_is_a_mismatch():
    want = [(1, 2, 3), (4, 5, 6)]
    hv = np.array([0, 0, 0, 1, 1, 1])
    hk = np.array([1, 2, 2, 4, 5, 6])               # vertex 0: pair 3 missing, pair 2 twice
    assert degree_mismatches(want, hv, hk, 2).tolist() == [0]
