"""The one path guard: what a file reference is, and whether it stays inside the asset's folder.

Every reader, writer, rule and the baker that follows a reference found in an asset (a texture, a
glTF buffer or image URI, a USD sublayer, reference, payload or clip, an XInclude) asks this module,
and nothing else decides containment. Two questions, answered once:

* :func:`classify` says what kind of reference a text is, by its form alone (no file-system access):
  ``relative``, ``absolute`` (POSIX ``/x`` or a lone ``\\x``), ``drive`` (``C:\\x``, ``C:/x``,
  ``C:x``), ``unc`` (``\\\\server\\share``, ``//server/share``), ``url`` (any ``scheme:`` of two or
  more characters: ``http://``, ``https:``, ``file:///``, ``data:``), ``nul`` (holds U+0000, which
  no file system accepts) and ``empty``. A drive letter is never a URL scheme.
* :meth:`PathGuard.resolve` anchors a relative reference at a folder, normalises it, resolves
  symbolic links, and says which allowed folder (the asset's own, or one the user allowed with
  ``--allow-outside``) holds the result, if any. A path that climbs out with ``..``, or leads out
  through a symbolic link, is outside; so is every ``absolute``, ``drive`` or ``unc`` reference that
  does not land inside an allowed folder. URLs, NUL paths and empty paths are never resolved: the
  toolkit never fetches a URL. Symbolic links are resolved before ``..`` (as the operating system
  opens the path); a symbolic-link loop names no file and is outside; a backslash counts as a
  separator too (``..\\a.png`` climbs out on Windows, so it is outside everywhere).

Containment is decided on real paths (symbolic links resolved) by path components, so ``/a/bc`` is
not inside ``/a/b``.
"""

from __future__ import annotations

import errno
import os
import re
import stat
from dataclasses import dataclass
from enum import Enum
from typing import Callable, Iterable

RELATIVE, ABSOLUTE, DRIVE, UNC, URL, NUL, EMPTY = "relative", "absolute", "drive", "unc", "url", "nul", "empty"


class Kind(str, Enum):
    """What a reference is, by its form."""

    RELATIVE = RELATIVE
    ABSOLUTE = ABSOLUTE
    DRIVE = DRIVE
    UNC = UNC
    URL = URL
    NUL = NUL
    EMPTY = EMPTY


# A URL scheme is a letter followed by letters, digits, '+', '-' or '.' (RFC 3986 section 3.1),
# then ':'. One letter before ':' is a Windows drive, not a scheme.
_SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]+:")
_DRIVE = re.compile(r"^[A-Za-z]:")
_UNC = re.compile(r"^(?:\\\\|//|\\/|/\\)")


def classify(reference: str) -> Kind:
    """The kind of ``reference`` (see the module docstring); looks at the text only."""
    if not reference or not reference.strip():
        return Kind.EMPTY
    if "\x00" in reference:
        return Kind.NUL
    if _UNC.match(reference):
        return Kind.UNC
    if _DRIVE.match(reference):
        return Kind.DRIVE
    if _SCHEME.match(reference):
        return Kind.URL
    if reference.startswith(("/", "\\")):
        return Kind.ABSOLUTE
    return Kind.RELATIVE


def is_url(reference: str) -> bool:
    """Whether ``reference`` names a URL (never fetched, never a file)."""
    return classify(reference) is Kind.URL


def climbs(reference: str) -> bool:
    """Whether a relative reference has a ``..`` component (either separator): it names a file
    outside its anchor folder unless it comes back in."""
    return ".." in re.split(r"[\\/]", reference)


def leaves(reference: str) -> bool:
    """Whether a relative reference climbs out of its anchor folder once its ``..`` components are taken against
    the components before them (``textures/v002/../albedo.png`` stays inside; ``../albedo.png`` leaves). Symbolic
    links are the guard's concern (:meth:`PathGuard.resolve` resolves them before ``..``, as the system does)."""
    depth = 0
    for part in re.split(r"[\\/]", reference):
        if part == "..":
            depth -= 1
            if depth < 0:
                return True
        elif part not in ("", "."):
            depth += 1
    return False


@dataclass(frozen=True, slots=True)
class Resolved:
    """A reference resolved by :meth:`PathGuard.resolve`.

    ``path`` is the absolute, normalised path it names (``None`` for a URL, a NUL or an empty
    reference, which name no file); ``real`` the same with symbolic links resolved; ``root`` the
    allowed folder (real path) holding ``real``, ``None`` when it is outside every allowed folder
    (or when it is a symbolic-link loop).
    """

    reference: str
    kind: Kind
    path: str | None = None
    real: str | None = None
    root: str | None = None

    @property
    def inside(self) -> bool:
        return self.root is not None

    @property
    def relative(self) -> str | None:
        """``real`` relative to ``root`` with ``/`` separators (``None`` when outside)."""
        if self.root is None or self.real is None:
            return None
        return os.path.relpath(self.real, self.root).replace(os.sep, "/")


class PathGuard:
    """Decides whether references stay inside ``folder`` (the asset's folder) or one of the
    ``allow_outside`` folders. ``real_path`` is injectable (tests, sandboxed runs)."""

    def __init__(self, folder: str | os.PathLike, allow_outside: Iterable[str | os.PathLike] = (),
                 real_path: Callable[[str], str] = os.path.realpath):
        self.folder = os.path.abspath(os.fspath(folder))
        self.real_path = real_path
        self.roots: tuple[str, ...] = tuple(
            real_path(os.path.abspath(os.fspath(f))) for f in (self.folder, *allow_outside))

    @classmethod
    def for_asset(cls, asset_path: str | os.PathLike, allow_outside: Iterable[str | os.PathLike] = (),
                  real_path: Callable[[str], str] = os.path.realpath) -> "PathGuard":
        """The guard of the folder holding ``asset_path``."""
        return cls(os.path.dirname(os.path.abspath(os.fspath(asset_path))), allow_outside, real_path)

    @property
    def own_root(self) -> str:
        """The asset's own folder, as a real path."""
        return self.roots[0]

    def root_of(self, real: str) -> str | None:
        """The allowed folder holding the real path ``real``, or ``None``."""
        for root in self.roots:
            if real == root or real.startswith(root.rstrip(os.sep) + os.sep):
                return root
        return None

    def contains(self, path: str) -> bool:
        """Whether the file-system path ``path`` (absolute, or relative to the working folder) is
        inside an allowed folder once symbolic links are resolved."""
        if classify(path) in (Kind.URL, Kind.NUL, Kind.EMPTY):
            return False
        real = self.real_path(path if os.path.isabs(path) else os.path.join(os.getcwd(), path))
        return not _unresolved(real) and self.root_of(real) is not None

    def resolve(self, reference: str, base: str | os.PathLike | None = None) -> Resolved:
        """Resolve ``reference`` relative to ``base`` (a folder; default the asset's folder)."""
        kind = classify(reference)
        if kind in (Kind.URL, Kind.NUL, Kind.EMPTY):
            return Resolved(reference, kind)
        anchor = os.path.abspath(os.fspath(base)) if base is not None else self.folder
        if kind is Kind.RELATIVE:
            joined = os.path.join(anchor, reference)
        elif kind is Kind.ABSOLUTE and os.sep == "/" and reference.startswith("/"):
            joined = reference
        elif os.name == "nt":
            joined = reference
        else:  # a drive, UNC or backslash-absolute path names nothing on this system: outside
            return Resolved(reference, kind)
        # Symbolic links are resolved before "..": "link/../x" names x beside the link's target, as
        # the operating system opens it, not x beside the link.
        path, real = os.path.normpath(joined), self.real_path(joined)
        root = None if _unresolved(real) else self.root_of(real)
        if root is not None and os.sep == "/" and "\\" in reference:
            # On Windows a backslash separates: "..\\a.png" climbs out there, so it is outside here
            # too (an asset is checked for every system it may be opened on).
            forward = reference.replace("\\", "/")
            other = self.real_path(os.path.join(anchor, forward) if kind is Kind.RELATIVE else forward)
            if _unresolved(other) or self.root_of(other) is None:
                root = None
        return Resolved(reference, kind, path, real, root)


def _unresolved(real: str) -> bool:
    """Whether resolving symbolic links stopped in a loop: a fully resolved path is never a link,
    and no prefix of it is one (``loop/x.png`` fails with ELOOP). A loop names no file, and where it
    "is" depends on where the walk stopped: it counts as outside."""
    try:
        return stat.S_ISLNK(os.lstat(real).st_mode)
    except OSError as error:
        return error.errno == errno.ELOOP
    except ValueError:  # not a path the system takes
        return True
