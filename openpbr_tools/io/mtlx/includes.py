"""MaterialX XIncludes, followed as MaterialX follows them, through the one path guard; and an included document
read in the context of the document that includes it."""

from __future__ import annotations

import os

from .. import read_bytes
from ..paths import PathGuard
from .xmlscan import decode_document, scan

MAX_XINCLUDE_DEPTH = 8
#: references that name no file here (paths.classify), by kind: MaterialX's reader cannot open them either
_NAMES_NO_FILE = {"drive": "a Windows drive path", "unc": "a network (UNC) path", "absolute": "a Windows absolute path",
                  "url": "a URL", "nul": "a path holding NUL", "empty": "an empty path"}


def follow_includes(document, path: str, xincludes, guard: PathGuard, seen: set[str], depth: int = 0,
                    shadowed: list | None = None, followed: list | None = None) -> list[tuple]:
    """Follow the XIncludes of ``document`` (read from ``path``) as MaterialX does: each included
    document's elements are imported into it (``importLibrary``), marked with the included file as
    their source URI so the reader uses them to resolve references but does not validate them
    again (they are validated as their own file). Only files inside the asset's folder are read (the
    one path guard), at most 8 levels deep, each once (a cycle is not followed). Returns
    ``(line, href, reason, broken)`` for every include not followed; ``broken`` when MaterialX
    could not follow it either (missing, unreadable, a cycle), not merely refused here. ``shadowed``
    collects (name, href) of the document's own elements an include also defines: MaterialX reads the
    included one and drops the document's own, wherever the include stands (``validate()`` passes).
    ``followed`` collects the files this document includes itself (not their includes), named from ``path`` as
    the asset is (relative stays relative), so a validation can check each as a file of its own (and theirs with
    them)."""
    not_followed = []
    for line, href in xincludes:
        resolved = guard.resolve(href, base=os.path.dirname(os.path.abspath(path)))
        reason, broken = None, True
        if not resolved.inside and resolved.path is None:  # a URL, or a drive/UNC path on a POSIX system
            reason = f"is {_NAMES_NO_FILE.get(resolved.kind.value, 'a reference')}, which names no file on this system"
        elif not resolved.inside:
            reason, broken = "leads outside the asset's folder, so it is not opened", False
        elif resolved.real in seen:
            reason = "is already being included (a cycle), so it is not followed again"
        elif depth >= MAX_XINCLUDE_DEPTH:
            reason, broken = f"is nested deeper than {MAX_XINCLUDE_DEPTH} includes, so it is not opened", False
        elif not os.path.isfile(resolved.real):
            reason = "does not exist"
        if reason is None:
            try:
                included, nested = _without_includes(resolved.real)
            except Exception as error:  # noqa: BLE001 - ReadError, UnicodeDecodeError, XmlSyntaxError and MaterialX's own types
                reason = f"cannot be read ({getattr(error, 'message', error)})"
            else:
                shown = os.path.normpath(os.path.join(os.path.dirname(path), href))
                if followed is not None:
                    followed.append(shown)
                for _, inner, why, inner_broken in follow_includes(included, shown, nested, guard,
                                                                   seen | {resolved.real}, depth + 1):
                    not_followed.append((line, href, f"includes {inner!r}, which {why}", inner_broken))
                included.setSourceUri(resolved.real)
                if shadowed is not None:  # top-level names the document defines itself (importLibrary keeps those)
                    shadowed += [(c.getName(), href) for c in included.getChildren() if document.getChild(c.getName())
                                 is not None and not document.getChild(c.getName()).getActiveSourceUri()]
                document.importLibrary(included)
        if reason is not None:
            not_followed.append((line, href, reason, broken))
    return not_followed


def _without_includes(path: str):
    """(the MaterialX document at ``path`` read without following its XIncludes, which :func:`follow_includes`
    follows through the guard; its ``(line, href)`` XIncludes). Raises what reading or parsing raises."""
    import MaterialX as mx  # lazy: loaded by the reader that calls this

    data = read_bytes(path)
    document = mx.createDocument()
    options = mx.XmlReadOptions()
    options.readXIncludeFunction = None
    mx.readFromXmlString(document, decode_document(data), mx.FileSearchPath(), options)
    return document, scan(data).xincludes


def import_includer(document, includer: str, allow_outside: tuple[str, ...]) -> bool:
    """Import the document that XIncludes this one (``includer``, with its own includes, read through its own path
    guard) into ``document`` as a library, marked with its source, as MaterialX composes them when it loads the
    includer: a library split into files (nodedefs in one, their implementation graphs in another) resolves its
    references only there. The document's own elements stay its own (importLibrary skips names it has). Returns
    whether the includer was read."""
    composed = _composition(includer, tuple(allow_outside))
    if composed is None:
        return False
    document.importLibrary(composed)
    return True


#: The includers composed last, by (real path, size, modification time, allowed folders): a library of N files
#: each read in the composition of the one file that includes them all composes it once, not N times.
_COMPOSED: dict = {}
_COMPOSED_KEPT = 4


def _composition(includer: str, allow_outside: tuple[str, ...]):
    """``includer`` read with its includes, marked with its source (``None`` when it cannot be read now)."""
    try:
        status = os.stat(includer)
    except OSError:
        return None
    guard = PathGuard.for_asset(includer, allow_outside)
    key = (guard.resolve(os.path.abspath(includer)).real, status.st_size, status.st_mtime_ns, allow_outside)
    if key in _COMPOSED:
        return _COMPOSED[key]
    try:
        composed, xincludes = _without_includes(includer)
        follow_includes(composed, includer, xincludes, guard, {key[0]})
    except Exception:  # noqa: BLE001 - the includer was read before; a change since is its own finding
        return None
    composed.setSourceUri(os.path.abspath(includer))
    while len(_COMPOSED) >= _COMPOSED_KEPT:
        _COMPOSED.pop(next(iter(_COMPOSED)))
    _COMPOSED[key] = composed
    return composed
