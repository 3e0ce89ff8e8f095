"""The float coefficient tables of the batched Krawczyk test (runtime.certify.offset_batch.FloatOffsetSystem):
every stored float coefficient of o_i and of ∂o_i/∂x_j is within its stored radius of the exact
rational coefficient (checked in exact rational arithmetic), for a compact and a spread-out scene."""
from __future__ import annotations

import flint
import pytest

from curvedvoronoi.runtime.certify.offset_batch import FloatOffsetSystem
from curvedvoronoi.runtime.certify.offset_system import framed_offset_system, scene_frame
from curvedvoronoi.runtime.predicates.locator import demo_configuration


def _spread():
    from curvedvoronoi.runtime.sites.conic import Conic
    from fractions import Fraction as F
    return [Conic.ellipse(centre=(0, 0), axes=(3, 1), rotation=(1, 0)),
            Conic.ellipse(centre=(60, 7), axes=(F(5, 2), 2), rotation=(F(3, 5), F(4, 5))),
            Conic.ellipse(centre=(F(45, 2), 48), axes=(4, F(3, 2)), rotation=(F(5, 13), F(12, 13)))]


@pytest.mark.parametrize("cs", [demo_configuration()[:3], _spread()], ids=["compact", "spread"])
def test_fast_system_radii_bound_the_exact_coefficients(cs):
    sys = framed_offset_system(cs, scene_frame(cs))
    fs = FloatOffsetSystem(sys)
    exact = sys.value_gradient_columns()
    rows = {tuple(int(t) for t in e): n for n, e in enumerate(fs.exps)}
    assert set(rows) == {m for col in exact for m in col}
    checked = 0
    for q, col in enumerate(exact):
        for m, v in col.items():
            t = rows[m]
            f, r = float(fs.C[t, q]), float(fs.R[t, q])
            err = abs(flint.fmpq(*f.as_integer_ratio()) - flint.fmpq(v))
            assert err <= flint.fmpq(*r.as_integer_ratio()), (q, m)
            checked += 1
    # entries with no coefficient are exact zeros
    nz = sum(len(col) for col in exact)
    assert checked == nz and (fs.C != 0).sum() <= nz
