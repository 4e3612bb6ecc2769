"""The package's layers (design.md, "Architecture"), enforced on its import graph.

Every ``.py`` under ``symcable/`` is parsed with :mod:`ast`; every import statement counts,
at module level or inside a function (a lazy import is still a dependency, and still closes
a cycle at run time). Relative imports are resolved; ``from . import x`` points to the
submodule ``x`` when there is one, else to the package; importing ``a.b.c`` also depends on
the package ``a.b`` (its ``__init__`` runs first) unless the importer lives inside it.

Layers, lowest first; a module may import modules of its own layer or of a lower one:

0. ``errors``, ``limits``, ``progress``, ``analytic``, ``linalg``, ``data``: leaves that know
   no scene, model or solver
1. ``scene`` (what is modelled) and ``mechanism`` (the Mechanism every formulation produces,
   its assembly, the Functions derived from it and generated C): neither knows the other
2. ``models``: the formulations (never a solver)
4. ``results``, ``plotting``: what comes out (results import plotting lazily; plotting
   imports no solver)
5. ``solvers``: how it is solved
6. ``api``, ``sweep``, ``cli`` and the package's ``__init__``: orchestration and entry points

No formulation compiles anything (the planar DynamicModel is a plain record; its
Mechanism's Functions come from ``mechanism.functions``).

Beyond the layers there is no import cycle at all, not even between two modules of one
layer (two modules that import each other).

A module missing from :data:`LAYERS` fails the test: give it a layer there.
"""
from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = "symcable"

#: module or package (with everything inside it) -> layer; ``symcable`` itself is only the
#: package's ``__init__``
LAYERS = {
    "symcable.errors": 0,
    "symcable.limits": 0,
    "symcable.progress": 0,
    "symcable.analytic": 0,
    "symcable.linalg": 0,
    "symcable.data": 0,
    "symcable.scene": 1,
    "symcable.mechanism": 1,
    "symcable.models": 2,
    "symcable.results": 4,
    "symcable.plotting": 4,
    "symcable.solvers": 5,
    "symcable.api": 6,
    "symcable.sweep": 6,
    "symcable.cli": 6,
    "symcable.__main__": 6,
    "symcable": 6,
}

#: Graph: importer -> {imported module: [where, ...]}, where = "path:line" (+ a note)
Graph = dict


# --------------------------------------------------------------------------- the graph

def find_modules(src: Path, package: str) -> dict:
    """``{dotted module name: path}`` of every ``.py`` file of the package under ``src``
    (a package's ``__init__.py`` is the package's own name)."""
    modules = {}
    for path in sorted((src / package).rglob("*.py")):
        parts = list(path.relative_to(src).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        modules[".".join(parts)] = path
    return modules


def _is_package(name: str, modules: dict) -> bool:
    return modules[name].name == "__init__.py"


def _resolve_from(importer: str, level: int, module: str | None, modules: dict) -> str:
    """Absolute name of the module part of ``from <dots><module> import ...``."""
    if level == 0:
        return module or ""
    base = importer.split(".")
    if not _is_package(importer, modules):
        base = base[:-1]  # a plain module's relative imports start from its package
    if level > 1:
        base = base[:-(level - 1)]
    return ".".join(base + ([module] if module else []))


def _known(name: str, modules: dict) -> str | None:
    """The longest prefix of ``name`` that is a module of the package (None: not ours)."""
    parts = name.split(".")
    while parts:
        candidate = ".".join(parts)
        if candidate in modules:
            return candidate
        parts.pop()
    return None


def _targets(importer: str, node: ast.AST, modules: dict) -> list:
    """The package's modules that one import statement names."""
    if isinstance(node, ast.Import):
        names = [alias.name for alias in node.names]
    else:
        base = _resolve_from(importer, node.level, node.module, modules)
        names = [base if alias.name == "*" else f"{base}.{alias.name}" for alias in node.names]
        # ``from pkg import name``: the submodule pkg.name if there is one, else pkg itself
        names = [n if n in modules else base for n in names]
    return [t for t in (_known(n, modules) for n in names) if t is not None]


def import_graph(src: Path = ROOT, package: str = PACKAGE) -> Graph:
    """The import graph of the package under ``src``, with where each edge comes from."""
    modules = find_modules(src, package)
    graph: Graph = {name: {} for name in modules}
    for name, path in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        where = f"{path.relative_to(src).as_posix()}"
        for node in ast.walk(tree):
            if not isinstance(node, (ast.Import, ast.ImportFrom)):
                continue
            for target in _targets(name, node, modules):
                edges = [(target, f"{where}:{node.lineno}")]
                # importing a.b.c runs a.b's __init__ first, unless the importer is inside a.b
                parts = target.split(".")
                for i in range(len(parts) - 1, 0, -1):
                    parent = ".".join(parts[:i])
                    if name == parent or name.startswith(parent + "."):
                        break
                    edges.append((parent, f"{where}:{node.lineno} (package of {target})"))
                for t, w in edges:
                    if t != name and w not in graph[name].setdefault(t, []):
                        graph[name][t].append(w)
    return graph


# --------------------------------------------------------------------------- the checks

def layer_of(module: str, layers: dict) -> int | None:
    """The layer of ``module``: its own entry, else that of the nearest enclosing package
    with an entry (the top-level package's entry covers only its ``__init__``)."""
    parts = module.split(".")
    for i in range(len(parts), 0, -1):
        key = ".".join(parts[:i])
        if key in layers and (i == len(parts) or i > 1):
            return layers[key]
    return None


def find_cycle(graph: Graph) -> list | None:
    """One import cycle ``[m0, m1, ..., m0]`` of ``graph``, or None when it has none."""
    state: dict = {}  # module -> 1 on the current path, 2 done
    path: list = []

    def visit(m):
        state[m] = 1
        path.append(m)
        for t in sorted(graph.get(m, {})):
            if state.get(t) == 1:
                return path[path.index(t):] + [t]
            if t not in state:
                found = visit(t)
                if found:
                    return found
        path.pop()
        state[m] = 2
        return None

    for m in sorted(graph):
        if m not in state:
            found = visit(m)
            if found:
                return found
    return None


def strongly_connected(graph: Graph) -> list:
    """The strongly connected components of ``graph`` with more than one module (Tarjan):
    each holds at least one cycle, and every cycle lies in one of them."""
    index: dict = {}
    low: dict = {}
    stack: list = []
    on_stack: set = set()
    out: list = []

    def visit(m):
        index[m] = low[m] = len(index)
        stack.append(m)
        on_stack.add(m)
        for t in sorted(graph.get(m, {})):
            if t not in index:
                visit(t)
                low[m] = min(low[m], low[t])
            elif t in on_stack:
                low[m] = min(low[m], index[t])
        if low[m] == index[m]:
            component = []
            while True:
                t = stack.pop()
                on_stack.discard(t)
                component.append(t)
                if t == m:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for m in sorted(graph):
        if m not in index:
            visit(m)
    return sorted(out)


def find_cycles(graph: Graph) -> list:
    """One import cycle ``[m0, m1, ..., m0]`` in each strongly connected component: breaking
    every cycle reported (and running again) removes them all."""
    found = []
    for component in strongly_connected(graph):
        inside = set(component)
        found.append(find_cycle({m: {t: w for t, w in graph[m].items() if t in inside}
                                 for m in component}))
    return found


def problems(graph: Graph, layers: dict) -> list:
    """Readable messages for every module without a layer, every import of a higher layer,
    and an import cycle in each group of modules that import each other in a circle. Empty
    when all is well."""
    out = []
    for m in sorted(graph):
        if layer_of(m, layers) is None:
            out.append(f"{m} has no layer: add it to LAYERS in tests/test_architecture.py")
    for m in sorted(graph):
        lm = layer_of(m, layers)
        for t, where in sorted(graph[m].items()):
            lt = layer_of(t, layers)
            if lm is None or lt is None or lt <= lm:
                continue
            # a package entered only on the way to a submodule that is itself reported
            via = [w.partition(" (package of ")[2].rstrip(")") for w in where]
            if all(v and (layer_of(v, layers) or 0) > lm for v in via):
                continue
            out.append(f"upward import: {m} (layer {lm}) imports {t} (layer {lt}) at "
                       f"{', '.join(where)}: move the code that needs {t} up to a layer "
                       f">= {lt} (e.g. symcable.api.analyses), or what it needs down")
    for component, cycle in zip(strongly_connected(graph), find_cycles(graph)):
        steps = "; ".join(f"{a} imports {b} at {', '.join(graph[a][b])}"
                          for a, b in zip(cycle, cycle[1:]))
        out.append(f"import cycle: {' -> '.join(cycle)} ({steps}); the modules "
                   f"{', '.join(component)} all reach each other")
    return out


#: the formulations' packages under symcable.models
FORMULATIONS = ("planar", "cable3d", "rod", "body", "toys")
#: what a formulation (and the shared physics, models.common) may import of the package,
#: besides its own package: design.md's rule, plus the leaves of layer 0
FORMULATION_MAY_IMPORT = ("symcable.scene", "symcable.mechanism", "symcable.models.common",
                          "symcable.analytic", "symcable.errors", "symcable.limits",
                          "symcable.progress", "symcable.linalg")


def _under(module: str, prefix: str) -> bool:
    return module == prefix or module.startswith(prefix + ".")


def rule_problems(graph: Graph) -> list:
    """Messages for every import that breaks design.md's rules beyond the layers: a
    formulation (or models.common) importing anything but the scene, the mechanism, the
    shared physics and the leaves (another formulation, a solver, the API, results); the
    solvers importing a formulation; a module outside ``api`` importing both the
    formulations and the solvers."""
    out = []
    for m in sorted(graph):
        own = next((f"symcable.models.{f}" for f in FORMULATIONS
                    if _under(m, f"symcable.models.{f}")), None)
        if own is None and _under(m, "symcable.models.common"):
            own = "symcable.models.common"
        if own is not None:
            for t, where in sorted(graph[m].items()):
                if _under(t, own) or any(_under(t, a) for a in FORMULATION_MAY_IMPORT):
                    continue
                if t in ("symcable", "symcable.models"):  # packages on the way down
                    continue
                out.append(f"{m} imports {t} at {', '.join(where)}: a formulation imports only "
                           "the scene, the mechanism, models.common and the leaves")
        if _under(m, "symcable.solvers"):
            for t, where in sorted(graph[m].items()):
                if _under(t, "symcable.models"):
                    out.append(f"{m} imports {t} at {', '.join(where)}: the solvers see only "
                               "the Mechanism")
        if not _under(m, "symcable.api") and m != "symcable":
            targets = list(graph[m])
            if any(_under(t, "symcable.models") for t in targets) and \
                    any(_under(t, "symcable.solvers") for t in targets):
                out.append(f"{m} imports both symcable.models and symcable.solvers: only "
                           "symcable.api may")
    return out


#: the formulation kinds a scene's ``model`` key takes, and the enum members naming them
KINDS = ("planar", "cable3d", "rod", "hybrid")
KIND_MEMBERS = ("PLANAR", "CABLE3D", "ROD", "HYBRID")
#: where a kind may be named: the formulations and their registry, and the scene reader
#: (which reads the ``model`` key and says which keys each kind takes)
MAY_NAME_KINDS = ("models", "scene")


def _names_kind(node: ast.AST) -> bool:
    """Whether ``node`` (a comparison operand) is a kind: a string constant of
    :data:`KINDS`, a collection of them, ``Model.X`` of :data:`KIND_MEMBERS`, or a scene's
    ``model`` (``x.model``, ``x.model.value``)."""
    if isinstance(node, ast.Constant):
        return node.value in KINDS
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return any(_names_kind(e) for e in node.elts)
    if isinstance(node, ast.Attribute):
        if node.attr in KIND_MEMBERS or node.attr == "model":
            return True
        return node.attr == "value" and isinstance(node.value, ast.Attribute) \
            and node.value.attr == "model"
    return False


def kind_problems(src: Path = ROOT, package: str = PACKAGE) -> list:
    """Messages for every place outside :data:`MAY_NAME_KINDS` that branches on a
    formulation kind (a comparison with a kind, ``Model.CABLE3D``, a scene's ``model``),
    and every module outside ``models`` and ``api`` that imports a formulation's own
    package: the layers above ask the registry (``models.formulation_of``) instead."""
    out = []
    modules = find_modules(src, package)
    graph = import_graph(src, package)
    for name, path in sorted(modules.items()):
        if any(_under(name, f"{package}.{m}") for m in MAY_NAME_KINDS):
            continue
        tree = ast.parse(path.read_text(), str(path))
        for node in ast.walk(tree):
            where = f"{path.relative_to(src)}:{getattr(node, 'lineno', '?')}"
            if isinstance(node, ast.Compare) and any(
                    _names_kind(x) for x in [node.left, *node.comparators]):
                out.append(f"{where}: compares with a formulation kind")
            elif isinstance(node, ast.Attribute) and node.attr in KIND_MEMBERS:
                out.append(f"{where}: names Model.{node.attr}")
        if name == package or _under(name, f"{package}.api"):
            continue
        for t, at in sorted(graph.get(name, {}).items()):
            if any(_under(t, f"{package}.models.{f}") for f in FORMULATIONS):
                out.append(f"{name} imports {t} at {', '.join(at)}: only models and api "
                           "import a formulation's package")
    return out


# --------------------------------------------------------------------------- the tests

def test_symcable_layers_and_no_cycles():
    graph = import_graph()
    found = problems(graph, LAYERS)
    assert not found, "\n" + "\n".join(found)


def test_formulations_solvers_and_api_rules():
    """design.md's rules: no formulation imports another formulation, a solver or the API;
    the solvers never import a formulation; only the API imports both."""
    found = rule_problems(import_graph())
    assert not found, "\n" + "\n".join(found)


def test_nothing_outside_models_names_a_formulation_kind():
    """design.md's rule: the API, CLI, results, plots, export and sweeps read the
    formulation's capabilities (models.formulation_of) and the Mechanism's layout; only
    models/ (and the scene reader) name the kinds."""
    found = kind_problems()
    assert not found, "\n" + "\n".join(found)


def test_kind_checker_finds_each_form(tmp_path):
    pkg = tmp_path / "pkg"
    (pkg / "models" / "rod").mkdir(parents=True)
    for f in ("__init__.py", "models/__init__.py", "models/rod/__init__.py"):
        (pkg / f).write_text("")
    (pkg / "models" / "rod" / "x.py").write_text("A = 1\nif 'rod' == 'rod': pass\n")
    (pkg / "cli.py").write_text(
        "from .models.rod import x\n"
        "def f(scene, Model):\n"
        "    if scene.model.value in ('rod', 'hybrid'): pass\n"
        "    if scene.model is Model.CABLE3D: pass\n"
        "    if kind == 'planar': pass\n"
        "    text = 'a planar line'\n")
    found = kind_problems(tmp_path, "pkg")
    lines = {f.split(": ")[0].rsplit(":", 1)[-1] for f in found if "compares" in f}
    assert lines == {"3", "4", "5"}, found  # not line 6: naming a kind in text is fine
    assert sum("names Model.CABLE3D" in f for f in found) == 1, found
    assert any(f.startswith("pkg.cli imports pkg.models.rod") for f in found), found
    assert not any("models/rod/x.py" in f for f in found), found  # inside models: allowed


def test_rule_checker_finds_each_kind():
    graph = {"symcable.models.rod.rod": {"symcable.models.cable3d.line": ["r.py:3"],
                                          "symcable.models.common.elements": ["r.py:4"]},
             "symcable.solvers.branch": {"symcable.models.rod.reanchor": ["b.py:9"]},
             "symcable.cli.main": {"symcable.models": ["c.py:1"], "symcable.solvers": ["c.py:2"]},
             "symcable.api.branch": {"symcable.models": ["a.py:1"], "symcable.solvers": ["a.py:2"]}}
    found = rule_problems(graph)
    assert len(found) == 3
    assert found[0].startswith("symcable.cli.main imports both")
    assert found[1].startswith("symcable.models.rod.rod imports symcable.models.cable3d.line at r.py:3")
    assert found[2].startswith("symcable.solvers.branch imports symcable.models.rod.reanchor")


def test_checker_finds_a_cycle_within_one_layer():
    graph = {"pkg.a": {"pkg.b": ["pkg/a.py:3"]},
             "pkg.b": {"pkg.c": ["pkg/b.py:5"]},
             "pkg.c": {"pkg.a": ["pkg/c.py:9"]}}
    found = problems(graph, {"pkg.a": 0, "pkg.b": 0, "pkg.c": 0})
    assert len(found) == 1 and found[0].startswith(
        "import cycle: pkg.a -> pkg.b -> pkg.c -> pkg.a (pkg.a imports pkg.b at pkg/a.py:3; ")
    assert "pkg/c.py:9" in found[0]
    assert find_cycle({"x": {"y": ["x.py:1"]}, "y": {}}) is None


def test_checker_finds_upward_and_unplaced_modules():
    graph = {"pkg.low": {"pkg.high": ["pkg/low.py:7"]}, "pkg.high": {}, "pkg.new": {}}
    found = problems(graph, {"pkg.low": 0, "pkg.high": 1})
    assert any("upward import: pkg.low (layer 0) imports pkg.high (layer 1) at pkg/low.py:7" in f
               for f in found)
    assert any(f.startswith("pkg.new has no layer") for f in found)


def test_graph_resolves_relative_lazy_and_package_imports(tmp_path):
    """The walk itself, on a small package written here."""
    files = {
        "pkg/__init__.py": "from .top import run\n",
        "pkg/top.py": "def run():\n    from .sub import leaf\n    from . import sub\n",
        "pkg/sub/__init__.py": "from . import leaf\nfrom .leaf import VALUE\n",
        "pkg/sub/leaf.py": "import os\nVALUE = 1\n",
        "pkg/sub/deep.py": "from .. import top\nfrom ..sub.leaf import VALUE\nimport pkg.sub\n",
    }
    for name, text in files.items():
        p = tmp_path / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    g = import_graph(tmp_path, "pkg")
    assert set(g) == {"pkg", "pkg.top", "pkg.sub", "pkg.sub.leaf", "pkg.sub.deep"}
    assert set(g["pkg"]) == {"pkg.top"}
    assert set(g["pkg.top"]) == {"pkg.sub.leaf", "pkg.sub"}  # lazy imports, package of leaf
    assert set(g["pkg.sub"]) == {"pkg.sub.leaf"}
    assert g["pkg.sub.leaf"] == {}
    # absolute and two-dot imports; pkg.sub only as named (it is deep's own package)
    assert g["pkg.sub.deep"] == {"pkg.top": ["pkg/sub/deep.py:1"],
                                 "pkg.sub.leaf": ["pkg/sub/deep.py:2"],
                                 "pkg.sub": ["pkg/sub/deep.py:3"]}
    assert find_cycle(g) is None
    (tmp_path / "pkg/sub/leaf.py").write_text("def f():\n    from ..top import run\n")
    g = import_graph(tmp_path, "pkg")
    cycle = find_cycle(g)
    assert cycle[0] == cycle[-1] and {"pkg.top", "pkg.sub.leaf"} <= set(cycle)
    found = problems(g, {"pkg": 0, "pkg.top": 0, "pkg.sub": 0})
    assert len(found) == 1 and found[0].startswith("import cycle: pkg.sub -> ")
    assert "pkg.sub.leaf imports pkg.top at pkg/sub/leaf.py:2" in found[0]


# --------------------------------------------------------------------------- sizes

#: design.md's limits on the package's shape: modules at the top of ``symcable/`` (besides
#: ``__init__``), lines of a library file, lines of code of a function (docstring, blank and
#: comment lines not counted; nested functions count toward the function that holds them)
MAX_TOP_MODULES, MAX_FILE_LINES, MAX_FUNCTION_LINES = 5, 600, 100


def code_lines(lines: list, node: ast.AST) -> int:
    """Lines of code of a function ``node`` in a file of ``lines``: not blank, not a comment,
    not its docstring."""
    skip = set()
    body = node.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
            and isinstance(body[0].value.value, str):
        skip = set(range(body[0].lineno, body[0].end_lineno + 1))
    return sum(1 for i in range(node.lineno, node.end_lineno + 1)
               if i not in skip and lines[i - 1].strip()
               and not lines[i - 1].strip().startswith("#"))


def size_problems(src: Path = ROOT, package: str = PACKAGE) -> list:
    """Messages for a package over the limits above."""
    out = []
    top = sorted(p.stem for p in (src / package).glob("*.py") if p.stem != "__init__")
    if len(top) > MAX_TOP_MODULES:
        out.append(f"{len(top)} modules at the top of {package}/ ({', '.join(top)}): at most "
                   f"{MAX_TOP_MODULES}")
    for path in sorted((src / package).rglob("*.py")):
        text = path.read_text()
        lines = text.splitlines()
        rel = path.relative_to(src)
        if len(lines) > MAX_FILE_LINES:
            out.append(f"{rel}: {len(lines)} lines, more than {MAX_FILE_LINES}")
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = code_lines(lines, node)
                if n > MAX_FUNCTION_LINES:
                    out.append(f"{rel}:{node.lineno} {node.name}: {n} lines of code, more "
                               f"than {MAX_FUNCTION_LINES}")
    return out


def test_package_shape():
    """At most 5 modules at the top of symcable/, no library file over 600 lines, no function
    over 100 lines of code (design.md: files small enough to read in one sitting)."""
    found = size_problems()
    assert not found, "\n" + "\n".join(found)


def test_size_checker_finds_each_kind(tmp_path):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    for k in range(6):
        (pkg / f"m{k}.py").write_text("x = 1\n")
    body = "\n".join(f"    y{k} = {k}" for k in range(100))  # + the def line: 101
    (pkg / "long.py").write_text('def f():\n    """doc\n    string"""\n    # note\n\n'
                                 + body + "\n" + "\n" * 600)
    found = size_problems(tmp_path, "pkg")
    assert any("7 modules at the top" in f for f in found), found
    assert any("long.py: " in f and "more than 600" in f for f in found), found
    assert any("f: 101 lines of code" in f for f in found), found
