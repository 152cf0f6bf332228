"""The architecture the README describes holds: one path guard, no import cycles, the README's
architecture table names every package folder."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "openpbr_tools"

# Uses of realpath/relpath/commonpath/"://" outside io/paths.py, each with why it decides no
# containment: everything that asks "may this file be read?" goes through io/paths.py.
NOT_CONTAINMENT = {
    ("config.py", "relpath"): "matches a file against an override's glob patterns",
    ("selection.py", "realpath"): "compares files with what git reports changed",
    ("baseline.py", "relpath"): "spells a file relative to the baseline's folder",
    ("rules/__init__.py", "realpath"): "the injectable real-path function handed to the path guard",
    ("reports/sarif.py", "://"): "the SARIF schema URI",
    ("io/usd/texture_files.py", "relpath"): "spells a texture path relative to the output folder",
    ("io/usd/network.py", "relpath"): "spells an anchored asset path relative to the root layer",
    ("convert_textures.py", "relpath"): "spells a texture path relative to the output folder",
    ("batch.py", "relpath"): "places an output below the output folder as its input sits below its argument",
    ("io/mtlx/library.py", "realpath"): "keys the library cache by MaterialX's own library folder",
    ("io/mtlx/library.py", "relpath"): "lists MaterialX's own definition files below its library folder",
}


def test_only_the_path_guard_decides_containment():
    found = set()
    for path in PACKAGE.rglob("*.py"):
        relative = path.relative_to(PACKAGE).as_posix()
        if relative == "io/paths.py":
            continue
        for line in path.read_text(encoding="utf-8").splitlines():
            for word in ("realpath", "relpath", "commonpath", "://"):
                if word in line and not line.strip().startswith("#"):
                    found.add((relative, word))
    docstring_only = {(f, w) for f, w in found if w == "://" and f != "reports/sarif.py"}
    assert found - docstring_only == set(NOT_CONTAINMENT), found - docstring_only ^ set(NOT_CONTAINMENT)


def _imports():
    modules = {}
    for path in PACKAGE.rglob("*.py"):
        parts = list(path.relative_to(ROOT).with_suffix("").parts)
        is_package = parts[-1] == "__init__"
        modules[".".join(parts[:-1] if is_package else parts)] = (path, is_package)
    graph = {}
    for name, (path, is_package) in modules.items():
        edges = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = name.split(".") if is_package else name.split(".")[:-1]
                    base = ".".join(base[:len(base) - node.level + 1] + ([node.module] if node.module else []))
                else:
                    base = node.module or ""
                edges |= {f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base for a in node.names}
            elif isinstance(node, ast.Import):
                edges |= {a.name for a in node.names}
        graph[name] = {e for e in edges if e in modules and e != name and not name.startswith(e + ".")}
    return graph


def test_no_import_cycles_even_through_imports_inside_functions():
    graph = _imports()
    cycles, index, low, stack, on = [], {}, {}, [], set()

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                cycles.append(sorted(component))

    for module in graph:
        if module not in index:
            visit(module)
    assert cycles == []


def test_the_readme_architecture_names_every_package_folder():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("## Architecture", 1)[1].split("\n## ", 1)[0]
    named = set(re.findall(r"^\| `([^`]+)` \|", section, re.M))
    folders = {f"openpbr_tools/{p.parent.relative_to(PACKAGE).as_posix()}/" for p in PACKAGE.rglob("__init__.py")
               if p.parent != PACKAGE}
    assert folders <= named, folders - named
    for entry in named:
        assert (ROOT / entry).exists(), entry


def _function_imports_without_reason(root: Path):
    """Imports inside functions with no reason written beside them: a comment on the import's line,
    or on the line right above it or above the run of imports it belongs to."""
    missing = []
    for path in sorted(root.rglob("*.py")):
        text = path.read_text(encoding="utf-8")
        lines = text.splitlines()
        tree = ast.parse(text)
        for function in ast.walk(tree):
            if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            for node in ast.walk(function):
                if not isinstance(node, (ast.Import, ast.ImportFrom)):
                    continue
                index = node.lineno - 1
                if "#" in lines[node.end_lineno - 1] or "#" in lines[index]:
                    continue
                above = index - 1
                while above >= 0 and lines[above].strip().startswith(("import ", "from ")):
                    above -= 1
                if above >= 0 and lines[above].strip().startswith("#"):
                    continue
                missing.append(f"{path.relative_to(ROOT)}:{node.lineno}: {lines[index].strip()}")
    return missing


def test_imports_inside_functions_say_why():
    """An import kept inside a function (a heavy or optional module kept off a start-up path: pxr
    ~0.1-0.2 s, colour-science ~0.6 s, Dask; a module chosen at run time; a command's library behind
    `openpbr --help`) says why beside it; any other belongs at the top. Library and cli alike."""
    assert _function_imports_without_reason(PACKAGE) + _function_imports_without_reason(ROOT / "cli") == []


def test_long_modules_say_why():
    """A module fits in one head: past 400 lines its docstring says why it is one module."""
    long = []
    for path in sorted(PACKAGE.rglob("*.py")):
        text = path.read_text(encoding="utf-8")
        if len(text.splitlines()) > 400:
            docstring = ast.get_docstring(ast.parse(text)) or ""
            if "One module because" not in docstring:
                long.append(f"{path.relative_to(ROOT)} ({len(text.splitlines())} lines)")
    assert long == []
