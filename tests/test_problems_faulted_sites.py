"""The sites a certificate's faults name (runtime/voronoi/verify/problems.py, faulted_sites): the
construction refines there, so the set must hold exactly the sites of the Problem records that are
faults — their own ``sites``, and those of the edge and of the vertex they name — and nothing from
the limits of the proof (plain strings, or records with ``fault=False``).  Indices outside the
diagram (a document's invalid ids) name nothing.  The diagram here is a hand-made stand-in with
three vertices and three edges among five sites; each expected set is written from the records."""
from __future__ import annotations

from types import SimpleNamespace

from curvedvoronoi.runtime.voronoi.verify.problems import Problem, fault, faulted_sites


def _diagram():
    V = [SimpleNamespace(sites=(0, 1, 2)), SimpleNamespace(sites=(1, 2, 3)), SimpleNamespace(sites=(2, 3, 4))]
    E = [SimpleNamespace(sites=(0, 1)), SimpleNamespace(sites=(3, 4)), SimpleNamespace(sites=(1, 4))]
    return SimpleNamespace(sites=list(range(5)), vertices=V, edges=E)


def test_a_fault_names_its_sites_and_those_of_its_edge_and_vertex():
    D = _diagram()
    assert faulted_sites([fault("site 3 is closer", kind="site", sites=(3,))], D) == {3}
    assert faulted_sites([fault("site 4 is closer", kind="site", sites=(4,))], D) == {4}
    assert faulted_sites([fault("edge 1 is wrong", kind="edge", edge=1)], D) == {3, 4}
    assert faulted_sites([fault("vertex 0 is wrong", kind="vertex", vertex=0)], D) == {0, 1, 2}
    assert faulted_sites([fault("both", kind="edge", sites=(0,), edge=2, vertex=2)], D) == {0, 1, 2, 3, 4}


def test_limits_of_the_proof_name_no_site():
    D = _diagram()
    limits = ["edge 1: the tail is undecided (work limit)",
              Problem("edge 1: not proved", kind="edge", sites=(3, 4), edge=1, vertex=1, fault=False)]
    assert faulted_sites(limits, D) == set()
    assert faulted_sites(limits + [fault("site 2 is closer", kind="site", sites=(2,))], D) == {2}


def test_ids_outside_the_diagram_name_nothing():
    D = _diagram()
    assert faulted_sites([fault("bad ids", kind="diagram", sites=(5, 7), edge=3, vertex=3)], D) == set()
    assert faulted_sites([fault("one bad, one good", kind="diagram", sites=(5, 1))], D) == {1}
