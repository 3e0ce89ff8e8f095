"""The Voronoi diagram of four ellipses and a circle, with curved edges, as JSON and a picture.

Run: ``python examples/voronoi_of_ellipses.py [OUT.png]``.  Thesis §1.2 (Voronoi diagram and
Delaunay graph of curved sites).
"""
import json
import sys
from fractions import Fraction

import curvedvoronoi as cv

sites = [cv.Conic.ellipse(centre=(0, 0), axes=(2, 1)),
         cv.Conic.ellipse(centre=(6, 1), axes=(Fraction(3, 2), 1), rotation=("3/5", "4/5")),
         cv.Conic.ellipse(centre=(2, 6), axes=(2, Fraction(2, 3)), rotation=("5/13", "12/13")),
         cv.Conic.ellipse(centre=(7, 7), axes=(1, Fraction(1, 2)), rotation=("8/17", "15/17")),
         cv.Circle.from_radius(-4, 5, 1)]
D = cv.voronoi(sites)
print(f"{len(D.vertices)} Voronoi vertices, {len(D.edges)} edges, certified={D.certified}")
print("Delaunay graph:", D.delaunay_edges())
for v in D.vertices:
    print(f"  vertex of sites {v.sites}: ({v.x:.4f}, {v.y:.4f}), empty circle radius {v.radius:.4f}")
doc = D.to_json()
print("JSON keys:", sorted(doc))
json.dumps(doc)                                   # plain JSON, ready to write
if len(sys.argv) > 1:                             # a picture with matplotlib (part of the default install)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 7))
    for i, s in enumerate(sites):
        c = cv.Conic.circle(centre=(s.cx, s.cy), r2=s.r2) if isinstance(s, cv.Circle) else s
        xy = c.sample(300) + c.sample(1)
        ax.plot([p[0] for p in xy], [p[1] for p in xy], lw=2, label=f"site {i}")
    for k, e in enumerate(D.edges):
        ax.plot(e.polyline[:, 0], e.polyline[:, 1], color="tab:orange", label="Voronoi edge" if k == 0 else None)
    ax.plot([v.x for v in D.vertices], [v.y for v in D.vertices], "ko", ms=4, label="Voronoi vertex")
    ax.set_xlim(-10, 14)
    ax.set_ylim(-6, 13)
    ax.set_aspect("equal")
    ax.legend(loc="lower right", fontsize=8)
    fig.savefig(sys.argv[1], dpi=90)
    print("wrote", sys.argv[1])
