"""calib's layers: every import runs down the layer order, and no modules import each other in a circle.

The layers, lowest first (a module may import its own layer and those below it):

    0  nfdmodel, calib.output, calib.optional, calib.lammps_plugin, meshes
                                                        (the runtime laws, where results go, extras, the plugin's build)
    1  calib.fe, calib.sweep                            (the FE; the resumable runner)
    2  calib.fit                                        (the calibration recipe, the fits, the tables)
    3  calib.report                                     (the writers of result folders)
    4  calib.studies                                    (studies; they may use report's writers)
    5  calib.scenes                                     (scene files, their plan and run)
    6  calib.commands                                   (one module per ``nfdcal`` sub-command)
    7  calib.cli                                        (``nfdcal``)

report sits below studies: a study may use report's writers and index helpers (its own section of
results/README.md among them), report imports no study; the command ``nfdcal results-readme`` lists
the sections in their order. A command may call a study's entry point; what fit, report or a
command's library part reuses lives on a library layer.

Every module of calib and meshes is parsed with ``ast``; each ``import`` / ``from ... import``
anywhere in it (module level, inside functions, classes or ``try`` blocks) is an edge.
``from calib.fit import calibration`` is an edge to the module ``calib.fit.calibration`` when there
is one, else to the package ``calib.fit`` (its ``__init__.py``).
"""
import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("calib", "meshes")
PACKAGE = "calib"      # calib/__init__.py itself: a docstring, on the lowest layer
LAYERS = (
    ("nfdmodel", "calib.output", "calib.optional", "calib.interrupt", "calib.lammps_plugin", "meshes", PACKAGE),
    ("calib.fe", "calib.sweep"),
    ("calib.fit",),
    ("calib.report",),
    ("calib.studies",),
    ("calib.scenes",),
    ("calib.commands",),
    ("calib.cli", "calib.cli_readme"),
)


def module_sources(root: Path = ROOT) -> dict[str, str]:
    """{dotted module name: source} of every .py file under calib/ and meshes/."""
    sources = {}
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = list(path.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            sources[".".join(parts)] = path.read_text(encoding="utf-8")
    return sources


def imports_of(source: str, modules: set[str], filename: str = "<module>") -> set[str]:
    """The modules of ``modules`` that ``source`` imports anywhere, and nfdmodel (as one name)."""
    found = set()

    def target(name: str) -> None:
        if name == "nfdmodel" or name.startswith("nfdmodel."):
            found.add("nfdmodel")
            return
        while name and name not in modules:        # calib.fit.calibration.X: the module it is in
            name = name.rpartition(".")[0]
        if name:
            found.add(name)

    for node in ast.walk(ast.parse(source, filename=filename)):
        if isinstance(node, ast.Import):
            for alias in node.names:
                target(alias.name)
        elif isinstance(node, ast.ImportFrom):
            assert node.level == 0, f"{filename}: a relative import; calib and meshes import by full name"
            for alias in node.names:
                submodule = f"{node.module}.{alias.name}"
                target(submodule if submodule in modules else node.module)
    return found


def import_graph(sources: dict[str, str]) -> dict[str, set[str]]:
    """module -> the modules of calib and meshes (and nfdmodel) it imports."""
    modules = set(sources)
    return {module: imports_of(source, modules, module) - {module} for module, source in sources.items()}


def layer(module: str) -> int:
    """The layer of ``module``: that of the longest name in LAYERS it starts with."""
    best, found = -1, None
    for index, names in enumerate(LAYERS):
        for name in names:
            inside = module == name or (name != PACKAGE and module.startswith(name + "."))
            if inside and len(name) > best:
                best, found = len(name), index
    assert found is not None, f"{module} is on no layer: add it to LAYERS"
    return found


def arrows_up(graph: dict[str, set[str]]) -> list[str]:
    """Every import of a module on a higher layer, as 'importer -> imported'."""
    return sorted(f"{module} -> {name}" for module, names in graph.items() for name in names
                  if layer(name) > layer(module))


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every import circle of ``graph``: its strongly connected components of more than one module
    (Tarjan), each sorted."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(node):
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for other in graph.get(node, ()):
            if other not in index:
                visit(other)
                low[node] = min(low[node], low[other])
            elif other in on_stack:
                low[node] = min(low[node], index[other])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return sorted(found)


def test_the_finder_sees_imports_inside_functions():
    sources = {"calib.fit.a": "def f():\n    from calib.studies.b import g\n    return g\n",
               "calib.studies.b": "from calib.fit import a\nimport nfdmodel.vz\n",
               "calib.studies": "",
               "calib.scenes.c": "import calib.studies\n"}
    graph = import_graph(sources)
    assert graph == {"calib.fit.a": {"calib.studies.b"}, "calib.studies.b": {"calib.fit.a", "nfdmodel"},
                     "calib.studies": set(), "calib.scenes.c": {"calib.studies"}}
    assert arrows_up(graph) == ["calib.fit.a -> calib.studies.b"]
    assert circles(graph) == [["calib.fit.a", "calib.studies.b"]]
    graph["calib.fit.a"] = set()
    assert circles(graph) == [] and arrows_up(graph) == []


def test_a_new_top_level_module_is_on_no_layer_until_placed():
    assert layer("calib") == 0 and layer("calib.lammps_plugin") == 0 and layer("calib.fit.measured.data") == 2
    with pytest.raises(AssertionError, match="on no layer"):
        layer("calib.elsewhere")


def test_every_module_is_on_a_layer():
    sources = module_sources()
    assert len(sources) > 100 and "calib.fit.calibration" in sources
    for module in sources:
        layer(module)


def test_no_import_runs_up_the_layers():
    up = arrows_up(import_graph(module_sources()))
    assert not up, "imports that run up the layer order:\n" + "\n".join(up)


def test_no_import_circle():
    found = circles(import_graph(module_sources()))
    assert not found, "import circles:\n" + "\n".join(", ".join(c) for c in found)
