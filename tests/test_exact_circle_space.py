"""Exact route in circle-space coordinates (T = x² + y² − R, the power of the origin; thesis §5.3 with
the circle-space chart of runtime.certify.chart):

* the real solutions msolve isolates in (T, x, y), mapped back to (x, y, R), match one to one those
  it isolates on the original system o1 = o2 = o3 = 0, on a triple with vertices far outside the scene,
  and on a triple far from the origin that msolve solves translated;
* the image box of a (T, x, y) box contains the image point (exact interval arithmetic);
* a background exact solve gives the same solutions as a direct one, and a cancelled one leaves
  nothing behind.
"""
from __future__ import annotations

from fractions import Fraction as F

import numpy as np

from curvedvoronoi.runtime.predicates.locator import clear_cache
from curvedvoronoi.runtime.solve.exact import (cancel_solve_exact, exact_solved, exact_triple_system, msolve_run,
                                               parse_output, solve_exact, solve_exact_cached, start_solve_exact,
                                               system_text, world_box)


def _meet(b, c):
    return all(not (i[1] < j[0] or j[1] < i[0]) for i, j in zip(b, c))


def _assert_boxes_match_the_world_system(cs):
    """solve_exact's boxes are one to one the real solutions msolve isolates on o1 = o2 = o3 = 0 in
    (x, y, R) as given (no circle space, no translation)."""
    ref = parse_output(msolve_run(system_text(exact_triple_system(*cs)), "-p", "128"))[1][1]
    ref = [tuple((F(lo), F(hi)) for lo, hi in b) for b in ref]
    boxes = solve_exact(*cs).boxes
    assert len(boxes) == len(ref) > 0
    for b in ref:
        assert sum(_meet(b, c) for c in boxes) == 1
    for c in boxes:
        assert sum(_meet(b, c) for b in ref) == 1


def test_circle_space_boxes_match_the_weighted_system():
    """Four parabolas (random rigid configuration, seed 102) whose null-space route refuses (far
    vertices): the real solutions msolve isolates in (T, x, y), mapped to (x, y, R), are one to one
    the real solutions it isolates on the original system o1 = o2 = o3 = 0 in (x, y, R)."""
    from test_locator import random_configuration

    cs = random_configuration("PPPP", 102)[:3]
    _assert_boxes_match_the_world_system(cs)


def test_translated_solve_matches_the_world_system():
    """Sites far from the origin (two homothetic parallel ellipses and a circle near (25, 29) of a
    60 × 60 scene): msolve runs on the conics translated to an integer point near them; its boxes,
    shifted back, are one to one the real solutions msolve isolates on the untranslated world
    system o1 = o2 = o3 = 0 in (x, y, R)."""
    from curvedvoronoi.runtime.sites.conic import Conic
    from curvedvoronoi.runtime.solve.exact import scene_translation

    cs = [Conic.from_coefficients(*map(F, co)) for co in
          [(29008, 11088, 11617, -1289904, -879972, 23810663),
           (116032, 44352, 46468, -7580832, -4616076, 183084533), (1, 0, 1, -50, -58, 1465)]]
    assert scene_translation(*cs) != (0, 0)
    _assert_boxes_match_the_world_system(cs)


def test_world_box_contains_the_image():
    """(x, y, x² + y² − T) lies in world_box of any (T, x, y) box containing (T, x, y), also when
    an interval straddles 0 (the square's lower end is then 0)."""
    rng = np.random.default_rng(5)
    for _ in range(200):
        t, x, y = (F(int(v), 7) for v in rng.integers(-30, 31, 3))
        w = [F(int(v), 11) for v in rng.integers(0, 5, 6)]
        b = ((t - w[0], t + w[1]), (x - w[2], x + w[3]), (y - w[4], y + w[5]))
        bx, by, bR = world_box(b)
        assert bx[0] <= x <= bx[1] and by[0] <= y <= by[1] and bR[0] <= x * x + y * y - t <= bR[1]


def test_background_exact_solve_and_cancel():
    """A background solve (started when the numeric route begins to refuse) gives the same real
    solutions as a direct one; a cancelled one leaves nothing behind, and the next request solves."""
    from test_locator import random_configuration

    cs = random_configuration("EPCE", 5)[:3]
    ref = solve_exact(*cs).boxes
    clear_cache()
    start_solve_exact(*cs)
    boxes = solve_exact_cached(*cs).boxes
    assert exact_solved(*cs)
    assert len(boxes) == len(ref) > 0 and all(sum(_meet(b, c) for c in boxes) == 1 for b in ref)
    clear_cache()
    start_solve_exact(*cs)
    cancel_solve_exact(*cs)
    assert not exact_solved(*cs)
    assert len(solve_exact_cached(*cs).boxes) == len(ref)
    clear_cache()
