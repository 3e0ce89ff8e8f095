"""Two steps of the completeness proof of runtime.certify.complete at their boundaries.

* Reality of the unique zero in a Krawczyk box (step 3, runtime.certify.solution_boxes.box_kind):
  a box tested as complex is called non-real only when some coordinate's imaginary part excludes
  0; a box whose imaginary parts all contain 0 (by as little as 10⁻⁹) decides nothing.
* Counting (step 4): N distinct simple zeros are all the isolated zeros only when N equals the
  proved bound; for three ellipses the circle-space mixed volume is 184 (Li–Wang; the generic
  count of msolve's parametrisation, generated/counts/root_counts.json), so 184 closes the
  count and 183 or 185 does not.
"""
from __future__ import annotations

import pytest
from flint import acb, arb

from curvedvoronoi.runtime.certify import complete
from curvedvoronoi.runtime.certify.solution_boxes import box_kind
from curvedvoronoi.runtime.predicates.locator import demo_configuration


def _box(im_lo, second_im=0.0):
    """Three complex balls; the imaginary parts: [-1e-3, 1e-3], second_im ± 1e-3 and
    [im_lo, im_lo + 2e-3] (a ball's radius is rounded up by < 10⁻¹² here, far below the 10⁻⁹ steps)."""
    return [acb(arb(1, 1e-3), arb(0, 1e-3)), acb(arb(2, 1e-3), arb(second_im, 1e-3)),
            acb(arb(3, 1e-3), arb(im_lo + 1e-3, 1e-3))]


@pytest.mark.parametrize("im_lo,kind", [(1e-9, "nonreal"), (-1e-9, None), (0.0, None), (-2e-3 - 1e-9, "nonreal"),
                                        (-2e-3 + 1e-9, None)])
def test_a_complex_box_is_non_real_only_if_some_imaginary_part_excludes_zero(im_lo, kind):
    K = _box(im_lo)
    got, K2 = box_kind(K, real=False)
    assert got == kind
    assert K2 is K
    assert box_kind(_box(im_lo, second_im=0.5), real=False)[0] == "nonreal"     # another coordinate decides


def test_a_box_tested_as_real_keeps_its_real_parts():
    K = _box(1e-9)
    got, K2 = box_kind(K, real=True)
    assert got == "real"
    assert all(isinstance(k, arb) and k.mid() == K[i].real.mid() and k.rad() == K[i].real.rad()
               for i, k in enumerate(K2))


@pytest.mark.parametrize("n,ok", [(183, False), (184, True), (185, False)])
def test_counting_closes_only_at_the_proved_bound(n, ok):
    c1, c2, c3, _ = demo_configuration()
    closes, note = complete._count_closes(c1, c2, c3, n)
    assert closes is ok, note
    if not ok:
        assert "no proved bound equal to it" in note
