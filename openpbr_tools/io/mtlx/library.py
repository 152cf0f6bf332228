"""MaterialX's standard libraries, loaded as little as a document needs.

Validating a document needs the node definitions of the categories it uses, not all ~800 of them:
loading every definition file costs ~35 ms of each ``openpbr validate`` start-up, loading
``stdlib_defs.mtlx`` and ``pbrlib_defs.mtlx`` (the type definitions and the common nodes) plus the
files that define the document's other categories ~10-20 ms, and an extract of just the type, unit
and geometric-property definitions and the node definitions of the document's categories ~0.2 ms
(the same verdicts: tests/test_mtlx_library.py checks every corpus file). Which file defines which
category is derived from the libraries once, and each extract is made once per set of categories;
both are kept in cache files keyed by the MaterialX version and the library folder's location and
modification time, so an upgraded MaterialX rebuilds them: ``$OPENPBR_CACHE_DIR`` or
``$XDG_CACHE_HOME/openpbr-tools`` (default ``~/.cache/openpbr-tools``), written atomically; where no
cache can be written they are kept in memory only.
"""

from __future__ import annotations

import json
import os
from functools import lru_cache

CACHE_FORMAT = 1
ALWAYS = ("stdlib/stdlib_defs.mtlx", "pbrlib/pbrlib_defs.mtlx")  # type definitions and common nodes


def _mx():
    import MaterialX as mx  # lazy: the rules import the reader at every start-up; MaterialX waits for a .mtlx

    return mx


def _roots() -> list[str]:
    mx = _mx()
    found = []
    for folder in mx.getDefaultDataSearchPath().asString().split(mx.PATH_LIST_SEPARATOR):
        for name in mx.getDefaultDataLibraryFolders():
            root = os.path.join(folder, name)
            if os.path.isdir(root):
                found.append(root)
    return found


def _definition_files(root: str) -> list[str]:
    """The files of ``root`` that declare node definitions (not the ``*_ng.mtlx`` implementations nor
    the code-generation folders), relative to ``root``, sorted."""
    files = []
    for directory, subdirectories, names in os.walk(root):
        subdirectories[:] = sorted(d for d in subdirectories if not d.startswith("gen"))
        files += [os.path.relpath(os.path.join(directory, n), root).replace(os.sep, "/")
                  for n in sorted(names) if n.endswith(".mtlx") and not n.endswith("_ng.mtlx")]
    return sorted(files)


def _cache_path(key: str, suffix: str = ".json") -> str:
    base = os.environ.get("OPENPBR_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "openpbr-tools")
    return os.path.join(base, f"materialx-library-{key}{suffix}")


@lru_cache(maxsize=1)
def _library_key() -> str:
    return _key(_roots())


def _key(roots: list[str]) -> str:
    import zlib  # lazy: only when the index is looked up (hashlib costs ~4 ms to import)

    stamp = [_mx().getVersionString(), str(CACHE_FORMAT)]
    for root in roots:
        stamp += [os.path.realpath(root), str(os.stat(root).st_mtime_ns)]
    return f"{_mx().getVersionString()}-{zlib.crc32(chr(10).join(stamp).encode()):08x}"


def _build(roots: list[str]) -> dict:
    mx = _mx()
    files: dict[str, list[str]] = {}
    complete: set[str] = set()
    for root in roots:
        for relative in _definition_files(root):
            document = mx.createDocument()
            mx.loadLibrary(os.path.join(root, relative), document)
            categories = sorted({nd.getNodeString() for nd in document.getNodeDefs()})
            if categories:
                files[os.path.join(root, relative)] = categories
        everything = mx.createDocument()
        mx.loadLibraries([os.path.basename(root)], mx.FileSearchPath(os.path.dirname(root)), everything)
        complete |= {nd.getNodeString() for nd in everything.getNodeDefs()}
    return {"format": CACHE_FORMAT, "files": files, "complete": sorted(complete)}


@lru_cache(maxsize=1)
def index() -> dict:
    """``{"files": {definition file: [categories it defines]}, "complete": [every category, the
    implementation files' included]}``, from the cache when it is current."""
    roots = _roots()
    path = _cache_path(_library_key())
    try:
        with open(path, encoding="utf-8") as handle:
            cached = json.load(handle)
        if cached.get("format") == CACHE_FORMAT and all(os.path.isfile(f) for f in cached["files"]):
            return cached
    except (OSError, ValueError, KeyError, TypeError):
        pass
    built = _build(roots)
    try:
        from ...atomic import write_text  # lazy: only when the cache is (re)built

        os.makedirs(os.path.dirname(path), exist_ok=True)
        write_text(path, json.dumps(built, sort_keys=True))
    except OSError:
        pass  # a read-only home: the index lives for this process only
    return built


def known_categories(complete: bool = False) -> frozenset[str]:
    if complete:
        return frozenset(index()["complete"])
    return frozenset(c for categories in index()["files"].values() for c in categories)


def library_for(categories) -> object:
    """A MaterialX document holding the standard definitions ``categories`` need for
    ``Document.validate()``: the type, unit and geometric-property definitions, and the node
    definitions of ``categories`` (from the files that define them), without the rest of those files
    or any implementation graph. Extracted once per set of categories and kept in the cache folder
    beside the index (the whole files cost ~10-20 ms to load; the extract ~0.2 ms)."""
    files = index()["files"]
    wanted = frozenset(categories)
    chosen = [f for f in files if f.replace(os.sep, "/").endswith(ALWAYS) or wanted & set(files[f])]
    return _trimmed(tuple(sorted(chosen)), wanted)


TRIMMED_KEEP = ("typedef", "unittypedef", "unitdef", "geompropdef", "targetdef")  # and the wanted nodedefs


@lru_cache(maxsize=8)
def _trimmed(files: tuple[str, ...], wanted: frozenset[str]):
    import zlib  # lazy: as in _key

    mx = _mx()
    digest = zlib.crc32("\n".join(list(files) + sorted(wanted)).encode())
    path = _cache_path(f"{_library_key()}-defs-{digest:08x}", ".mtlx")
    document = mx.createDocument()
    try:
        mx.readFromXmlFile(document, path)
        if document.getTypeDefs():
            return document
    except Exception:  # noqa: BLE001 - MaterialX raises its own exception types for a missing or broken file
        document = mx.createDocument()
    full = _load(files)

    def kept(element) -> bool:
        top = element
        while top.getParent() is not None and top.getParent().getParent() is not None:
            top = top.getParent()
        category = top.getCategory()
        return category in TRIMMED_KEEP or (category == "nodedef" and top.getNodeString() in wanted)

    options = mx.XmlWriteOptions()
    options.writeXIncludeEnable = False
    options.elementPredicate = kept
    text = mx.writeToXmlString(full, options)
    try:
        from ...atomic import write_text  # lazy: only when an extract is (re)built

        os.makedirs(os.path.dirname(path), exist_ok=True)
        write_text(path, text)
    except OSError:
        pass  # a read-only home: the extract lives for this process only
    mx.readFromXmlString(document, text)
    return document


@lru_cache(maxsize=8)
def _load(files: tuple[str, ...]):
    mx = _mx()
    library = mx.createDocument()
    for path in files:
        mx.loadLibrary(path, library)
    return library


def enum_violations(node) -> list[tuple[str, str, tuple[str, ...]]]:
    """``(input, value, allowed)`` for each input of ``node`` whose constant is outside the list its
    node definition declares: a string input's ``enum`` (``uaddressmode``: constant, clamp, periodic,
    mirror) or an integer input's ``enumvalues``. Other enums (a colour's presets) are suggestions, not
    lists; connected and unset inputs have no constant to judge."""
    nodedef = node.getNodeDef()
    if nodedef is None:
        return []
    found = []
    for port in node.getInputs():
        value = port.getValueString()
        if not value or port.hasInterfaceName() or port.getConnectedNode() is not None:
            continue
        allowed = declared_enum(nodedef.getActiveInput(port.getName()))
        if allowed is not None and value.strip() not in allowed:
            found.append((port.getName(), value, allowed))
    return found


def declared_enum(declared) -> tuple[str, ...] | None:
    """The values a node definition's input ``declared`` is restricted to: a string input's ``enum``, an integer
    input's ``enumvalues`` (as text); None for any other input (a colour's presets are suggestions, not a list).
    The .mtlx reader (:func:`enum_violations`) and the USD reader (its MaterialX nodes) judge by it."""
    if declared is None or not declared.hasAttribute("enum"):
        return None
    if declared.getType() == "string" and not declared.hasAttribute("enumvalues"):
        return tuple(e.strip() for e in declared.getAttribute("enum").split(","))
    if declared.getType() == "integer" and declared.hasAttribute("enumvalues"):
        return tuple(e.strip() for e in declared.getAttribute("enumvalues").split(","))
    return None


@lru_cache(maxsize=2)
def standard_library(complete: bool = False):
    """MaterialX's standard data libraries, loaded once per process.

    By default only the files that declare node definitions are loaded, not the implementations
    (``*_ng.mtlx`` node graphs, the ``genglsl``/``genosl``/... folders): validation needs node
    definitions, and this halves the start-up cost. ``complete=True`` loads everything, as
    ``mxvalidate`` does.
    """
    import MaterialX as mx  # lazy: the rules import the reader (so this module) at every start-up; MaterialX waits for a .mtlx

    library = mx.createDocument()
    if complete:
        mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
        return library
    for folder in mx.getDefaultDataSearchPath().asString().split(mx.PATH_LIST_SEPARATOR):
        for name in mx.getDefaultDataLibraryFolders():
            root = os.path.join(folder, name)
            for directory, subdirectories, files in os.walk(root):
                subdirectories[:] = sorted(d for d in subdirectories if not d.startswith("gen"))
                for file in sorted(files):
                    if file.endswith(".mtlx") and not file.endswith("_ng.mtlx"):
                        mx.loadLibrary(os.path.join(directory, file), library)
    return library
