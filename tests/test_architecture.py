"""The package's structure: no import cycles (also none hidden in function-level imports), runtime
never imports precompute, every sub-package is installed, and each module imports on its own."""
from __future__ import annotations

import ast
import re
import pathlib
import subprocess
import sys
import tomllib

import networkx as nx
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
PACKAGES = ("runtime", "precompute", "generated")


def _modules() -> dict[str, pathlib.Path]:
    mods = {}
    for pkg in PACKAGES:
        for f in (ROOT / pkg).rglob("*.py"):
            parts = list(f.relative_to(ROOT).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            mods[".".join(parts)] = f
    return mods


def import_graph() -> nx.DiGraph:
    """Module -> module edges of every import statement (top level or inside functions)."""
    mods = _modules()
    G = nx.DiGraph()
    G.add_nodes_from(mods)
    for name, f in mods.items():
        pkg = name.split(".") if f.name == "__init__.py" else name.split(".")[:-1]
        for node in ast.walk(ast.parse(f.read_text())):
            targets = []
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = ".".join(pkg[:len(pkg) - node.level + 1] + ([node.module] if node.module else []))
                else:
                    base = (node.module or "").removeprefix("curvedvoronoi.")
                targets = [base] + [f"{base}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                targets = [a.name.removeprefix("curvedvoronoi.") for a in node.names]
            for t in targets:
                if t in mods and t != name and not name.startswith(t + "."):
                    G.add_edge(name, t)
    return G


def test_no_import_cycles():
    cycles = list(nx.simple_cycles(import_graph()))
    assert not cycles, f"import cycles: {cycles}"


def test_the_import_graph_check_sees_function_level_imports(tmp_path):
    """The check is not vacuous: the graph has the known function-level edge from the CLI to the
    diagram command, and a cycle added on purpose is found."""
    G = import_graph()
    assert G.has_edge("runtime.cli", "runtime.voronoi.command")
    G.add_edge("runtime.voronoi.command", "runtime.cli")
    assert list(nx.simple_cycles(G))


def test_runtime_never_imports_precompute():
    G = import_graph()
    bad = [(a, b) for a, b in G.edges if a.startswith("runtime") and b.startswith("precompute")]
    assert not bad, bad


def test_every_subpackage_is_installed():
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(cfg["packages"])
    for pkg in PACKAGES:
        for init in (ROOT / pkg).rglob("__init__.py"):
            name = ".".join(("curvedvoronoi",) + init.parent.relative_to(ROOT).parts)
            assert name in listed, f"{name} missing from [tool.setuptools] packages in pyproject.toml"


@pytest.mark.parametrize("module", sorted(m for m in _modules() if m.startswith("runtime") and not m.endswith("__main__")))
def test_module_imports_in_isolation(module):
    """Each runtime module imports in a fresh interpreter (no order-dependent imports)."""
    r = subprocess.run([sys.executable, "-c", f"import curvedvoronoi.{module}"], cwd=ROOT,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]


def private_imports(modules=None) -> list[str]:
    """``from <module> import _name`` between modules of the package (the underscore marks a name
    private to its module: make it public where it is owned, or move it)."""
    bad = []
    for name, f in (modules or _modules()).items():
        for node in ast.walk(ast.parse(f.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith("curvedvoronoi")):
                bad += [f"{name}: {a.name}" for a in node.names if a.name.startswith("_") and a.name != "__name__"
                        and a.name != "__version__"]
    return bad


def test_no_private_name_crosses_a_module_border(tmp_path):
    assert not private_imports(), private_imports()
    f = tmp_path / "m.py"                        # the check is not vacuous
    f.write_text("from .sites.conic import _isqrt_exact\n")
    assert private_imports({"runtime.m": f}) == ["runtime.m: _isqrt_exact"]


#: how a module over ~400 lines states why it is one module (in its docstring)
LENGTH_REASON = re.compile(r"Length:|[Oo]ver 400 lines|[Ll]onger than 400 lines|hence its length")


def test_long_modules_say_why_in_their_docstring():
    long = {name: f for name, f in _modules().items() if len(f.read_text().splitlines()) > 420}
    silent = [name for name, f in long.items()
              if not LENGTH_REASON.search(ast.get_docstring(ast.parse(f.read_text())) or "")]
    assert not silent, f"modules over 400 lines without a reason in their docstring: {silent}"


def undefined_names(modules=None) -> list[str]:
    """Names used but never bound (pyflakes' UndefinedName / UndefinedLocal / UndefinedExport):
    an import removed from one place and not added where the name is used fails only when that
    line runs, often on a rare route (a refusal, a degenerate input)."""
    from pyflakes import checker, messages

    kinds = (messages.UndefinedName, messages.UndefinedLocal, messages.UndefinedExport)
    bad = []
    for name, f in (modules or _modules()).items():
        w = checker.Checker(ast.parse(f.read_text()), filename=str(f))
        bad += [f"{name}:{m.lineno}: {m.message % m.message_args}" for m in w.messages if isinstance(m, kinds)]
    return bad


def test_no_undefined_names(tmp_path):
    assert not undefined_names(), undefined_names()
    f = tmp_path / "m.py"                        # the check is not vacuous
    f.write_text("def f(c):\n    return sites_intersect(c, c)\n")
    assert undefined_names({"runtime.m": f}) == ["runtime.m:2: undefined name 'sites_intersect'"]


#: the construction of the diagram (sampling, triangulation, candidate vertices, polylines, local
#: updates); the verifier must reach none of them, directly or through other modules
CONSTRUCTION = {f"runtime.voronoi.{m}" for m in (
    "construction", "sampling", "sample_delaunay", "sample_walks", "apollonius_vertices", "conic_vertices",
    "edge_polylines", "vertex_emptiness", "near_degenerate", "cocircular", "collinear_points", "deletion",
    "site_arrays", "command")} | {f"runtime.segments.{m}" for m in (
    "construction", "vertices", "newton", "bisectors", "emptiness", "exact", "sampling", "contact_order", "edges", "loops",
    "command", "medial_axis", "walk_checks")}

#: the certificates: the curved-site verifier and the point/segment one
VERIFIERS = ("runtime.voronoi.verify", "runtime.segments.certificate")


def construction_reached_by_verifier(G=None) -> list[str]:
    """(verifier module, construction module) pairs where the first imports the second, directly or
    transitively (function-level imports included)."""
    G = import_graph() if G is None else G
    out = []
    for m in G.nodes:
        if m.startswith(VERIFIERS):
            for r in nx.descendants(G, m) & CONSTRUCTION:
                out.append(f"{m} -> {r}")
    return sorted(out)


def test_the_verifier_imports_nothing_of_the_construction():
    """The certificate is independent of the construction (runtime/voronoi/verify/certificate.py
    names the kernel both share: predicates, site geometries, the vertex proof, the frame)."""
    assert not construction_reached_by_verifier(), construction_reached_by_verifier()[:5]


def test_the_independence_check_sees_a_planted_import():
    G = import_graph()
    G.add_edge("runtime.voronoi.verify.strips", "runtime.voronoi.edge_polylines")
    assert "runtime.voronoi.verify.strips -> runtime.voronoi.edge_polylines" in construction_reached_by_verifier(G)
    G = import_graph()
    G.add_edge("runtime.voronoi.geometry", "runtime.voronoi.sampling")     # transitively, through the kernel
    assert any(p.endswith("-> runtime.voronoi.sampling") for p in construction_reached_by_verifier(G))
    G = import_graph()
    G.add_edge("runtime.segments.certificate_edges", "runtime.segments.bisectors")
    assert "runtime.segments.certificate_edges -> runtime.segments.bisectors" in construction_reached_by_verifier(G)
