"""Read sites from a JSON file (the schema of docs/index.md) and run the conflict locator.

Run: ``python examples/locate_from_json.py [FILE.json]`` (default: examples/sites_forms.json).
The same as ``curvedvoronoi locate FILE.json``, from Python.
"""
import sys
from pathlib import Path

import curvedvoronoi as cv

path = sys.argv[1] if len(sys.argv) > 1 else str(Path(__file__).with_name("sites_forms.json"))
sites = cv.read_sites(path, expected=4)          # validated; errors name the entry, 0-based
for i, s in enumerate(sites):
    print(f"site {i}: {s!r}")
res = cv.locate_conflicts(*sites)                # circles/points -> exact §3.1 locator, else ch. 5
print(f"conflict={res.conflict} certified={res.certified} method={res.method}")
for v in res.vertices:
    print(f"  vertex ({v.x:.6f}, {v.y:.6f}) radius {v.radius:.6f} in_conflict={v.in_conflict} "
          f"certified={v.certified}")
