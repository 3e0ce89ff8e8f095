"""Sites inside an ellipse whose Voronoi loop crosses the ellipse's medial axis (the segment
|X| ≤ (a² − b²)/a of its major axis, where the distance from inside has two nearest points and no
gradient): proved with the Clarke generalised gradient (runtime/voronoi/verify/clarke_gradient.py)
in the strips' monotonicity test.  References use none of the library's geometry: the ellipse's
distance by dense sampling of its boundary, the circles' in closed form, the nearest points of a
point on the medial axis in closed form (the normal through (x, 0) meets the ellipse where
cos t = a·x/(a² − b²))."""
from __future__ import annotations

import copy

import numpy as np

import curvedvoronoi as cv
from curvedvoronoi.runtime.predicates.circles import Circle
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.clarke_gradient import clarke_normal_range, difference_range, off_ridge_gradient
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, gradient_enclosure


def ellipse_distance(P, centre, axes, degrees=0.0, m=20000):
    """d(P, ellipse) by sampling m boundary points (error ≤ the half-spacing, about π·a/m)."""
    t = np.linspace(0, 2 * np.pi, m, endpoint=False)
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    X, Y = axes[0] * np.cos(t), axes[1] * np.sin(t)
    bx, by = centre[0] + c * X - s * Y, centre[1] + s * X + c * Y
    P = np.asarray(P, float).reshape(-1, 2)
    out = np.empty(len(P))
    for k in range(0, len(P), 200):
        Q = P[k:k + 200]
        out[k:k + 200] = np.hypot(Q[:, :1] - bx, Q[:, 1:] - by).min(1)
    return out


def test_the_clarke_range_holds_both_feet_on_the_medial_axis():
    """At q = (x, 0) on the medial axis of X²/100 + Y²/36 = 1 the two nearest points are
    (a cos t, ±b sin t) with cos t = a·x/(a² − b²); both unit vectors (q − p)/|q − p| lie in the
    Clarke gradient, so the range of g·n must hold both values, for n across and along the axis."""
    a, b, x = 10.0, 6.0, -4.0
    ct = a * x / (a * a - b * b)
    st = np.sqrt(1 - ct * ct)
    feet = np.array([[a * ct, b * st], [a * ct, -b * st]])
    u = (np.array([x, 0.0]) - feet) / np.hypot(*(np.array([x, 0.0]) - feet).T)[:, None]
    geoms = [site_geometry(cv.Conic.ellipse((0, 0), (a, b)))]
    T = SiteTable(geoms, 11.0)
    Q = np.array([[x, 0.0]] * 3)
    V = T.evaluate(Q, [0, 0, 0])
    N = np.array([[0.0, 1.0], [1.0, 0.0], [0.6, 0.8]])
    lo, hi, ok = clarke_normal_range(T, Q, [0, 0, 0], V.lo, V.hi, 1e-3, N, V.inner)
    assert ok.all()
    for r in range(3):
        vals = u @ N[r]
        assert lo[r] <= vals.min() and vals.max() <= hi[r]
        assert hi[r] - lo[r] <= (vals.max() - vals.min()) + 0.15          # and not much wider
    # across the axis the two feet have opposite components: no sign is proved there
    assert lo[0] < 0 < hi[0]


def test_the_clarke_range_contains_sampled_gradients_on_a_disc():
    """Every (q − p)/|q − p|, q in the disc and p a nearest point of q (dense sampling of the
    boundary), has its component along n within the range, for discs across the medial axis."""
    rng = np.random.default_rng(7)
    a, b, deg = 10.0, 6.0, 25.0
    geoms = [site_geometry(cv.Conic.ellipse((1, -2), (a, b), degrees=deg))]
    T = SiteTable(geoms, 13.0)
    t = np.linspace(0, 2 * np.pi, 200000, endpoint=False)
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    bx, by = 1 + c * a * np.cos(t) - s * b * np.sin(t), -2 + s * a * np.cos(t) + c * b * np.sin(t)
    for centre, R in (((1 + c * 3, -2 + s * 3), 0.5), ((1 - c * 5, -2 - s * 5), 0.2), ((1, -2), 1.0)):
        Qc = np.array([centre])
        V = T.evaluate(Qc, [0])
        rr = R * np.sqrt(rng.random(200))
        ph = 2 * np.pi * rng.random(200)
        q = Qc + np.column_stack([rr * np.cos(ph), rr * np.sin(ph)])
        k = np.array([np.hypot(qq[0] - bx, qq[1] - by).argmin() for qq in q])
        g = q - np.column_stack([bx[k], by[k]])
        g /= np.hypot(*g.T)[:, None]
        for ang in np.linspace(0, np.pi, 7):
            n = np.array([[np.cos(ang), np.sin(ang)]])
            lo, hi, ok = clarke_normal_range(T, Qc, [0], V.lo, V.hi, R, n, V.inner)
            assert ok[0]
            val = g @ n[0]
            # sampling puts the foot within 2e-4 of a nearest point: the direction within 1e-4
            assert lo[0] - 1e-4 <= val.min() and val.max() <= hi[0] + 1e-4, (centre, ang, lo, hi, val.min(), val.max())


def test_the_range_of_a_difference_holds_every_difference_of_gradients():
    """f = d_i − d_j of the circle (2, 0, 1) and the ellipse 10 × 6 at q = (−4, 0) on its medial
    axis: ∂f holds ∇d_circle − u_± with the two feet's unit vectors u_± (closed form, as above).
    Across the axis (n = (0, 1)) the values have both signs, so no monotonicity may be claimed, in
    either order of the pair; along it (n = (1, 0)) all are > 0 and f is proved monotone."""
    a, b, x = 10.0, 6.0, -4.0
    ct = a * x / (a * a - b * b)
    st = np.sqrt(1 - ct * ct)
    feet = np.array([[a * ct, b * st], [a * ct, -b * st]])
    u = (np.array([x, 0.0]) - feet) / np.hypot(*(np.array([x, 0.0]) - feet).T)[:, None]
    gc = np.array([-1.0, 0.0])                                   # ∇|q − (2, 0)| at q = (−4, 0)
    geoms = [site_geometry(cv.Conic.ellipse((0, 0), (a, b))), site_geometry(Circle.from_radius(2, 0, 1))]
    T = SiteTable(geoms, 11.0)
    Q = np.array([[x, 0.0], [x, 0.0]])
    R = np.array([1e-3, 1e-3])
    N = np.array([[0.0, 1.0], [1.0, 0.0]])
    V = [T.evaluate(Q, [k, k]) for k in (0, 1)]
    G = [gradient_enclosure(Q, V[k], R, 11.0) for k in (0, 1)]
    for i, j in ((0, 1), (1, 0)):
        lo, hi, ok = difference_range(T, Q, R, N, (np.array([i, i]), np.array([j, j])), (V[i], V[j]), (G[i], G[j]))
        assert ok.all()
        for r in range(2):
            gi = [gc] if i == 1 else list(u)
            gj = [gc] if j == 1 else list(u)
            vals = [float((p - q) @ N[r]) for p in gi for q in gj]
            assert lo[r] <= min(vals) and max(vals) <= hi[r], (i, j, r, lo[r], hi[r], vals)
        assert lo[0] < 0 < hi[0]                                 # across the axis: undecided
        assert (lo[1] > 0) if i == 0 else (hi[1] < 0)            # along it: proved


def test_a_point_on_the_ellipse_gets_no_range():
    geoms = [site_geometry(cv.Conic.ellipse((0, 0), (10, 6)))]
    T = SiteTable(geoms, 11.0)
    Q = np.array([[10.0, 0.0]])
    V = T.evaluate(Q, [0])
    lo, hi, ok = clarke_normal_range(T, Q, [0], V.lo, V.hi, 0.1, np.array([[1.0, 0.0]]), V.inner)
    assert not ok[0] and lo[0] == -np.inf and hi[0] == np.inf


def _loop_check(d, dist0, dist1, slack):
    """The closed edge's polyline points are equidistant from the container and the inner site
    (within the stated tolerance, doubled for |d_0 − d_1| ≤ 2·offset, plus the sampling error)."""
    loop = [e for e in d.edges if e.closed]
    assert len(loop) == 1
    P = np.array(loop[0].polyline, float)
    gap = np.abs(dist0(P) - dist1(P))
    assert gap.max() <= 2 * loop[0].tolerance + slack, gap.max()
    return P


def test_a_circle_alone_inside_an_ellipse_is_certified_across_the_medial_axis():
    """The bench's first drawing: circle (2, 0, 1) inside the ellipse 10 × 6.  Its loop crosses
    the medial axis (|x| ≤ 6.4 on y = 0) at x ≈ −4.1; not certified before (monotonicity
    undecided there)."""
    d = cv.voronoi([cv.Conic.ellipse((0, 0), (10, 6)), (2, 0, 1)], progress=False)
    assert d.certified, d.problems
    P = _loop_check(d, lambda P: ellipse_distance(P, (0, 0), (10, 6)),
                    lambda P: np.abs(np.hypot(P[:, 0] - 2, P[:, 1]) - 1), 5e-3)
    # the loop crosses the medial axis: points on both sides of y = 0 at x in [−6.4, 6.4], left of the circle
    left = P[(P[:, 0] < 1) & (np.abs(P[:, 0]) < 6.4)]
    assert (left[:, 1] > 0).any() and (left[:, 1] < 0).any()
    assert d.delaunay_edges() == [(0, 1)]


def test_a_corrupted_loop_across_the_medial_axis_is_refused():
    d = cv.voronoi([cv.Conic.ellipse((0, 0), (10, 6)), (2, 0, 1)], progress=False)
    doc = d.to_json()
    assert cv.verify(doc).ok
    t = next(t for t, e in enumerate(doc["edges"]) if e["closed"])
    tol = doc["edges"][t]["tolerance"]
    # only the points near the crossing moved, along the axis, by 20 tolerances
    bad = copy.deepcopy(doc)
    P = np.array(bad["edges"][t]["polyline"], float)
    near = np.hypot(P[:, 0] + 4.1, P[:, 1]) < 0.5
    assert near.any()
    P[near, 0] -= 20 * tol + 1e-3
    bad["edges"][t]["polyline"] = P.tolist()
    assert not cv.verify(bad).ok
    bad = copy.deepcopy(doc)                      # the loop dropped
    bad["edges"] = []
    bad["delaunay_edges"] = []
    assert not cv.verify(bad).ok


def test_nested_ellipses_are_certified_and_match_dense_sampling():
    """A rotated ellipse inside the ellipse 10 × 6: its loop crosses the container's medial axis
    (not certified before: monotonicity undecided near (−5.9, 0))."""
    outer, inner = ((0, 0), (10, 6), 0.0), ((1, 0.5), (3, 1.5), 20.0)
    d = cv.voronoi([cv.Conic.ellipse(outer[0], outer[1]), cv.Conic.ellipse(inner[0], inner[1], degrees=inner[2])],
                   progress=False)
    assert d.certified, d.problems
    P = _loop_check(d, lambda P: ellipse_distance(P, *outer), lambda P: ellipse_distance(P, *inner), 5e-3)
    assert ((np.abs(P[:, 1]) < 0.3) & (np.abs(P[:, 0]) < 6.4)).any()       # crosses the medial axis
    # the loop separates: inside it the inner ellipse is nearer, outside the container (grid test)
    X, Y = np.meshgrid(np.linspace(-9.5, 9.5, 60), np.linspace(-5.5, 5.5, 40))
    G = np.column_stack([X.ravel(), Y.ravel()])
    G = G[(G[:, 0] / 10) ** 2 + (G[:, 1] / 6) ** 2 < 1]
    from matplotlib.path import Path
    inside = Path(P).contains_points(G)
    d0, d1 = ellipse_distance(G, *outer), ellipse_distance(G, *inner)
    clear = np.abs(d0 - d1) > 0.05
    assert (inside[clear] == (d1 < d0)[clear]).all()
    bad = copy.deepcopy(d.to_json())                # the loop shrunk towards the inner ellipse by 2%
    e = next(e for e in bad["edges"] if e["closed"])
    Pb = np.array(e["polyline"], float)
    e["polyline"] = (np.array(inner[0]) + 0.98 * (Pb - np.array(inner[0]))).tolist()
    assert not cv.verify(bad).ok


def test_off_the_ridge_the_box_encloses_the_gradient_and_on_it_none_is_given():
    """Inside the ellipse 10 × 6 beyond the reach b²/a = 3.6 but off the open segment |x| < 6.4 of
    y = 0 the distance is C¹: the box must hold every sampled gradient of the disc; a disc that
    meets the segment gets no box (no gradient exists on the ridge)."""
    rng = np.random.default_rng(3)
    geoms = [site_geometry(cv.Conic.ellipse((0, 0), (10, 6)))]
    T = SiteTable(geoms, 11.0)
    t = np.linspace(0, 2 * np.pi, 200000, endpoint=False)
    bx, by = 10 * np.cos(t), 6 * np.sin(t)
    Q = np.array([[-2.0, 1.0], [1.0, -1.5], [-2.0, 0.2], [7.0, 0.0], [0.0, 0.05], [5.0, 0.0]])
    R = np.array([0.2, 0.15, 0.25, 0.15, 0.1, 0.1])
    V = T.evaluate(Q, [0] * len(Q))
    assert (V.hi[:2] + R[:2] > 3.6).all()                       # beyond the reach
    G, s, ok = off_ridge_gradient(T, Q, [0] * len(Q), V.lo, V.hi, R, V.inner)
    assert ok.tolist() == [True, True, False, True, False, False]  # (7, 0) lies beyond the ridge's end 6.4
    assert (s[:2] < 0.05).all() and s[3] < 0.5                   # linear in R, not the whole unit disc
    for r in np.nonzero(ok)[0]:
        rr = R[r] * np.sqrt(rng.random(150))
        ph = 2 * np.pi * rng.random(150)
        q = Q[r] + np.column_stack([rr * np.cos(ph), rr * np.sin(ph)])
        k = np.array([np.hypot(qq[0] - bx, qq[1] - by).argmin() for qq in q])
        g = q - np.column_stack([bx[k], by[k]])
        g /= np.hypot(*g.T)[:, None]
        err = np.hypot(*(g - G[r]).T)
        assert err.max() <= s[r] + 1e-4, (r, err.max(), s[r])


def test_two_sites_inside_a_rotated_ellipse_with_a_vertex_beyond_the_reach():
    """The ellipse 10 × 6 rotated 30° holding an ellipse and a circle: the vertex (0, 1, 2) lies
    at depth 3.69 in the container, beyond its reach 3.6, where the transversality test (T3) needs
    the off-ridge gradient box (not certified before: 'a third site undecided')."""
    outer, inner = ((0, 0), (10, 6), 30.0), ((-2, 1), (2, 1), -40.0)
    d = cv.voronoi([cv.Conic.ellipse(outer[0], outer[1], degrees=outer[2]),
                    cv.Conic.ellipse(inner[0], inner[1], degrees=inner[2]), (4, -1, 1)], progress=False)
    assert d.certified, d.problems
    assert len(d.vertices) == 2 and len(d.edges) == 3

    def dists(P):
        P = np.asarray(P, float).reshape(-1, 2)
        return np.stack([ellipse_distance(P, *outer), ellipse_distance(P, *inner),
                         np.abs(np.hypot(P[:, 0] - 4, P[:, 1] + 1) - 1)])
    for v in d.vertices:
        D = dists([v.x, v.y])[:, 0]
        assert np.ptp(D) < 5e-3 and abs(D.mean() - v.radius) < 5e-3
    assert max(v.radius for v in d.vertices) > 3.6
    for e in d.edges:
        P = np.array(e.polyline, float)
        D = dists(P)
        i, j = e.sites
        assert np.abs(D[i] - D[j]).max() <= 2 * e.tolerance + 5e-3
        k = 3 - i - j
        inner_pts = P[1:-1] if len(P) > 2 else P
        Dk = dists(inner_pts)
        assert (Dk[k] >= np.minimum(Dk[i], Dk[j]) - 5e-3).all()


def test_a_circle_container_has_its_centre_as_ridge():
    geoms = [site_geometry(Circle.from_radius(1, 2, 5))]
    T = SiteTable(geoms, 8.0)
    Q = np.array([[1.3, 2.0], [1.0, 4.0]])
    V = T.evaluate(Q, [0, 0])
    G, s, ok = off_ridge_gradient(T, Q, [0, 0], V.lo, V.hi, np.array([0.5, 0.5]), V.inner)
    assert ok.tolist() == [False, True]                          # the first disc holds the centre
    # ∇d = −(q − c)/|q − c| inside: (0, −1) at the second centre, within 0.5/1.5 in angle nearby
    assert np.hypot(G[1, 0] - 0.0, G[1, 1] + 1.0) <= s[1] <= 0.5


def test_the_clarke_range_holds_sampled_gradients_on_many_discs():
    """Random discs inside the ellipse 9 × 4 rotated 35° (medial segment |X| < 7.2): every sampled
    (q − p)/|q − p| (p the nearest of 40000 boundary samples) has its components in the ranges."""
    rng = np.random.default_rng(11)
    a, b, deg = 9.0, 4.0, 35.0
    geoms = [site_geometry(cv.Conic.ellipse((0.5, -1), (a, b), degrees=deg))]
    T = SiteTable(geoms, 11.0)
    t = np.linspace(0, 2 * np.pi, 40000, endpoint=False)
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    bx, by = 0.5 + c * a * np.cos(t) - s * b * np.sin(t), -1 + s * a * np.cos(t) + c * b * np.sin(t)
    U = rng.uniform(-1, 1, (60, 2)) * [a * 0.8, b * 0.8]
    U = U[(U[:, 0] / a) ** 2 + (U[:, 1] / b) ** 2 < 0.6]
    Qc = np.column_stack([0.5 + c * U[:, 0] - s * U[:, 1], -1 + s * U[:, 0] + c * U[:, 1]])
    R = rng.uniform(0.02, 0.4, len(Qc))
    V = T.evaluate(Qc, [0] * len(Qc))
    for N in (np.array([1.0, 0.0]), np.array([0.6, -0.8])):
        lo, hi, ok = clarke_normal_range(T, Qc, [0] * len(Qc), V.lo, V.hi, R, np.tile(N, (len(Qc), 1)), V.inner)
        for r in np.nonzero(ok)[0]:
            rr = R[r] * np.sqrt(rng.random(25))
            ph = 2 * np.pi * rng.random(25)
            q = Qc[r] + np.column_stack([rr * np.cos(ph), rr * np.sin(ph)])
            D = np.hypot(q[:, :1] - bx, q[:, 1:] - by)
            k = D.argmin(1)
            g = (q - np.column_stack([bx[k], by[k]])) / D.min(1)[:, None]
            val = g @ N
            assert lo[r] - 1e-3 <= val.min() and val.max() <= hi[r] + 1e-3, (r, lo[r], hi[r], val.min(), val.max())
        assert ok.sum() >= len(Qc) - 2
