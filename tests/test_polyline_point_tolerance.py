"""The verifier's check of each drawn point of an edge against the edge's stated tolerance
(runtime/voronoi/verify/edge_checks.py, ``_polyline_on_arc``), at its boundary: a point of the
circle–point edge moved off the bisector along its normal by k times the stated tolerance
(k = 1.5 … 2.9; the bisector |q − c| − 1 = |q − p| is a hyperbola branch, flat at the scale of the
move: its distance is k·tol to first order, checked here by sampling the branch) is refused by name
— that point, "from the bisector" —, not only by the later bound on the whole polyline; a move of a
quarter tolerance along the bisector's normal keeps a point the check accepts."""
import json
import math

import numpy as np
import pytest

import curvedvoronoi as cv

C0, P3 = np.array([0.0, 0.0]), np.array([3.0, 2.0])


def unit_normal(q):
    g = (q - C0) / np.linalg.norm(q - C0) - (q - P3) / np.linalg.norm(q - P3)
    return g / np.linalg.norm(g)


def distance_to_branch(q):
    """Distance from q to {x : |x − C0| − 1 = |x − P3|}, by dense sampling of the branch near q:
    on each ray from P3 at angle θ the branch point is at distance ρ(θ) with |P3 + ρu − C0| = 1 + ρ,
    ρ = (|P3 − C0|² − 1) / (2(1 − (P3 − C0)·u)) (closed form)."""
    w = P3 - C0
    th0 = math.atan2(*(q - P3)[::-1])
    th = th0 + np.linspace(-0.05, 0.05, 200001)
    u = np.column_stack([np.cos(th), np.sin(th)])
    rho = (w @ w - 1) / (2 * (1 - u @ w))
    X = P3 + rho[:, None] * u
    return float(np.min(np.hypot(*(X - q).T)))


@pytest.fixture(scope="module")
def doc():
    d = cv.voronoi([(0, 0, 1), (6, 0, 2), (2, 5, 1), (3, 2, 0)], certify=False)
    D = d.to_json()
    assert [sorted(e["sites"]) for e in D["edges"]][0] == [0, 3]
    return D


@pytest.mark.parametrize("k", [1.5, 2.0, 2.9])
def test_a_point_moved_off_the_bisector_is_refused_by_name(doc, k):
    D = json.loads(json.dumps(doc))
    e = D["edges"][0]
    tol = e["tolerance"]
    P = np.array(e["polyline"][6])
    Q = P + k * tol * unit_normal(P)
    assert distance_to_branch(Q) > 1.4 * tol            # the move is real: well beyond the tolerance
    e["polyline"][6] = [float(Q[0]), float(Q[1])]
    cert = cv.verify(D)
    assert not cert.ok
    assert any(str(p).startswith("edge 0 (sites 0, 3): polyline point 6 ") and "from the bisector" in str(p)
               for p in cert.problems), cert.problems


def test_a_point_a_quarter_tolerance_off_is_accepted_by_the_point_check(doc):
    D = json.loads(json.dumps(doc))
    e = D["edges"][0]
    P = np.array(e["polyline"][6])
    Q = P + 0.25 * e["tolerance"] * unit_normal(P)
    assert distance_to_branch(Q) < 0.5 * e["tolerance"]
    e["polyline"][6] = [float(Q[0]), float(Q[1])]
    cert = cv.verify(D)
    assert not any("polyline point 6" in str(p) for p in cert.problems), cert.problems


def polyline_to_branch(P, m=400):
    """max over the polyline's segments (m points each) of the distance to the branch: the part
    of the Hausdorff distance the segments add between nodes on the bisector."""
    worst = 0.0
    for A, B in zip(P[:-1], P[1:]):
        for s in np.linspace(0, 1, m):
            worst = max(worst, distance_to_branch(A + s * (B - A)))
    return worst


@pytest.mark.parametrize("k", [1.5, 2.5])
def test_chords_that_leave_the_arc_by_k_tolerances_are_refused(doc, k):
    """Every other interior point dropped: the nodes stay on the bisector, the chords between them
    leave it by `sag` (sampled); with the tolerance stated as sag / k the polyline must be refused
    by the bound on the whole polyline."""
    D = json.loads(json.dumps(doc))
    e = D["edges"][0]
    P = np.array(e["polyline"])
    Q = np.vstack([P[:-1:2], P[-1:]])
    sag = polyline_to_branch(Q, 60)
    assert sag > 1e-3                               # a real departure, far above rounding
    e["polyline"] = Q.tolist()
    e["tolerance"] = sag / k
    cert = cv.verify(D)
    assert any(str(p).startswith("edge 0 (sites 0, 3): its polyline is proved only within") for p in cert.problems), \
        cert.problems
