"""Validation of the independent reference oracle (tests/reference.py) on the public cases.

The oracle must reproduce, for each case, the number of true Voronoi vertices of (C1, C2, C3)
(thesis §5.2, Def. 5.2.1), their coordinates, radii and distances to C4 to 1e-9 relative
(it reaches ~1e-30), and the conflict / tangent flags (thesis Thm 5.2.2).

The default test runs a subset of 8 cases covering every group (~30 s on one core).  All 30
cases pass (about 85 s on one core) with::

    OPENBLAS_NUM_THREADS=1 python tests/test_reference.py --all

The oracle reads only the exact canonical constructions of the conics, not the runtime code.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

if __name__ == "__main__":  # script mode: make the repo root and tests/ importable
    sys.path[:0] = [str(Path(__file__).resolve().parent.parent), str(Path(__file__).resolve().parent)]

import mpmath
import pytest

from curvedvoronoi.runtime.validation import required_cases_path, load_cases
from reference import reference_locate, ref_distance, RefConic

CASES_PATH = required_cases_path()   # a missing file fails loudly, never skips
SUBSET = [
    "ellipses_a_ellipse4_conflict",    # 7 vertices
    "circles_b_circle4_conflict",
    "parabolas_b_parabola4_conflict",
    "hyperbolas_a_hyperbola4_conflict",
    "mixed_CEP_circle4_noconflict",
    "mixed_ECP_nested_no_vertex",      # no vertex at all
    "exact_EPC_circle4_tangent",       # margin exactly 0
    "parabolas_a_near_ellipse_-1e-7",  # margin -1e-7
]


def _cases():
    return load_cases(CASES_PATH)


def check_case(case, rel=1e-9):
    specs = [dict(c) for c in case.canonical]
    got = reference_locate(*specs)
    assert len(got) == len(case.vertices), (case.name, len(got), len(case.vertices))
    with mpmath.workdps(50):
        for g, e in zip(got, case.vertices):
            for key in ("x", "y", "radius", "distance_to_fourth"):
                want = getattr(e, key)
                want = mpmath.mpf(want.numerator) / want.denominator
                assert abs(g[key] - want) <= rel * (1 + abs(want)), (case.name, key, g[key], want)
            assert g["in_conflict"] == e.in_conflict and g["tangent"] == e.tangent, case.name
            if not e.tangent:
                assert mpmath.sign(g["margin"]) == mpmath.sign(mpmath.mpf(e.margin.numerator) / e.margin.denominator)
    assert any(v["in_conflict"] for v in got) == case.conflict
    return got


@pytest.mark.parametrize("name", SUBSET)
def test_reference_reproduces_validation_case(name):
    case = next(c for c in _cases() if c.name == name)
    check_case(case)


def test_reference_distance_simple_closed_forms():
    # ellipse x²/4 + y² = 1: from the centre d = 1; from (3/2, 0) (evolute cusp) d = 1/2
    e = RefConic({"type": "ellipse", "cos": 1, "sin": 0, "tx": 0, "ty": 0, "A2": 4, "B2": 1})
    with mpmath.workdps(45):
        assert abs(ref_distance(e, 0, 0) - 1) < mpmath.mpf(10) ** -35
        assert abs(ref_distance(e, "3/2", 0) - mpmath.mpf(1) / 2) < mpmath.mpf(10) ** -35
        # parabola y² = 2x, q = (5/2, 0): d = 2 ; hyperbola x² − y² = 1 from the origin: 1
        p = RefConic({"type": "parabola", "cos": "3/5", "sin": "4/5", "tx": 1, "ty": 2, "p": 1})
        assert abs(ref_distance(p, 1 + mpmath.mpf(3) / 2, 2 + 2) - 2) < mpmath.mpf(10) ** -35
        h = RefConic({"type": "hyperbola", "cos": 1, "sin": 0, "tx": 0, "ty": 0, "A2": 1, "B2": 1})
        assert abs(ref_distance(h, 0, 0) - 1) < mpmath.mpf(10) ** -35
        # from (0, y0): d² = min_X (X² − 1 + (√(X² − 1)... ) -> feet at Y = y0/2: d² = 1 + y0²/2
        assert abs(ref_distance(h, 0, 10) - mpmath.sqrt(51)) < mpmath.mpf(10) ** -35


if __name__ == "__main__":  # full validation of the oracle on every case
    cases = _cases()
    names = None if "--all" in sys.argv else SUBSET
    t_all = time.time()
    for case in cases:
        if names is not None and case.name not in names:
            continue
        t = time.time()
        check_case(case)
        print(f"{case.name:40s} {len(case.vertices):3d} vertices  ok  {time.time() - t:6.1f} s", flush=True)
    print(f"total {time.time() - t_all:.1f} s")
