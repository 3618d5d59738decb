"""The import graph of core/ and addon/: no cycles, and the packages of each import only downwards.

Every module is parsed (never imported), and every import statement counts,
the deferred ones inside functions included. Relative imports are resolved
against the importing module's package; ``from package import name`` is an
import of the submodule ``package.name`` when there is one, else of the
package itself.
"""

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
TOP_PACKAGES = ("core", "addon")

# core's layers, lowest first: a module may import modules of its own layer or of a lower one, never of a higher
# one. Within a package (one layer) the cycle test keeps the order. The base holds what every stage shares.
CORE_LAYERS = [
    ("base", {"core.errors", "core.version", "core.params", "core.progress", "core.colour", "core.results",
              "core.heap", "core.workers", "core.tuning", "core.lazy", "core.resample"}),
    ("lighting", {"core.lighting"}),
    ("files", {"core.files"}),
    ("analysis", {"core.analysis"}),
    ("motion", {"core.motion"}),
    ("strokes", {"core.strokes"}),
    ("measures", {"core.measures"}),
    ("methods", {"core.methods"}),
    ("sequence", {"core.sequence"}),
    ("farm", {"core.farm"}),
    ("surface", {"core.surface"}),
    ("figures", {"core.figures"}),
    ("api", {"core.api"}),
    ("objects", {"core.objects"}),
    ("evaluation", {"core.evaluation"}),
    ("entry", {"core", "core.cli", "core.__main__", "core.blender"}),
]

# addon's layers, lowest first, by the same rule. The base is what every part shares (pure helpers, the painter's
# libraries, the long operators' modal skeleton, the command lines' helpers); the scene builders come next; the settings sit above them because their update callbacks change the
# canvas and lights; the operators of painting and of the comparison read the settings; the relit film (film)
# renders with the comparison's settings; the Grease Pencil round trip (strokes) stages the canvas again; the
# sidebar names them all;
# Paint Object (objects) takes the painter's settings of painting; the command line and the package's
# register/unregister are the entry points.
ADDON_LAYERS = [
    ("base", {"addon.values", "addon.dependencies", "addon.modal_job", "addon.command_line"}),
    ("scene", {"addon.scene"}),
    ("settings", {"addon.settings"}),
    ("painting", {"addon.painting"}),
    ("objects", {"addon.objects"}),
    ("comparison", {"addon.comparison"}),
    ("film", {"addon.film"}),
    ("strokes", {"addon.strokes"}),
    ("panels", {"addon.panels"}),
    ("entry", {"addon", "addon.cli_command"}),
]


def module_name(path: Path) -> str:
    """core/files/reading.py -> core.files.reading; core/files/__init__.py -> core.files."""
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def all_modules() -> dict:
    """{module name: path} of every .py file under core/ and addon/."""
    found = {}
    for top in TOP_PACKAGES:
        for path in sorted((ROOT / top).rglob("*.py")):
            found[module_name(path)] = path
    return found


def imports_of(name: str, path: Path, known) -> set:
    """The modules among ``known`` that module ``name`` (file ``path``) imports anywhere in its body."""
    is_package = path.name == "__init__.py"
    package = name.split(".") if is_package else name.split(".")[:-1]
    targets = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), filename=str(path))):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name in known:
                    targets.add(alias.name)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                # The extension's root package (the repository root) is the empty prefix: `from .. import core`
                # in addon/x.py names core.
                base = package[:len(package) - (node.level - 1)] if node.level > 1 else package
                assert node.level - 1 <= len(package), f"{path}: relative import above the extension"
                base = base + (node.module.split(".") if node.module else [])
            else:
                base = node.module.split(".")
            base_name = ".".join(base)
            for alias in node.names:
                sub = f"{base_name}.{alias.name}" if base_name else alias.name
                if sub in known:
                    targets.add(sub)
                elif base_name in known:
                    targets.add(base_name)
    targets.discard(name)
    return targets


def import_graph() -> dict:
    known = all_modules()
    return {name: imports_of(name, path, known) for name, path in known.items()}


def cycles(graph: dict) -> list:
    """Strongly connected components of more than one module (Tarjan), each sorted."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def layer_of(module: str, layers=CORE_LAYERS) -> int:
    """Index in ``layers`` of a module: its own entry, else its package's (a top package holds only itself)."""
    tops = set(TOP_PACKAGES)
    for exact in (True, False):
        for i, (_, members) in enumerate(layers):
            for member in members:
                if module == member or (not exact and member not in tops and module.startswith(member + ".")):
                    return i
    raise AssertionError(f"{module} belongs to no layer")


def test_graph_is_read():
    graph = import_graph()
    assert "core.methods.registry" in graph and "addon.painting.ops_paint" in graph
    assert "core.methods.huang11" in graph["core.methods.registry"]
    assert "core.files.reading" in graph["core.strokes.brush"]  # a deferred import counts
    assert "core" in graph["addon.painting.ops_paint"]  # `from ... import core`, resolved
    assert "addon.scene.canvas_plane" in graph["addon.settings.properties"]  # `from ..scene import canvas_plane`, deferred


def test_a_method_is_reached_through_the_registry_alone():
    """No module of core or addon outside core/methods imports a method's own module: a still, a shot's frame and a
    texture's island are painted through ``core.methods.registry``."""
    graph = import_graph()
    methods = {"core.methods.huang11", "core.methods.hertzmann98"}
    assert methods <= set(graph)
    reaching = {module: sorted(graph[module] & methods) for module in graph
                if not module.startswith("core.methods") and graph[module] & methods}
    assert reaching == {}


def test_no_import_cycles():
    found = cycles(import_graph())
    assert not found, "import cycles: " + "; ".join(" <-> ".join(c) for c in found)


def test_cycle_finder_finds_a_deferred_cycle(tmp_path):
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert cycles(graph) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_relative_imports_are_resolved(tmp_path):
    pkg = tmp_path / "core" / "stage"
    pkg.mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    source = pkg / "mod.py"
    source.write_text("from . import other\nfrom ..base import thing\n\ndef f():\n    from .deep import x\n")
    known = {"core", "core.base", "core.stage", "core.stage.other", "core.stage.deep"}
    assert imports_of("core.stage.mod", source, known) == {"core.stage.other", "core.base", "core.stage.deep"}


@pytest.mark.parametrize("module", sorted(m for m in all_modules() if m == "core" or m.startswith("core.")))
def test_core_imports_run_down_the_layers(module):
    graph = import_graph()
    mine = layer_of(module)
    upward = [t for t in sorted(graph[module]) if t.startswith("core") and layer_of(t) > mine]
    assert not upward, f"{module} ({CORE_LAYERS[mine][0]}) imports higher layers: {upward}"


@pytest.mark.parametrize("module", sorted(m for m in all_modules() if m == "addon" or m.startswith("addon.")))
def test_addon_imports_run_down_the_layers(module):
    graph = import_graph()
    mine = layer_of(module, ADDON_LAYERS)
    upward = [t for t in sorted(graph[module]) if t.startswith("addon") and layer_of(t, ADDON_LAYERS) > mine]
    assert not upward, f"{module} ({ADDON_LAYERS[mine][0]}) imports higher layers: {upward}"


def test_core_never_imports_addon_or_bpy():
    for name, path in all_modules().items():
        if name.startswith("core"):
            tree = ast.parse(path.read_text(encoding="utf-8"))
            names = {a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
            names |= {(n.module or "").split(".")[0] for n in ast.walk(tree)
                      if isinstance(n, ast.ImportFrom) and n.level == 0}
            assert not names & {"bpy", "addon"}, f"{name} imports {names & {'bpy', 'addon'}}"


def test_the_architecture_names_these_layers_in_this_order():
    """docs/ARCHITECTURE.md's rules 1 and 7 name the layers core and addon are held to here, lowest first, and
    addon's base modules: a package added to one and not the other fails here."""
    text = " ".join((ROOT / "docs" / "ARCHITECTURE.md").read_text(encoding="utf-8").split())
    core_layers = re.search(r"Lowest first: (.*?) \(cli", text).group(1)
    assert [name.strip() for name in core_layers.split(",")] == [name for name, _ in CORE_LAYERS]
    addon_layers = re.search(r"lowest first: (.*?) \(`cli_command`", text).group(1)
    base = re.search(r"base \((.*?)\)", addon_layers).group(1)
    assert {"addon." + name.strip(" `") for name in base.split(",")} == ADDON_LAYERS[0][1]
    names = re.sub(r"\([^)]*\)", "", addon_layers).split(",")
    assert [name.strip(" `/") for name in names] == [name for name, _ in ADDON_LAYERS]
