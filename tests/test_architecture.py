"""The layers import one way, every module imports alone, and ``validate`` stays light.

`LAYERS` declares the order, from the floor up; a module may import only its
own layer and the layers below it.  Every import counts, function-level ones
included; only those under ``if TYPE_CHECKING:`` (annotations, never run) are
excluded.  ``from brushbem import NAME`` counts as an import of the module
that `brushbem.__init__` takes NAME from.  A cycle in the import graph fails
here too, as does a module that only imports after another has been imported.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "brushbem"
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _modules() -> dict[str, Path]:
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        found[name] = path
    return found


def _type_checking_only(tree: ast.AST) -> set[int]:
    """Line numbers of the statements inside ``if TYPE_CHECKING:`` blocks."""
    lines: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
            for statement in node.body:
                lines.update(range(statement.lineno, (statement.end_lineno or statement.lineno) + 1))
    return lines


def _public_names() -> dict[str, str]:
    """``brushbem.NAME`` -> the module `brushbem.__init__` imports it from on first use (its ``_PUBLIC``)."""
    tree = ast.parse((PACKAGE / "__init__.py").read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "_PUBLIC" for t in node.targets):
            return {name: f"brushbem.{module}" for name, module in ast.literal_eval(node.value).items()}
    raise AssertionError("brushbem/__init__.py has no _PUBLIC table")


def _import_lines(unresolved: list[str] | None = None):
    """(module, line, imported module) of every import of a package module, TYPE_CHECKING-only ones excluded;
    ``unresolved`` collects imports of modules that do not exist."""
    modules = _modules()
    public = _public_names()
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        tree = ast.parse(path.read_text(encoding="utf-8"))
        skipped = _type_checking_only(tree)
        for node in ast.walk(tree):
            if not isinstance(node, (ast.Import, ast.ImportFrom)) or node.lineno in skipped:
                continue
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            else:
                if node.level:
                    base = package.split(".")[: len(package.split(".")) - node.level + 1]
                    module = ".".join(base + ([node.module] if node.module else []))
                else:
                    module = node.module or ""
                if module.startswith("brushbem") and module not in modules and unresolved is not None:
                    unresolved.append(f"{name}:{node.lineno} imports {module}")
                # `from pkg import sub` imports the submodule when there is one.
                targets = [f"{module}.{alias.name}" if f"{module}.{alias.name}" in modules
                           else public.get(alias.name, module) if module == "brushbem" else module
                           for alias in node.names]
            for target in targets:
                while target not in modules and "." in target:
                    target = target.rpartition(".")[0]
                if target in modules and target != name:
                    yield name, node.lineno, target


def _import_graph(unresolved: list[str] | None = None) -> dict[str, set[str]]:
    """Module -> the package modules it imports; ``unresolved`` collects imports of modules that do not exist."""
    graph: dict[str, set[str]] = {name: set() for name in _modules()}
    for name, _, target in _import_lines(unresolved):
        graph[name].add(target)
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    counter = 0
    for root, children_of_root in graph.items():
        if root in index:
            continue
        work = [(root, iter(sorted(children_of_root)))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
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
    return found


def test_the_cycle_finder_finds_a_cycle():
    """The check below can fail: a graph with a cycle is reported."""
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


#: The layers from the floor up: a module imports only its own layer and those below.  The floor holds
#: what every layer may read (errors, the array backend, shared settings, the typed result records);
#: the library is everything up to `brushbem.api`; the applications above it are never imported by it.
LAYERS: tuple[tuple[str, ...], ...] = (
    ("brushbem", "brushbem.errors", "brushbem.backend", "brushbem.settings", "brushbem.results", "brushbem.examples",
     "brushbem.data"),
    ("brushbem.physics",),
    ("brushbem.config",),
    ("brushbem.numerics",),
    ("brushbem.protocol", "brushbem.pillars"),
    ("brushbem.io",),
    ("brushbem.figures",),
    ("brushbem.runs", "brushbem.design", "brushbem.design_files"),
    ("brushbem.api",),
    ("brushbem.sweep",),
    ("brushbem.studies",),
    ("brushbem.reproduction",),
    ("brushbem.report",),
    ("brushbem.cli", "brushbem.__main__"),
)


def _layer_of(module: str, layers=LAYERS) -> int | None:
    """The index in ``layers`` of the longest package prefix of ``module`` (None: in no layer).

    ``brushbem`` itself (its ``__init__``) is only itself: a new package must be given its layer.
    """
    best, found = -1, None
    for index, layer in enumerate(layers):
        for package in layer:
            inside = module == package or (package != "brushbem" and module.startswith(package + "."))
            if inside and len(package) > best:
                best, found = len(package), index
    return found


def _against_the_layers(lines, layers=LAYERS) -> list[str]:
    """``module:line imports target`` for every import of a higher layer (once per line and target)."""
    return list(dict.fromkeys(f"{name}:{line} imports {target}" for name, line, target in lines
                              if _layer_of(target, layers) > _layer_of(name, layers)))


def test_every_module_has_a_layer():
    assert [name for name in _modules() if _layer_of(name) is None] == []


def test_the_layer_order_holds():
    """No import against `LAYERS`, lazy (function-level) ones included."""
    found = _against_the_layers(_import_lines())
    assert not found, "\n".join(found)


def test_the_layer_check_finds_an_import_upwards():
    """The check can fail: an import of a higher layer, at any depth of the package, is reported."""
    layers = (("brushbem.results",), ("brushbem.io",), ("brushbem.cli",))
    lines = [("brushbem.io.reading", 14, "brushbem.results.case"), ("brushbem.results.case", 3, "brushbem.io"),
             ("brushbem.io", 96, "brushbem.cli.common")]
    assert _against_the_layers(lines, layers) == ["brushbem.results.case:3 imports brushbem.io",
                                                  "brushbem.io:96 imports brushbem.cli.common"]


def test_the_library_imports_no_application():
    """physics, numerics, protocol, results, io, config and the runs import nothing of sweep, studies,
    reproduction, report or cli (implied by `LAYERS`; stated here by name)."""
    library = ("brushbem.physics", "brushbem.numerics", "brushbem.protocol", "brushbem.pillars", "brushbem.results",
               "brushbem.io", "brushbem.config", "brushbem.runs", "brushbem.figures", "brushbem.backend")
    applications = ("brushbem.sweep", "brushbem.studies", "brushbem.reproduction", "brushbem.report",
                    "brushbem.cli")
    found = [f"{name}:{line} imports {target}" for name, line, target in _import_lines()
             if name.startswith(library) and target.startswith(applications)]
    assert not found, "\n".join(found)


def test_no_import_cycles():
    unresolved: list[str] = []
    graph = _import_graph(unresolved)
    # A function-level import runs only when called: one of a module that does not exist is caught here.
    assert unresolved == []
    assert graph["brushbem.runs.assembly"] >= {"brushbem.config", "brushbem.physics.structure"}
    assert "brushbem.runs.assembly" not in graph["brushbem.config"]
    assert _cycles(graph) == []


#: Imports each named module in a child forked from a fresh interpreter that holds the third-party
#: libraries but no brushbem module: the module imports alone, without the cost of a new interpreter
#: and of NumPy/SciPy per module.
_ALONE = """
import os, sys, traceback
import numpy, scipy, scipy.fft, scipy.linalg, scipy.sparse, xarray, pydantic, click, rich, matplotlib, pandas
assert not any(name.startswith("brushbem") for name in sys.modules)
running = 0
for name in sys.argv[1:]:
    if running >= (os.cpu_count() or 1):
        os.wait()
        running -= 1
    pid = os.fork()
    if pid == 0:
        try:
            __import__(name)
        except BaseException:
            print(name, "::", traceback.format_exc().strip().splitlines()[-1], flush=True)
            os._exit(1)
        os._exit(0)
    running += 1
while running:
    os.wait()
    running -= 1
"""


@pytest.mark.slow
def test_every_module_imports_alone():
    names = sorted(_modules())
    done = subprocess.run([sys.executable, "-c", _ALONE, *names], capture_output=True, text=True, check=False,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout == "", done.stdout


def test_the_import_check_finds_a_module_that_fails_alone(tmp_path):
    """The forked check reports an import error (a check that cannot fail proves nothing)."""
    (tmp_path / "broken_alone.py").write_text("import brushbem_does_not_exist\n")
    done = subprocess.run([sys.executable, "-c", _ALONE, "broken_alone"], capture_output=True, text=True,
                          check=False, timeout=120, cwd=tmp_path, env={**__import__("os").environ, "PYTHONPATH": str(tmp_path)})
    assert "broken_alone :: ModuleNotFoundError" in done.stdout


@pytest.mark.parametrize("example", ["default.toml", "punch_spring.toml"])
def test_validate_loads_neither_the_solver_nor_scipy(example):
    code = (
        "import sys\n"
        "from click.testing import CliRunner\n"
        "from brushbem.cli import main\n"
        f"result = CliRunner().invoke(main, ['validate', {str(EXAMPLES / example)!r}])\n"
        "assert result.exit_code == 0 and result.output.startswith('ok'), result.output\n"
        "heavy = ('scipy', 'brushbem.numerics.solver', 'brushbem.protocol', 'brushbem.numerics.operator', 'brushbem.physics.halfspace')\n"
        "print(sorted(m for m in sys.modules if m.startswith(heavy)))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


_PILLARS_FILE = """
[halfspace]
contact_modulus = 1.0
work_of_adhesion = 1e-4
[grid]
size = 1.0
elements = 64
[indenter]
shape = "brush"
layout = "square"
region = "square"
pillars_per_side = 4
pillar_radius = 0.05
stiffness_ratio = 0.05
[protocol]
method = "pillars"
preload_displacement = 2e-3
"""


@pytest.mark.parametrize("adhesion", [1e-4, 0.0])
def test_validating_a_pillar_model_file_loads_no_solver(tmp_path, adhesion):
    """The pillar model's domain is checked on the rasterised brush by its rule alone: neither the pillar model,
    the load paths, the operator nor SciPy is loaded (a file it refuses, no adhesion, takes the same light way)."""
    path = tmp_path / "pillars.toml"
    path.write_text(_PILLARS_FILE.replace("work_of_adhesion = 1e-4", f"work_of_adhesion = {adhesion}"))
    code = (
        "import sys\n"
        "from click.testing import CliRunner\n"
        "from brushbem.cli import main\n"
        f"result = CliRunner().invoke(main, ['validate', {str(path)!r}])\n"
        "print(result.exit_code, repr(result.output[:60]), 'models adhesive pull-off' in result.output)\n"
        "heavy = ('scipy', 'brushbem.numerics.solver', 'brushbem.numerics.operator', 'brushbem.protocol', "
        "'brushbem.pillars', 'brushbem.physics.halfspace')\n"
        "print(sorted(m for m in sys.modules if m.startswith(heavy)))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    status, loaded = done.stdout.strip().splitlines()[-2:]
    assert loaded == "[]"
    if adhesion:
        assert status.startswith("0 'ok") and status.endswith("False"), status
    else:
        assert status.startswith("2 'invalid") and status.endswith("True"), status


def test_the_pillar_model_rule_refuses_by_key_without_the_model():
    """The configuration reports the pillar model's domain (`pillar_model_problems`) by key before a run."""
    from brushbem.config import ConfigError
    from brushbem.runs.assembly import parse_config

    document = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4}, "grid": {"size": 1.0, "elements": 64},
                "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": 0.05},
                "protocol": {"method": "pillars", "preload_displacement": 2e-3}}
    with pytest.raises(ConfigError, match=r"protocol\.method.*models brushes of flat pillars"):
        parse_config(document)


#: The numerical core: the modules whose functions the size rule covers.
NUMERICS = ("numerics", "physics/halfspace.py", "physics/springs.py", "physics/structure", "protocol", "pillars")
MAX_LINES = 80  # code lines, the docstring not counted
MAX_PARAMETERS = 8  # self and cls not counted
REASON = "Why one function:", "Why these parameters:"


def _sizes(tree: ast.AST):
    for node in ast.walk(tree):
        if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        doc = ast.get_docstring(node) or ""
        body = node.body[1:] if doc and len(node.body) > 1 else node.body
        lines = node.end_lineno - body[0].lineno + 1
        args = node.args
        names = [a.arg for a in (*args.posonlyargs, *args.args, *args.kwonlyargs)]
        parameters = len([n for n in names if n not in ("self", "cls")])
        yield node, lines, parameters, doc


def _numerics_files():
    for name in NUMERICS:
        path = PACKAGE / name
        yield from (sorted(path.glob("*.py")) if path.is_dir() else [path])


def test_numerics_functions_are_short_or_say_why():
    """No function of the numerics over 80 code lines or 8 parameters without its reason in the docstring."""
    unexplained = []
    for path in _numerics_files():
        for node, lines, parameters, doc in _sizes(ast.parse(path.read_text(encoding="utf-8"))):
            if (lines > MAX_LINES or parameters > MAX_PARAMETERS) and not any(r in doc for r in REASON):
                unexplained.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {node.name} "
                                   f"({lines} lines, {parameters} parameters)")
    assert not unexplained, "\n".join(unexplained)


def test_the_size_rule_finds_a_long_function():
    body = "\n".join(f"    x{i} = {i}" for i in range(MAX_LINES + 1))
    source = f'def long(a, b, c, d, e, f, g, h, i):\n    """No reason."""\n{body}\n'
    [(_, lines, parameters, doc)] = list(_sizes(ast.parse(source)))
    assert lines == MAX_LINES + 1 and parameters == 9 and not any(r in doc for r in REASON)


#: The numerics and physics: modules that know parameters of Python objects, never configuration keys.
PHYSICS = ("numerics", "physics", "protocol", "pillars")


def _configuration_keys() -> set[str]:
    """Every ``section.field`` of the run configuration, from the schema."""
    from brushbem.config.schema import RunConfig

    keys = set()
    for section, field in RunConfig.model_fields.items():
        keys.update(f"{section}.{name}" for name in field.annotation.model_fields)
    return keys


def _text_with_line(source: str):
    """(line, text) of every string literal and comment; an f-string's ``{...}`` expressions are blanked."""
    import io
    import re
    import tokenize

    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type not in (tokenize.STRING, tokenize.COMMENT):
            continue
        text = token.string
        prefix = re.match(r"[A-Za-z]*", text).group(0).lower()
        if "f" in prefix:
            text = re.sub(r"\{\{|\}\}|\{[^{}]*(\{[^{}]*\}[^{}]*)*\}",
                          lambda m: m.group(0) if m.group(0) in ("{{", "}}") else " " * len(m.group(0)), text)
        yield token.start[0], text


def _key_hits(source: str, keys: set[str]) -> list[tuple[int, str]]:
    import re

    sections = "|".join(sorted({key.split(".")[0] for key in keys}))
    pattern = re.compile(rf"(?<![\w.])(?:{sections})\.[a-z_]+\b")
    hits = []
    for line, text in _text_with_line(source):
        for match in pattern.finditer(text):
            if match.group(0) in keys:
                hits.append((line + text[: match.start()].count("\n"), match.group(0)))
    return hits


#: Hits left for another change in flight (file, key): remove an entry once its file is edited.
KEY_HITS_PENDING: set[tuple[str, str]] = set()


def test_no_numerics_module_names_a_configuration_key():
    """The numerics name their own parameters; only the run layer (assembly) knows configuration keys."""
    keys = _configuration_keys()
    found = []
    for name in PHYSICS:
        path = PACKAGE / name
        for file in sorted(path.rglob("*.py")) if path.is_dir() else [path]:
            where = file.relative_to(PACKAGE).as_posix()
            for line, key in _key_hits(file.read_text(encoding="utf-8"), keys):
                if (where, key) not in KEY_HITS_PENDING:
                    found.append(f"{where}:{line} names {key}")
    assert not found, "\n".join(found)


def test_the_key_rule_finds_a_key_and_spares_attributes():
    keys = {"grid.size", "protocol.speed"}
    source = ('"""Set grid.size here."""\n'
              'x = grid.size  # protocol.speed too\n'
              'y = f"{grid.size} is self.grid.size, Grid.size"\n')
    assert _key_hits(source, keys) == [(1, "grid.size"), (2, "protocol.speed")]


def test_the_run_layer_maps_parameters_back_to_keys():
    """`brushbem.runs.assembly.PARAMETER_KEYS` names schema keys; a `ParameterError` reads as a `ConfigError` by key."""
    from brushbem.runs.assembly import PARAMETER_KEYS, configuration_errors
    from brushbem.config import ConfigError
    from brushbem.errors import ParameterError

    assert set(PARAMETER_KEYS.values()) <= _configuration_keys()
    with pytest.raises(ConfigError, match=r"protocol\.speed = 1 only applies .*\(indenter\.viscoelastic\)") as info:
        with configuration_errors():
            raise ParameterError("LoadPath", "speed", "LoadPath.speed = 1 only applies (Indenter.viscoelastic)")
    assert isinstance(info.value.__cause__, ParameterError)
    with pytest.raises(ConfigError, match=r"^grid\.elements: must be >= 2$"):
        with configuration_errors():
            raise ParameterError("Grid", "elements", "must be >= 2")


def _stacks_at_transforms(run) -> dict[tuple[str, ...], int]:
    """The package modules on the call stack at every padded convolution of ``run()``, in order, repeats merged."""
    import collections

    from brushbem import backend

    stacks: collections.Counter = collections.Counter()
    originals = {name: getattr(backend, name) for name in ("padded_convolution", "padded_convolution_rows")}

    def spy(original):
        def recorded(*args, **kwargs):
            frames = []
            frame = sys._getframe(1)  # not inspect.stack(): that reads every frame's source lines
            while frame is not None:
                frames.append(frame.f_globals.get("__name__") or "")
                frame = frame.f_back
            modules: list[str] = []
            for module in reversed(frames):
                if module.startswith("brushbem") and (not modules or modules[-1] != module):
                    modules.append(module)
            stacks[tuple(modules)] += 1
            return original(*args, **kwargs)

        return recorded

    try:
        for name, original in originals.items():
            setattr(backend, name, spy(original))
        run()
    finally:
        for name, original in originals.items():
            setattr(backend, name, original)
    return dict(stacks)


@pytest.mark.parametrize("method", ["events", "fixed"])
def test_a_pull_off_goes_down_to_the_transforms_without_climbing_back(method):
    """From `brushbem.run` to every FFT, no module is entered twice on the way down (a callback would).

    The stack at each transform is the path a newcomer follows from the API
    to the numerics: api > case > load path > steps > equilibria > set
    solve > CG > block deflection > operator > backend, each once.
    """
    import brushbem

    config = {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": {"shape": "brush", "layout": "square", "region": "square", "pillars_per_side": 4,
                     "pillar_radius": 0.05, "stiffness_ratio": 0.05, "roughness": {"sigma": 5e-4}, "seed": 3},
        "protocol": {"method": method, "preload_displacement": 2e-3, "step": 4e-4},
    }
    stacks = _stacks_at_transforms(lambda: brushbem.run(config))
    assert stacks
    climbing = {" > ".join(s): n for s, n in stacks.items() if len(set(s)) < len(s)}
    assert not climbing, climbing


#: The most lines a module of the package may have: one topic a reader can hold at once.
MAX_MODULE_LINES = 600


def test_no_module_is_over_600_lines():
    long = {name: n for name, path in _modules().items()
            if (n := len(path.read_text(encoding="utf-8").splitlines())) > MAX_MODULE_LINES}
    assert not long, f"split these modules (at most {MAX_MODULE_LINES} lines): {long}"


#: The packages of the load path, whose numerical choices are `brushbem.settings.Switches` fields.
_LOAD_PATH = ("brushbem.backend", "brushbem.numerics", "brushbem.protocol", "brushbem.pillars", "brushbem.physics")


def _switch_setattrs(source: str) -> list[str]:
    """``name.ATTRIBUTE`` of every ``setattr(name, "ATTRIBUTE", ...)`` (monkeypatch's too) of an upper-case
    attribute on a module of the load path imported in ``source``."""
    import re

    tree = ast.parse(source)
    aliases = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and not node.level:
            for alias in node.names:
                if f"{node.module}.{alias.name}".startswith(_LOAD_PATH):
                    aliases.add(alias.asname or alias.name)
    return [f"{m.group(1)}.{m.group(2)}"
            for m in re.finditer(r"setattr\(\s*(\w+)\s*,\s*[\"']([A-Z][A-Z0-9_]*)[\"']", source) if m.group(1) in aliases]


def test_no_switch_of_the_load_path_is_set_by_setattr():
    """Tests and benchmarks switch the numerics through `brushbem.settings.using`, one frozen value, never by
    setting a module attribute (a benchmark's fallback for commits before the settings aside)."""
    root = PACKAGE.parents[1]
    found = [f"{path.relative_to(root)}: {hit}" for folder in ("tests", "benchmarks", "src")
             for path in sorted((root / folder).rglob("*.py"))
             for hit in _switch_setattrs(path.read_text(encoding="utf-8"))]
    assert not found, "\n".join(found)


def test_the_switch_check_finds_a_setattr():
    source = ("from brushbem.numerics.solver import set_solve\nfrom brushbem.io import writing\n"
              "monkeypatch.setattr(set_solve, 'SINGLE_PRODUCTS', False)\nsetattr(writing, 'IN_MEMORY_LIMIT', 0)\n")
    assert _switch_setattrs(source) == ["set_solve.SINGLE_PRODUCTS"]


#: The most methods (properties, class methods and dunder methods included) a class of the load path may have:
#: one job a reader can hold at once.
MAX_METHODS = 15

#: Classes of the load path over `MAX_METHODS`, left for their own change: remove an entry once its class is
#: within the budget (none now).
METHOD_BUDGET_PENDING: set[str] = set()


def _method_counts(source: str) -> dict[str, int]:
    """Class name -> how many functions its body defines (nested classes counted on their own)."""
    return {node.name: sum(isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)) for item in node.body)
            for node in ast.walk(ast.parse(source)) if isinstance(node, ast.ClassDef)}


def test_no_class_on_the_load_path_is_over_its_method_budget():
    """The operator, the window, the connections' state, the solvers: at most `MAX_METHODS` methods each."""
    over = {}
    for name, path in _modules().items():
        if not name.startswith(_LOAD_PATH):
            continue
        for cls, count in _method_counts(path.read_text(encoding="utf-8")).items():
            if count > MAX_METHODS and f"{name}.{cls}" not in METHOD_BUDGET_PENDING:
                over[f"{name}.{cls}"] = count
    assert not over, over
    modules = _modules()
    for pending in METHOD_BUDGET_PENDING:  # an entry that is within the budget is removed, not kept
        module, _, cls = pending.rpartition(".")
        assert _method_counts(modules[module].read_text(encoding="utf-8"))[cls] > MAX_METHODS, pending


def test_the_method_budget_counts_every_method():
    source = "class A:\n" + "".join(f"    def m{i}(self): ...\n" for i in range(16)) + "class B:\n    x = 1\n"
    assert _method_counts(source) == {"A": 16, "B": 0}


def test_the_operator_holds_no_solver_state():
    """`ContactOperator` keeps nothing a solve writes: what the solves reuse is the caller's `SolverCache`."""
    import numpy as np

    from brushbem.numerics.operator import ContactOperator, Window
    from brushbem.numerics.solver import SolverCache, solve_on_set
    from brushbem.physics.halfspace import HalfSpace
    from brushbem.physics.structure import Grid, brush

    grid = Grid(1.0, 32)
    indenter = brush(grid, layout="square", pillars_per_side=2, pillar_radius=0.1, stiffness=0.05,
                     contact_modulus=1.0, work_of_adhesion=1e-4)
    operator = ContactOperator(HalfSpace(32, grid.element_size, 1.0), indenter, Window.full(32))
    before = dict(vars(operator))
    mask = np.asarray(indenter.footprint)
    cache = SolverCache()
    result = solve_on_set(operator, mask, np.where(mask, 1.0, 0.0), cache=cache)
    assert result.converged
    assert vars(operator).keys() == before.keys() and all(vars(operator)[k] is v for k, v in before.items())
    assert cache.pillars.coarse is not None and cache.set_solvers  # the solve wrote the caller's cache
    for name in ("set_solver", "remember_solution", "known_tip_deflection", "cache", "sub_operator"):
        assert not hasattr(operator, name), name


def _state_writes(source: str) -> list[str]:
    """``Class.function:line`` (or ``function:line``) of every assignment to an attribute ``state``."""
    found = []

    def visit(node, where):
        for child in ast.iter_child_nodes(node):
            name = where
            if isinstance(child, (ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
                name = f"{where}.{child.name}" if where else child.name
            if isinstance(child, (ast.Assign, ast.AugAssign, ast.AnnAssign)):
                targets = child.targets if isinstance(child, ast.Assign) else [child.target]
                for target in targets:
                    for part in ast.walk(target):
                        if isinstance(part, ast.Attribute) and part.attr == "state" and isinstance(part.ctx, ast.Store):
                            found.append(f"{where}:{child.lineno}")
            visit(child, name)

    visit(ast.parse(source), "")
    return found


def test_the_element_paths_hand_their_state_from_step_to_step():
    """No step or driver of the element paths writes a state back into a holder: each takes the path's state and
    returns the next (`brushbem.protocol.steps`); the `PathContext` holds only the state a path starts from."""
    writes = {name: hits for name, path in _modules().items() if name.startswith("brushbem.protocol")
              and (hits := _state_writes(path.read_text(encoding="utf-8")))}
    assert list(writes) == ["brushbem.protocol.steps"], writes
    assert [hit.partition(":")[0] for hit in writes["brushbem.protocol.steps"]] == ["PathContext.__init__"]


def test_the_state_write_check_finds_a_write():
    source = "class T:\n    def f(self):\n        self.state = 1\n\ndef g(t):\n    t.state, x = 1, 2\n    y = t.state\n"
    assert _state_writes(source) == ["T.f:3", "g:6"]


#: The calls that change the pillar model's cache (`brushbem.pillars.state.RasterCache`): a raster's arrays and
#: the kept inverse's set.
_PILLAR_CACHE_CHANGES = frozenset({"set_raster", "add_many", "remove_many", "reshape", "refactor"})


def _pillar_cache_changes(source: str) -> list[str]:
    """``function:line`` of every call of a `_PILLAR_CACHE_CHANGES` method on a ``model`` or a ``solver`` (a name
    or an attribute of that name: ``solver.add_many``, ``cache.model.set_raster``)."""
    found = []

    def visit(node, where):
        for child in ast.iter_child_nodes(node):
            name = f"{where}.{child.name}" if isinstance(child, (ast.ClassDef, ast.FunctionDef)) else where
            if isinstance(child, ast.Call) and isinstance(child.func, ast.Attribute):
                receiver = child.func.value
                holder = receiver.id if isinstance(receiver, ast.Name) else getattr(receiver, "attr", None)
                if child.func.attr in _PILLAR_CACHE_CHANGES and holder in ("model", "solver"):
                    found.append(f"{where.lstrip('.')}:{child.lineno}")
            visit(child, name)

    visit(ast.parse(source), "")
    return found


def test_the_pillar_path_changes_its_cache_only_where_a_state_becomes_the_next():
    """The pillar model's path state is a frozen value (`brushbem.pillars.state.PillarState`); the model's raster
    arrays and the kept inverse, the cache, change only in the steps that give the next state (`_apply`, which
    also brings the cache to a saved state, and `attached_together`): no other module of the pillar model
    changes them behind a state's back."""
    changes = {name: [hit.partition(":")[0] for hit in hits] for name, path in _modules().items()
               if name.startswith("brushbem.pillars")
               and (hits := _pillar_cache_changes(path.read_text(encoding="utf-8")))}
    assert set(changes) == {"brushbem.pillars.state"}, changes
    assert set(changes["brushbem.pillars.state"]) == {"_apply", "attached_together"}, changes


def test_the_pillar_cache_check_finds_a_change():
    source = ("class S:\n    def f(self):\n        self.refactor()\n        self.model.set_raster(0, m)\n\n"
              "def g(cache, solver):\n    cache.solver.add_many(p)\n    solver.refactor()\n    x.reshape(2, 2)\n")
    assert _pillar_cache_changes(source) == ["S.f:4", "g:7", "g:8"]
