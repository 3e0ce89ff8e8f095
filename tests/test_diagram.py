"""Tests of the incremental Delaunay graph / Voronoi diagram (thesis §1.2, Prop. 1.2.1).

Independent reference: nearest-site labelling of a fine grid by point-to-site distances
(closed form for circles; for conics the sampling + Newton distance of tests/reference.py,
which shares no code with the runtime).  Two labels adjacent on the grid must be a Delaunay
edge; a Delaunay edge missing from the grid must be explained by the grid's limits (all its
Voronoi vertices outside the window, or an edge shorter than a few grid steps).
"""
from __future__ import annotations

import json
import math
import random

import numpy as np
import pytest

from curvedvoronoi.runtime.circles import Circle, locate_conflicts_circles
from curvedvoronoi.runtime.diagram import DelaunayGraph, as_site, conic_locator_available, run_diagram
from curvedvoronoi.runtime.result import LocatorError

AGREEMENT: dict[str, list[int]] = {}


def random_circles(seed: int, m: int):
    rnd = random.Random(seed)
    out = set()
    while len(out) < m:
        out.add((rnd.randint(0, 1000) / 10, rnd.randint(0, 1000) / 10, rnd.randint(10, 200) / 10))
    return sorted(out)


def grid_edges(dist_fns, box, n: int = 700):
    """Pairs of labels adjacent on an n x n grid labelled by the nearest site."""
    x0, x1, y0, y1 = box
    xs, ys = np.linspace(x0, x1, n), np.linspace(y0, y1, n)
    X, Y = np.meshgrid(xs, ys)
    D = np.stack([f(X, Y) for f in dist_fns])
    L = D.argmin(0)
    pairs = set()
    for A, B in ((L[:, :-1], L[:, 1:]), (L[:-1, :], L[1:, :])):
        m = A != B
        for a, b in set(zip(A[m].tolist(), B[m].tolist())):
            pairs.add((min(a, b), max(a, b)))
    return pairs, max(xs[1] - xs[0], ys[1] - ys[0])


def check_against_grid(G, dist_fns, box, n=700, label="circles"):
    R, h = grid_edges(dist_fns, box, n)
    E = G.edges()
    assert R <= E, f"grid adjacencies missing from the Delaunay graph: {sorted(R - E)}"
    x0, x1, y0, y1 = box
    for p in E - R:
        vs = [v for v in G.vertices if p[0] in v.sites and p[1] in v.sites]
        outside = vs and all(not (x0 + 2 * h < v.x < x1 - 2 * h and y0 + 2 * h < v.y < y1 - 2 * h) for v in vs)
        short = any(math.hypot(a.x - b.x, a.y - b.y) < 4 * h for a in vs for b in vs if a is not b)
        assert outside or short, f"Delaunay edge {p} not seen on the grid (vertices {vs})"
    AGREEMENT.setdefault(label, [0, 0])
    AGREEMENT[label][0] += E == R
    AGREEMENT[label][1] += 1
    return E == R


def circle_box(cs, pad=1.0):
    C = np.array(cs, float)
    x0, x1 = (C[:, 0] - C[:, 2]).min(), (C[:, 0] + C[:, 2]).max()
    y0, y1 = (C[:, 1] - C[:, 2]).min(), (C[:, 1] + C[:, 2]).max()
    w = max(x1 - x0, y1 - y0)
    return x0 - pad * w, x1 + pad * w, y0 - pad * w, y1 + pad * w


def circle_dist(c):
    return lambda X, Y: np.abs(np.hypot(X - c[0], Y - c[1]) - c[2])


@pytest.mark.parametrize("seed", range(10))
def test_circles_match_grid_reference(seed):
    m = 5 + seed  # 5 .. 14 circles
    cs = random_circles(100 + seed, m)
    G = DelaunayGraph(cs)
    check_against_grid(G, [circle_dist(c) for c in cs], circle_box(cs))
    # every empty circle is empty of all sites (exact locator, independent call) and touches its three
    for v in G.vertices:
        for k, c in enumerate(cs):
            d = abs(math.hypot(v.x - c[0], v.y - c[1]) - c[2])
            if k in v.sites:
                assert d == pytest.approx(v.radius, rel=1e-9, abs=1e-9)
            else:
                assert d > v.radius * (1 - 1e-9)
        i, j, k = v.sites
        others = [c for n, c in enumerate(cs) if n not in v.sites]
        for c4 in others[:4]:
            res = locate_conflicts_circles(cs[i], cs[j], cs[k], c4)
            match = [w for w in res.vertices if abs(w.x - v.x) + abs(w.y - v.y) < 1e-9 * (1 + v.radius)]
            assert len(match) == 1 and not match[0].in_conflict and match[0].certified


def test_agreement_summary():
    """Runs after the parametrised grid tests: report the agreement counts."""
    if "circles" in AGREEMENT:
        ok, tot = AGREEMENT["circles"]
        print(f"\ngrid reference, circles: {ok}/{tot} exact agreement, the rest explained by grid limits")
        assert ok >= tot // 2


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_insertion_order_independence(seed):
    cs = random_circles(200 + seed, 10)
    G1 = DelaunayGraph(cs)
    order = list(range(len(cs)))
    random.Random(seed).shuffle(order)
    G2 = DelaunayGraph(cs, order=order)
    assert G1.edges() == G2.edges()
    key = lambda G: sorted((v.sites, round(v.x, 9), round(v.y, 9)) for v in G.vertices)  # noqa: E731
    assert key(G1) == key(G2)
    assert len(G1.vertices) > 0


def test_candidate_modes_agree():
    cs = random_circles(300, 9)
    Ge, Ga = DelaunayGraph(cs), DelaunayGraph(cs, candidates="all")
    assert Ge.edges() == Ga.edges()
    assert [v.to_dict() for v in Ge.vertices] == [v.to_dict() for v in Ga.vertices]
    assert Ga.stats["triples_computed"] > Ge.stats["triples_computed"]


def test_cache_reuse_counts():
    cs = random_circles(400, 12)
    G1, G0 = DelaunayGraph(cs), DelaunayGraph(cs, cache=False)
    assert [v.to_dict() for v in G1.vertices] == [v.to_dict() for v in G0.vertices]
    assert G1.stats["triples_computed"] < G0.stats["triples_computed"]
    assert 0 < G1.cache_hit_rate() < 1 and G0.cache_hit_rate() == 0


def test_two_sites_certified_edge():
    G = DelaunayGraph([(0, 0, 1), (5, 0, 2)])
    assert G.edges() == {(0, 1)} and G.certified and G.vertices == []


def test_collinear_points_strip():
    # three collinear points: two parallel Voronoi lines, no vertex; (0, 2) are not neighbours
    G = DelaunayGraph([(0, 0, 0), (1, 0, 0), (3, 0, 0)])
    assert G.vertices == []
    assert G.edges() == {(0, 1), (1, 2)}
    assert not G.certified and all("numeric" in u for u in G.uncertified())
    G.insert((1, 4, 0))  # a fourth point off the line creates vertices: the edges become certified
    assert G.certified and G.edges() == {(0, 1), (1, 2), (0, 3), (1, 3), (2, 3)}


def test_nested_site_prop_1_2_1():
    # site 1 inside site 0, away from everything else: disconnected diagram, dangling edge
    cs = [(0, 0, 10), (1, 1, 1), (30, 0, 3), (0, 30, 4), (25, 25, 2)]
    G = DelaunayGraph(cs)
    info = G.edge_info()
    assert info[(0, 1)]["evidence"] == "numeric"
    assert all(1 not in v.sites for v in G.vertices)
    assert G.nested_components() == [[1], [0, 2, 3, 4]]
    check_against_grid(G, [circle_dist(c) for c in cs], circle_box(cs), label="nested")
    # a second nested site next to the first: they become neighbours through vertices
    G.insert((-4, -3, 1))
    assert (1, 5) in G.edges() and (0, 5) in G.edges()
    # a site bridging the two components (intersecting 0) reconnects the diagram
    G.insert((0, 12, 3))
    assert G.nested_components() == []


def test_json_networkx_and_cli(tmp_path):
    import importlib.resources as ir

    ex = ir.files("curvedvoronoi.runtime") / "data" / "example_sites.json"
    out_json, out_png = tmp_path / "d.json", tmp_path / "d.png"
    pytest.importorskip("matplotlib", reason="matplotlib (extra 'plot') is needed for the picture")
    G = run_diagram(str(ex), png=str(out_png), json_out=str(out_json), progress=False)
    d = json.loads(out_json.read_text())
    n = len(json.loads(ex.read_text())["conics"])
    assert len(d["sites"]) == n
    assert all(i < j for i, j in d["edges"]) and {tuple(e) for e in d["edges"]} == G.edges()
    for v in d["vertices"]:
        assert set(v) >= {"sites", "x", "y", "radius", "certified"} and v["sites"] == sorted(v["sites"])
    assert d["certified"] is False and any("[7, 8]" in u for u in d["uncertified_decisions"])  # nested 8 in 7
    assert out_png.stat().st_size > 10_000
    Gx = G.to_networkx()
    assert Gx.number_of_nodes() == n and set(map(tuple, map(sorted, Gx.edges()))) == G.edges()


def test_cli_errors(tmp_path):
    from curvedvoronoi.runtime.diagram import diagram_main

    bad = tmp_path / "bad.json"
    bad.write_text('{"conics": [{"coefficients": [1, 0, 1, 0, 0]}]}')
    assert diagram_main([str(bad), "--no-progress"]) == 2
    bad.write_text("not json")
    assert diagram_main([str(bad), "--no-progress"]) == 2


def test_bad_input():
    with pytest.raises(LocatorError, match="same curve"):
        DelaunayGraph([(0, 0, 1), (0, 0, 1)])
    with pytest.raises(ValueError):
        DelaunayGraph([(0, 0, 1)], candidates="some")
    with pytest.raises(ValueError):
        as_site({"coeffs": [1, 0, 1, 0, 0, -1]})
    s = as_site([1, 0, 1, 0, 0, -4])  # circle given by coefficients -> exact circle route
    assert s.is_circle and s.circle == Circle(0, 0, 4)


# ------------------------------------------------------------------ conics (general locator)

def _mixed_conics(seed: int, m: int):
    from curvedvoronoi.runtime.conic import Conic

    rnd = random.Random(seed)
    out = []
    while len(out) < m:
        cx, cy = rnd.randint(-40, 40), rnd.randint(-40, 40)
        if any(math.hypot(cx - a, cy - b) < 12 for a, b, _ in out):
            continue
        kind = rnd.choice(["ellipse", "ellipse", "circle"])
        if kind == "circle":
            c = Conic.circle(centre=(cx, cy), radius=rnd.randint(2, 5))
        else:
            c = Conic.ellipse(centre=(cx, cy), axes=(rnd.randint(3, 6), rnd.randint(1, 3)),
                              rotation=rnd.choice([("3/5", "4/5"), ("4/5", "3/5"), (1, 0), (0, 1), ("5/13", "12/13")]))
        out.append((cx, cy, c))
    return [c for _, _, c in out]


def test_conic_site_without_locator_is_clear():
    from curvedvoronoi.runtime.conic import Conic

    e = Conic.ellipse(centre=(0, 0), axes=(3, 1))
    assert conic_locator_available()     # shipped with the package: conic sites are accepted
    G = DelaunayGraph([e, (10, 0, 1), (0, 10, 2)])
    assert len(G.sites) == 3


def _mixed_set():
    from curvedvoronoi.runtime.conic import Conic

    return [Conic.ellipse(centre=(0, 0), axes=(6, 2), rotation=("3/5", "4/5")),
            Conic.circle(centre=(-15, 10), radius=3),
            Conic.ellipse(centre=(18, -4), axes=(4, 2), rotation=(0, 1)),
            Conic.circle(centre=(8, 15), radius=4),
            Conic.circle(centre=(-4, -18), radius=3)]


def test_mixed_conics_match_grid_reference():
    """2 ellipses + 3 circles (kept small: each conic triple costs seconds); more random sets
    (_mixed_conics) are run by bench/bench_diagram.py."""
    from reference import RefConic, _grid_dist

    conics = _mixed_set()
    G = DelaunayGraph(conics)
    assert not G.certified  # the conic locator's numeric route is not certified
    refs = [RefConic(c) for c in conics]
    box = (-60.0, 60.0, -60.0, 60.0)
    check_against_grid(G, [lambda X, Y, r=r: _grid_dist(r, X, Y) for r in refs], box, n=300, label="conics")
    assert len(G.vertices) >= 3
    for v in G.vertices:
        for k, r in enumerate(refs):
            d = float(_grid_dist(r, np.array([v.x]), np.array([v.y]))[0])
            if k in v.sites:
                assert d == pytest.approx(v.radius, rel=1e-6, abs=1e-6)
            else:
                assert d > v.radius * (1 - 1e-6)
