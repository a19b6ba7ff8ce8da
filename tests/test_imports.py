"""nfdmodel's imports: one way (no circle, function-level imports included) and light (stdlib,
numpy and scipy only).

Every module of nfdmodel is parsed with ``ast``; each ``import`` / ``from ... import`` anywhere in
it (module level, inside functions, classes or ``try`` blocks) is an edge of the module graph.
``from . import name`` is an edge to the submodule ``name`` when nfdmodel has one, else to the
package itself (``nfdmodel/__init__.py``, which imports every module).
"""
import ast
import graphlib
import sys
from pathlib import Path

import pytest

PACKAGE = "nfdmodel"
ROOT = Path(__file__).resolve().parent.parent / PACKAGE
ALLOWED = {"numpy", "scipy"}           # besides the standard library
COMPILED = {"_native"}                 # nfdmodel._native, built from nfdmodel/_native.c


def module_sources(root: Path = ROOT) -> dict[str, str]:
    """{dotted module name: source} of every .py file of the package (not recursive: nfdmodel
    is flat; nfdmodel/lammps holds no Python)."""
    sources = {}
    for path in sorted(root.glob("*.py")):
        name = PACKAGE if path.stem == "__init__" else f"{PACKAGE}.{path.stem}"
        sources[name] = path.read_text(encoding="utf-8")
    return sources


def imports_of(module: str, source: str, modules: set[str]) -> tuple[set[str], set[str]]:
    """(package modules, other top-level names) that ``module`` imports anywhere in ``source``."""
    package = module if module == PACKAGE else module.rsplit(".", 1)[0]
    inside, outside = set(), set()

    def target(name: str) -> None:
        if name == PACKAGE or name.startswith(PACKAGE + "."):
            imported = ".".join(name.split(".")[:2])        # nfdmodel.x.y: the module nfdmodel.x
            if imported in modules:
                inside.add(imported)
            # else a compiled extension (nfdmodel._native): no source, imports nothing of nfdmodel
        else:
            outside.add(name.split(".")[0])

    for node in ast.walk(ast.parse(source, filename=module)):
        if isinstance(node, ast.Import):
            for alias in node.names:
                target(alias.name)
        elif isinstance(node, ast.ImportFrom):
            if node.level:                                  # relative: from . import x / from .x import y
                base = package.split(".")[:len(package.split(".")) - (node.level - 1)]
                origin = ".".join(base + ([node.module] if node.module else []))
            else:
                origin = node.module
            if origin == PACKAGE:                           # from . import x: the submodule x, if there is one
                for alias in node.names:
                    submodule = f"{PACKAGE}.{alias.name}"
                    target(submodule if submodule in modules or alias.name in COMPILED else PACKAGE)
            else:
                target(origin)
    inside.discard(module)
    return inside, outside


def import_graph(sources: dict[str, str]) -> tuple[dict[str, set[str]], dict[str, set[str]]]:
    """(module -> package modules it imports, module -> other top-level packages it imports)."""
    modules = set(sources)
    graph, external = {}, {}
    for module, source in sources.items():
        graph[module], external[module] = imports_of(module, source, modules)
    return graph, external


def cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One import circle of ``graph`` (its modules in order), or None."""
    try:
        tuple(graphlib.TopologicalSorter(graph).static_order())
    except graphlib.CycleError as error:
        return list(error.args[1])
    return None


def test_the_finder_sees_a_circle_closed_inside_a_function():
    sources = {"nfdmodel.a": "from .b import f\n",
               "nfdmodel.b": "def f():\n    from . import a\n    return a\n",
               "nfdmodel.c": "import numpy as np\nfrom nfdmodel.a import f\n"}
    graph, external = import_graph(sources)
    assert graph == {"nfdmodel.a": {"nfdmodel.b"}, "nfdmodel.b": {"nfdmodel.a"}, "nfdmodel.c": {"nfdmodel.a"}}
    assert set(cycle(graph)) == {"nfdmodel.a", "nfdmodel.b"}
    assert external["nfdmodel.c"] == {"numpy"}
    del graph["nfdmodel.b"]
    assert cycle(graph) is None


def test_nfdmodel_imports_run_one_way():
    graph, _ = import_graph(module_sources())
    assert len(graph) > 20 and f"{PACKAGE}.native" in graph
    found = cycle(graph)
    assert found is None, f"import circle: {' -> '.join(found)}"


def test_nfdmodel_imports_nothing_heavier_than_numpy_and_scipy():
    _, external = import_graph(module_sources())
    heavy = {module: sorted(names - ALLOWED - set(sys.stdlib_module_names))
             for module, names in external.items()}
    heavy = {module: names for module, names in heavy.items() if names}
    assert not heavy, f"nfdmodel imports beyond the standard library, numpy and scipy: {heavy}"


@pytest.mark.parametrize("module", ["nfdmodel.native", "nfdmodel.registry", "nfdmodel.collision"])
def test_the_law_modules_sit_below_the_registry(module):
    """native imports no law and no registry; the registry and collision import the laws."""
    graph, _ = import_graph(module_sources())
    laws = {f"{PACKAGE}.{name}" for name in ("hertz", "vz", "vz_table", "thornton", "walton_braun")}
    if module == "nfdmodel.native":
        assert not graph[module] & (laws | {"nfdmodel.registry", "nfdmodel.collision", PACKAGE})
    else:
        below = set()
        stack = [module]
        while stack:
            for name in graph[stack.pop()]:
                if name not in below:
                    below.add(name)
                    stack.append(name)
        assert laws <= below
