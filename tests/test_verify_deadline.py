"""The verifier's deadline (runtime/voronoi/verify/certificate.verify, ``deadline``): "edges not
checked by then are not proved".  An edge whose proof is complete before the deadline stays proved
when the deadline passes while the certificate is assembled; only the work that would start after
it (the tails of unbounded curved edges, runtime/voronoi/verify/curved_edges.py) is left undone,
and the certificate then says so.

The deadline is made to pass at a chosen moment, right after the chains of strips of every curved
edge are done (runtime/voronoi/verify/curved.prove_curved_edges), by replacing the clock test
``curved_edges.past``; nothing else of the verifier is replaced.
"""
from __future__ import annotations

import time
from fractions import Fraction as F

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.verify import curved, curved_edges


def test_bounded_curved_edges_proved_before_the_deadline_stay_proved(monkeypatch):
    """Ellipses (axes 2, 1) centred at (0, 0), (7, 0), (13, 1/6), (7, −3) (the diagram of
    tests/test_verify_float_boundaries.py: three bounded edges, three unbounded).  With the
    deadline passing once the chains are proved, the three bounded edges are proved and the
    unbounded ones, whose tails would start after the deadline, are not checked."""
    d = cv.voronoi([cv.Conic.ellipse(centre=c, axes=(2, 1)) for c in [(0, 0), (7, 0), (13, F(1, 6)), (7, -3)]])
    assert d.certified, d.problems
    doc = d.to_json()
    chains_done = [False]
    prove_chains = curved.prove_curved_edges

    def chains_then_deadline(*args, **kw):
        out = prove_chains(*args, **kw)
        chains_done[0] = True
        return out

    monkeypatch.setattr(curved, "prove_curved_edges", chains_then_deadline)
    monkeypatch.setattr(curved_edges, "past", lambda deadline: deadline is not None and chains_done[0])
    cert = cv.verify(doc, deadline=time.perf_counter() + 3600)
    assert chains_done[0]
    bounded = [k for k, e in enumerate(doc["edges"]) if None not in e["ends"]]
    unbounded = [k for k, e in enumerate(doc["edges"]) if None in e["ends"]]
    assert len(bounded) == 3 and len(unbounded) == 3
    assert all(cert.edges[k] for k in bounded)
    assert not any(cert.edges[k] for k in unbounded)
    assert not cert.ok and any("time limit" in p for p in cert.problems)
    # without a deadline the same diagram is proved
    assert cv.verify(doc).ok
