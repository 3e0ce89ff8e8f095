"""Conflict-locator systems and Table 5.1 (thesis ch. 5, §5.3–5.4, App. C)."""
import json
import pathlib
import random

import flint
import numpy as np
import pytest

from curvedvoronoi.precompute.mixed import mixed_volume
from curvedvoronoi.precompute.newton_matrix import newton_matrix
from curvedvoronoi.precompute.offsets import canonical_offset
from curvedvoronoi.precompute.systems import (TABLE_5_1_ROWS, TRIPLES, app_c1_parabola_offset, build_all,
                                conflict_system, simplify_term, vertex_system)

GOLDEN = json.loads((pathlib.Path(__file__).parent / "golden" / "table_5_1.json").read_text())
PRIME = 4294967291


def test_app_c1_offset1_equals_canonical_parabola_offset():
    ctx, poly = canonical_offset("parabola")                  # (u, v, R, p)
    u, v, R, p = ctx.gens()
    c1 = app_c1_parabola_offset(ctx, u, v, R, p)
    # equal up to a nonzero rational factor
    ratio = None
    for k, c in c1.to_dict().items():
        d = poly.to_dict().get(k, 0)
        assert d != 0
        ratio = ratio or flint.fmpq(int(d)) / int(c)
        assert flint.fmpq(int(d)) / int(c) == ratio
    assert len(c1) == len(poly) == 23


def test_simplification_cancels_top_terms():
    s = conflict_system("EEEE")
    for i, term in ((2, (0, 0, 4, 0)), (3, (0, 0, 4, 0)), (4, (8, 0, 0, 0))):
        assert term in s.polys[1].to_dict() and term not in s.polys[i].to_dict()
    s = conflict_system("PPPP")
    for i, term in ((2, (0, 0, 3, 0)), (3, (0, 0, 3, 0)), (4, (0, 6, 0, 0))):
        assert term in s.polys[1].to_dict() and term not in s.polys[i].to_dict()
    assert simplify_term("E", "P", "r") is None
    # the combination only uses monomials of o_i and o1
    raw = conflict_system("EEEE", simplify=False)
    s = conflict_system("EEEE")
    for i in (2, 3, 4):
        allowed = set(raw.polys[i].to_dict()) | set(raw.polys[1].to_dict())
        assert set(s.polys[i].to_dict()) <= allowed


@pytest.mark.parametrize("row", GOLDEN["rows"], ids=[r["configuration"] for r in GOLDEN["rows"]])
def test_table_5_1(row):
    conf = row["configuration"]
    sup = conflict_system(conf).supports
    mvs = [mixed_volume(sup[:i] + sup[i + 1:]) for i in range(5)]
    got = {"MV_-0": mvs[0], "MV_-1": mvs[1], "MV_-2": mvs[2], "MV_-3": mvs[3], "MV_-4": mvs[4],
           "deg_R_A": sum(mvs)}
    assert got == {k: row[k] for k in got}


@pytest.mark.parametrize("triple", TRIPLES)
def test_vertex_systems(triple):
    s = vertex_system(triple)
    mv = mixed_volume(s.supports[1:])
    assert mv == GOLDEN["vertex_systems_MV"][triple]
    mat = newton_matrix(s.polys, variables=s.variables)
    assert mat.n00 == mv
    rng = random.Random(triple)
    co = [[rng.randrange(1, PRIME) for _ in a] for a in mat.supports]
    if mat.size <= 900:
        assert mat.fill_nmod(co, PRIME).rank() == mat.size


def test_four_ellipses_matrix_matches_singular():
    g = GOLDEN["newton_matrix_four_ellipses"]
    s = conflict_system("EEEE")
    mat = newton_matrix(s.polys, variables=s.variables)
    assert (mat.size, mat.n00, mat.size - mat.n00, mat.nnz) == (g["size"], g["n00"], g["n11"], g["nnz_singular"])


def test_four_parabolas_plain_matches_singular_and_is_generically_nonsingular():
    g = GOLDEN["newton_matrix_four_parabolas_plain"]
    s = conflict_system("PPPP", simplify=False)
    mat = newton_matrix(s.polys, variables=s.variables)
    assert (mat.size, mat.nnz) == (g["size"], g["nnz"])
    assert mat.n00 == 324


def test_build_all_deterministic(tmp_path):
    a = build_all(tmp_path / "a", configurations=["PPP"], n_jobs=1)
    b = build_all(tmp_path / "b", configurations=["PPP"], n_jobs=1)
    assert [p.name for p in a] == ["system_PPP.json", "system_PPP.npz"]
    for pa, pb in zip(a, b):
        assert pa.read_bytes() == pb.read_bytes()
    header = json.loads(a[0].read_text())
    with np.load(a[1], allow_pickle=False) as z:
        assert len(z["rows"]) == header["nnz"] and len(z["points"]) == header["size"]
        assert int((z["row_poly"] == 0).sum()) == header["n00"] == 108
        assert header["variables"] == ["x", "y", "r"]
        assert z["points"].tolist() == header["column_monomials"]
