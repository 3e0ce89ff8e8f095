"""Quick start: sites, the conflict locator, and what its answer means.

Run: ``python examples/quickstart.py``.  Thesis references: §3.1.3 (circles), ch. 5 (conics).
"""
import curvedvoronoi as cv

# Sites.  Conics are exact: integers, fractions, rational strings, or floats taken exactly.
c1 = cv.Conic.ellipse(centre=(0, 0), axes=(2, 1))                        # x²/4 + y² = 1
c2 = cv.Conic.from_coefficients(144, -96, 116, -1248, 316, 2549)
c3 = cv.Conic.from_coefficients("2642", "-1920", "738", "714", "-3762", "6577")
c4 = cv.Conic.from_coefficients(1076, -336, 549, -4708, -1356, 7116)
for i, c in enumerate((c1, c2, c3, c4)):
    print(f"site {i}: {c.kind:9s} centre ({c.frame.tx:.3f}, {c.frame.ty:.3f})")

# The conflict locator: true Voronoi vertices of sites 0, 1, 2 (centres of empty circles tangent
# to the three), and whether site 3 enters each empty circle.
res = cv.locate_conflicts(c1, c2, c3, c4)
print(f"conflict={res.conflict} certified={res.certified} complete={res.complete}")
for v in res.vertices:
    print(f"  vertex ({v.x:.6f}, {v.y:.6f}) radius {v.radius:.6f}: site 3 at distance "
          f"{v.distance_to_fourth:.6f} -> in_conflict={v.in_conflict}")
assert res.certified and res.conflict

# Circles and points go to the exact locator of §3.1.3 (every decision proved).
sites = [cv.Circle.from_radius(0, 0, 1), cv.Circle.from_radius(4, 0, 1), cv.Circle.from_radius(0, 4, 1),
         cv.Point(1, 1)]
res = cv.locate_conflicts_circles(*sites)
(v,) = res.vertices
print(f"circles: vertex ({float(v.x)}, {float(v.y)}), radius {float(v.radius):.6f} = 2√2 − 1, "
      f"point (1, 1) in conflict: {v.in_conflict}")
assert v.in_conflict and res.certified

# Bad input is a one-line ValueError.
try:
    cv.Conic.from_coefficients(1, 0, 1, 0, 0, 1)
except cv.InvalidConicError as exc:
    print(f"refused: {exc}")
