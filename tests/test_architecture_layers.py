"""The layers of docs/architecture.md and the "one of each" rule: every module the page names
exists; the site kinds are enumerated once (runtime/sites/kinds.py) and agree with every
geometry; Krawczyk's test and rational parsing live in their kernel modules only (an AST rule,
shown failing on planted copies), with the places not yet moved listed by name and reason."""
from __future__ import annotations

import ast
import doctest
import pathlib
import re

import pytest

from curvedvoronoi.runtime.predicates.circles import Circle
from curvedvoronoi.runtime.sites import kinds
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.sites.kinds import SiteKind
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry


def test_site_kinds_doctests():
    assert doctest.testmod(kinds).failed == 0


SITES = [
    (Circle(0, 0, 0), SiteKind.POINT),
    (Circle(1, 2, 4), SiteKind.CIRCLE),
    (Conic.from_coefficients(1, 0, 1, 0, 0, -4), SiteKind.CIRCLE),          # a circle given as a conic
    (Conic.ellipse(centre=(0, 0), axes=(3, 1)), SiteKind.ELLIPSE),
    (Conic.hyperbola(centre=(0, 0), axes=(1, 2)), SiteKind.HYPERBOLA),
    (Conic.parabola(vertex=(0, 0), p=1), SiteKind.PARABOLA),
]


@pytest.mark.parametrize("site, kind", SITES, ids=[k.label + str(i) for i, (_, k) in enumerate(SITES)])
def test_every_geometry_spells_its_kind_from_the_enumeration(site, kind):
    g = site_geometry(site)
    assert g.kind == kind.label and g.site_kind is kind
    assert g.bounded == kind.bounded == all(abs(v) < float("inf") for v in g.bounding_box())


def test_kind_codes_and_labels():
    # the codes the verifier's flat site table stores (0 point, 1 circle, 2 ellipse, 3 hyperbola,
    # 4 parabola) must not move: arrays written with them compare against the members
    assert [int(k) for k in SiteKind][:5] == [0, 1, 2, 3, 4]
    assert [k.label for k in SiteKind] == ["point", "circle", "ellipse", "hyperbola", "parabola", "segment", "arc",
                                           "elliptic_arc"]
    assert all(SiteKind.of(k.label) is k and SiteKind.of(int(k)) is k for k in SiteKind)
    assert [k.label for k in SiteKind if k.circular] == ["point", "circle"]
    assert [k.label for k in SiteKind if not k.bounded] == ["hyperbola", "parabola"]
    with pytest.raises(ValueError, match="unknown site kind 'line'"):
        SiteKind.of("line")


def test_segment_diagrams_store_the_enumeration_codes():
    # the elementary sites of a segment diagram (thesis §2.2) carry SiteKind codes, in the order
    # point < segment < arc < elliptic arc that ``kind >= ARC`` (the curved pieces) relies on
    from curvedvoronoi.runtime.segments import certificate_sites, elementary
    from curvedvoronoi.runtime.segments.elementary import decompose
    from curvedvoronoi.runtime.sites.arc import Arc
    from curvedvoronoi.runtime.sites.segment import Segment

    for mod in (elementary, certificate_sites):
        assert (mod.POINT, mod.SEGMENT, mod.ARC, mod.ELLIPSE) == (
            SiteKind.POINT, SiteKind.SEGMENT, SiteKind.ARC, SiteKind.ELLIPTIC_ARC)
        # plain ints: numpy compares an enum member through a failed metaclass lookup per call
        assert {type(k) for k in (mod.POINT, mod.SEGMENT, mod.ARC, mod.ELLIPSE)} == {int}
    assert SiteKind.POINT < SiteKind.SEGMENT < SiteKind.ARC < SiteKind.ELLIPTIC_ARC
    E = decompose([Segment((0, 0), (4, 0)), Arc.circular((0, 5), 2, 0, 90)])
    assert sorted(SiteKind(int(k)).label for k in E.kind) == ["arc", "point", "point", "point", "point", "segment"]
    src = (ROOT / "runtime" / "segments").glob("*.py")
    bare = [p.name for p in src if re.search(r"^_?POINT\b.*=\s*0\b", p.read_text(), re.M)]
    assert bare == [], f"site kinds as bare integers in {bare}: import them from runtime.sites.kinds"


# ----------------------------------------------------------------------------- the drawing

ROOT = pathlib.Path(__file__).resolve().parents[1]
ARCHITECTURE = ROOT / "docs" / "architecture.md"
TOP = ("runtime", "precompute", "generated", "curvedvoronoi", "tests", "bench", "docs")
PY = re.compile(r"(?<![\w/.])([\w/]+\.py)(?:::(\w+))?")


def _resolve(path: str, directory: str | None) -> str:
    if "/" in path:
        return path if path.split("/")[0] in TOP else f"runtime/{path}"
    return f"{directory}{path}" if directory else f"<no directory>/{path}"


def documented_paths(text: str) -> list[tuple[str, str | None]]:
    """(file, name or None) for every module the page names: in the fenced drawing, a line
    starting with ``dir/`` sets the directory of the bare file names after it (a ``══`` rule
    clears it); elsewhere, every backticked path (relative to ``runtime/`` unless it starts with a
    top-level folder), with ``path.py::name`` naming a function or class of the module."""
    out = []
    fenced, directory = False, None
    for line in text.splitlines():
        if line.startswith("```"):
            fenced, directory = not fenced, None
            continue
        if fenced:
            m = re.match(r"^([\w/]+/)\s", line)
            if m:
                directory = m.group(1)
            elif line.startswith("══"):
                directory = None
            out += [(_resolve(p, directory), None) for p, _ in PY.findall(line)]
        else:
            for tick in re.findall(r"`([^`]+)`", line):
                m = PY.fullmatch(tick)
                if m and "/" in m.group(1):
                    out.append((_resolve(m.group(1), None), m.group(2)))
    return out


def missing(paths) -> list[str]:
    bad = []
    for path, name in paths:
        f = ROOT / path
        if not f.is_file():
            bad.append(path)
        elif name is not None:
            tree = ast.parse(f.read_text())
            defined = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
            if name not in defined:
                bad.append(f"{path}::{name}")
    return bad


def test_every_module_the_architecture_names_exists():
    paths = documented_paths(ARCHITECTURE.read_text())
    assert len(paths) > 150                      # the drawing is read, not skipped
    assert ("runtime/segments/certificate_hull.py", None) in paths
    assert ("runtime/voronoi/conic_geometry.py", "site_geometry") in paths
    assert not missing(paths), missing(paths)


def test_the_drawing_check_sees_a_missing_module():
    text = ("```\nruntime/sites/       rationals.py · kinds.py\n                     nowhere.py\n"
            "══ layer ══\nruntime/voronoi/     geometry.py\n```\n"
            "See `voronoi/vertex.py::certify_vertex` and `sites/reader.py::no_such_function`.\n")
    assert missing(documented_paths(text)) == ["runtime/sites/nowhere.py", "runtime/sites/reader.py::no_such_function"]


# ----------------------------------------------------------------------------- one of each

#: the one module that decides Krawczyk's test, and what a Krawczyk-named function must call
KRAWCZYK_KERNEL = "runtime.certify.interval_newton"
KRAWCZYK_CALLS = {"krawczyk_image", "krawczyk_inflation", "float_krawczyk_test"}
#: the one rational parser, and what a parser-named function must call
RATIONALS = "runtime.sites.rationals"
RATIONAL_CALLS = {"to_fraction", "parse_rational"}
PARSER_NAME = re.compile(r"^(to_|as_|parse_)?(frac|fraction|fmpq|rational|number|q)$")

#: places that still break the rule, each with why (none left; a new one fails the test)
NOT_YET_MOVED: dict = {}


def _runtime_modules() -> dict[str, pathlib.Path]:
    mods = {}
    for f in (ROOT / "runtime").rglob("*.py"):
        parts = list(f.relative_to(ROOT).with_suffix("").parts)
        mods[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = f
    return mods


def _called(node) -> str | None:
    f = node.func if isinstance(node, ast.Call) else None
    return f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else None


def _contraction_matrix(node) -> bool:
    """I − Y·J: an identity (eye / identity, possibly indexed) minus a product."""
    if not (isinstance(node, ast.BinOp) and isinstance(node.op, ast.Sub)):
        return False
    left = node.left.value if isinstance(node.left, ast.Subscript) else node.left
    right = node.right
    product = (isinstance(right, ast.BinOp) and isinstance(right.op, (ast.Mult, ast.MatMult))) or \
        _called(right) in ("einsum", "dot", "matmul")
    return _called(left) in ("eye", "identity", "_identity") and product


def one_of_each_findings(modules=None) -> list[str]:
    """``module:function: what`` for each function outside the kernel that implements Krawczyk's
    test (named like it without calling the kernel's test, or forming I − Y·J) or parses
    rationals (named like a parser without calling :func:`runtime.sites.rationals.to_fraction`)."""
    out = set()
    for name, f in (modules or _runtime_modules()).items():
        for fn in ast.walk(ast.parse(f.read_text())):
            if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            inner = list(ast.walk(fn))
            used = {n.id for n in inner if isinstance(n, ast.Name)}
            used |= {n.attr for n in inner if isinstance(n, ast.Attribute)}
            if name != KRAWCZYK_KERNEL:
                if "krawczyk" in fn.name.lower() and not used & KRAWCZYK_CALLS:
                    out.add(f"{name}:{fn.name}: a Krawczyk test of its own")
                if any(_contraction_matrix(n) for n in inner):
                    out.add(f"{name}:{fn.name}: forms I - Y.J")
            if name != RATIONALS and PARSER_NAME.match(fn.name.strip("_").lower()) and not used & RATIONAL_CALLS:
                out.add(f"{name}:{fn.name}: a rational parser of its own")
    return sorted(out)


def test_krawczyk_and_rational_parsing_live_in_the_kernel_only():
    found = one_of_each_findings()
    assert not set(found) - set(NOT_YET_MOVED), sorted(set(found) - set(NOT_YET_MOVED))
    stale = set(NOT_YET_MOVED) - set(found)
    assert not stale, f"moved to the kernel: remove from NOT_YET_MOVED: {sorted(stale)}"


def test_the_rule_fails_on_planted_copies(tmp_path):
    """A copy of the kernel's modules elsewhere, and a hand-written parser and Krawczyk test, are
    found; a wrapper that calls the kernel is not."""
    planted = tmp_path / "planted.py"
    planted.write_text(
        "from fractions import Fraction\nimport numpy as np\n\n"
        "def _frac(v):\n    return Fraction(v)\n\n"
        "def krawczyk_box(Y, J, F, r):\n    return (np.abs(np.eye(2)[None] - Y @ J) @ r < r).all()\n\n"
        "def _q(v):\n    return to_fraction(v, 'v')\n\n"
        "def prove(Y, J):\n    return float_krawczyk_test(0, np.eye(2) - np.einsum('ij,jk->ik', Y, J), 1)\n")
    copies = {"runtime.voronoi.kernel_copy": ROOT / "runtime/certify/interval_newton.py",
              "runtime.voronoi.rationals_copy": ROOT / "runtime/sites/rationals.py",
              "runtime.voronoi.planted": planted}
    found = one_of_each_findings(copies)
    assert found == [
        "runtime.voronoi.kernel_copy:float_contraction_bound: forms I - Y.J",
        "runtime.voronoi.kernel_copy:float_krawczyk_test: a Krawczyk test of its own",
        "runtime.voronoi.kernel_copy:krawczyk_image: a Krawczyk test of its own",
        "runtime.voronoi.kernel_copy:krawczyk_image: forms I - Y.J",
        "runtime.voronoi.planted:_frac: a rational parser of its own",
        "runtime.voronoi.planted:krawczyk_box: a Krawczyk test of its own",
        "runtime.voronoi.planted:krawczyk_box: forms I - Y.J",
        "runtime.voronoi.planted:prove: forms I - Y.J",
        "runtime.voronoi.rationals_copy:to_fraction: a rational parser of its own",
    ]
    # the real modules pass: the kernel may do what its copies may not
    assert not one_of_each_findings({KRAWCZYK_KERNEL: copies["runtime.voronoi.kernel_copy"],
                                     RATIONALS: copies["runtime.voronoi.rationals_copy"]})


# ----------------------------------------------------------------------------- one generator per scene

#: the random scenes drawn in tests/scenes.py, which tests and benchmarks import
SCENES = ("random_disjoint_circles", "random_ellipses", "random_segments", "random_points_off", "clustered_circles")


def scene_copies(files) -> list[tuple[str, str]]:
    """(file name, generator) for each definition of a scene generator of tests/scenes.py outside it."""
    return [(f.name, node.name) for f in files for node in ast.walk(ast.parse(f.read_text()))
            if isinstance(node, ast.FunctionDef) and node.name in SCENES]


def test_tests_and_benchmarks_draw_each_scene_from_one_generator(tmp_path):
    files = [f for d in ("tests", "bench") for f in (ROOT / d).rglob("*.py") if f.name != "scenes.py"]
    assert len(files) > 50 and not scene_copies(files), scene_copies(files)
    planted = tmp_path / "bench_planted.py"                 # the check is not vacuous
    planted.write_text("import scenes\n\ndef random_ellipses(n, seed):\n    return scenes.random_ellipses(n, seed)\n")
    assert scene_copies([planted]) == [("bench_planted.py", "random_ellipses")]


# ----------------------------------------------------------------------------- the layers, tested

LAYER_RULE = re.compile(r"^══ layer (\d+)")

#: result types whose methods import the I/O layer at call time (``d.plot()``, ``d.cells()``): a
#: facade; their top-level imports obey the layers like every module's
FACADES = {"runtime.voronoi.structure"}

#: imports from a lower layer into a higher one that stay, each with its reason (the test fails
#: when one is no longer made, so the list cannot go stale)
UPWARD_IMPORTS = {
    ("runtime.sites.reader", "runtime.algebra.polyalg"):
        "the reader refuses a conic whose precomputed offset (App. B) overflows floats: an input check "
        "that evaluates the kernel's offset polynomial, at call time",
}


def module_layers(text: str) -> dict[str, int]:
    """Dotted module name -> layer number, from the fenced drawing: a ``══ layer N`` rule starts
    layer N; the modules named after it (directory lines as in :func:`documented_paths`) are in it."""
    out, fenced, directory, layer = {}, False, None, None
    for line in text.splitlines():
        if line.startswith("```"):
            fenced, directory = not fenced, None
            continue
        if not fenced:
            continue
        m = LAYER_RULE.match(line)
        if m:
            layer, directory = int(m.group(1)), None
            continue
        m = re.match(r"^([\w/]+/)\s", line)
        if m:
            directory = m.group(1)
        for p, _ in PY.findall(line):
            path = _resolve(p, directory)
            if layer is not None and path.startswith("runtime/"):
                out[path[:-3].replace("/", ".")] = layer
    return out


def _top_level_imports(name: str, f: pathlib.Path) -> set[str]:
    """What module ``name`` imports outside functions and outside ``if TYPE_CHECKING:``."""
    pkg = name.split(".")[:-1]
    out = set()
    tree = ast.parse(f.read_text())
    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and node.level:
            base = ".".join(pkg[:len(pkg) - node.level + 1] + ([node.module] if node.module else []))
            out |= {base} | {f"{base}.{a.name}" for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = (node.module or "").removeprefix("curvedvoronoi.")
            out |= {base} | {f"{base}.{a.name}" for a in node.names}
    return out


def upward_imports(G, layers: dict[str, int]) -> set[tuple[str, str]]:
    """(importer, imported) for every import of a module of a higher layer than the importer's
    (``G``: the import graph of tests/test_architecture.py, function-level imports included;
    facades count with their top-level imports only).  Direct imports suffice: every module has
    a layer, so a chain that climbs has a step that climbs."""
    out = set()
    for m, r in G.edges:
        if m in layers and r in layers and layers[r] > layers[m]:
            if m in FACADES and r not in _top_level_imports(m, ROOT / (m.replace(".", "/") + ".py")):
                continue
            out.add((m, r))
    return out


def _import_graph():
    import sys

    sys.path.insert(0, str(ROOT / "tests"))
    from test_architecture import import_graph

    return import_graph()


def test_no_module_imports_a_higher_layer():
    layers = module_layers(ARCHITECTURE.read_text())
    assert set(layers.values()) == {0, 1, 2, 3}
    found = upward_imports(_import_graph(), layers)
    assert not found - set(UPWARD_IMPORTS), sorted(found - set(UPWARD_IMPORTS))
    assert not set(UPWARD_IMPORTS) - found, f"no longer made: remove {sorted(set(UPWARD_IMPORTS) - found)}"


def test_every_runtime_module_has_a_layer():
    layers = module_layers(ARCHITECTURE.read_text())
    modules = {".".join(f.relative_to(ROOT).with_suffix("").parts) for f in (ROOT / "runtime").rglob("*.py")
               if f.name not in ("__init__.py", "__main__.py")}
    assert not modules - set(layers), sorted(modules - set(layers))


def test_the_layer_check_sees_a_planted_upward_import():
    layers = module_layers(ARCHITECTURE.read_text())
    G = _import_graph()
    G.add_edge("runtime.sites.conic", "runtime.voronoi.construction")
    G.add_edge("runtime.certify.foot", "runtime.voronoi.verify.certificate")
    found = upward_imports(G, layers)
    assert {("runtime.sites.conic", "runtime.voronoi.construction"),
            ("runtime.certify.foot", "runtime.voronoi.verify.certificate")} <= found
    # a facade's call-time import is not counted, a top-level one would be
    assert ("runtime.voronoi.structure", "runtime.voronoi.plot") not in found
    assert ("runtime.voronoi.structure", "runtime.voronoi.plot") in G.edges
