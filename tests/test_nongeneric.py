"""The conic conflict locator on non-generic configurations (thesis §5.2–§5.3; exact fallback).

Configurations people draw -- identical translated ellipses, axis-aligned ellipses, parallel and
opposite parabola axes, a shared symmetry axis, collinear centres, small sites far apart (size /
scene = 1/100) -- come from bench/bench_nongeneric.py's generator.  Each answer must be
certified *and* complete, and its vertices must equal those of the independent oracle
tests/reference.py (grid seeding + mpmath Newton on distances, no offsets, no msolve).
"""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_nongeneric import cases  # noqa: E402
from reference import reference_vertices  # noqa: E402

CASES = {k: v for k, v in cases().items() if v is not None and not k.startswith("spread-out")}
#: kinds whose systems have fewer finite solutions than the generic count (measured with msolve)
EXACT_KINDS = {"identical translated ellipses", "parallel parabola axes", "opposite parabola axes",
               "shared symmetry axis (C, E, P)"}


@pytest.mark.parametrize("kind", list(CASES))
def test_nongeneric_certified_complete_and_equal_to_reference(kind):
    cs = CASES[kind]
    clear_cache()
    res = locate_conflicts(*cs)
    assert res.complete, res.notes
    assert res.certified
    ref = reference_vertices(*cs[:3])
    assert len(ref) == len(res.vertices)
    for x, y, r in ref:
        hit = [v for v in res.vertices
               if abs(v.x - float(x)) <= 1e-8 * (1 + abs(float(x))) and abs(v.y - float(y)) <= 1e-8 * (1 + abs(float(y)))]
        assert len(hit) == 1
        assert abs(hit[0].radius - float(r)) <= 1e-8 * (1 + float(r))
    # the completeness claim rests on a proof named in the notes (counting or exact); the kinds with
    # fewer finite solutions than the generic count must have gone through the exact route
    assert any(n.startswith("certify completeness:") and ("generic count" in n or "exact:" in n)
               for n in res.notes)
    if kind in EXACT_KINDS:
        assert any(n.startswith("certify completeness: exact:") for n in res.notes), res.notes
