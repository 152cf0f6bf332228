"""Readers and writers: the only code that knows a file format.

:func:`read_asset` picks the reader from the file's suffix. Heavy modules (``pxr``, OpenImageIO)
are imported by the reader that needs them, never here.
"""

from __future__ import annotations

import io
import os
import re
import stat
from importlib.util import find_spec

from ..model import Asset, Location

MTLX_SUFFIXES = (".mtlx",)
USD_SUFFIXES = (".usda", ".usdc", ".usd", ".usdz")
GLTF_SUFFIXES = (".gltf", ".glb")


class ReadError(Exception):
    """Input that cannot be read at all. ``kind`` is ``unreadable`` (I/O, encoding),
    ``not_materialx`` / ``not_usd`` / ``not_gltf`` (wrong or broken format) or ``unsupported``
    (a suffix no reader handles); the rules map kinds to codes. ``convert_file`` raises two more when
    the input holds nothing to write: ``no_material`` and ``xinclude_broken`` (MaterialX reads nothing)."""

    def __init__(self, kind: str, message: str, location: Location):
        super().__init__(message)
        self.kind = kind
        self.message = message
        self.location = location


SUPPORTED_SUFFIXES = MTLX_SUFFIXES + USD_SUFFIXES + GLTF_SUFFIXES

# Inputs larger than this are refused before parsing (MaterialX holds a document in memory at about
# ten times its size on disk); set OPENPBR_MAX_FILE_MB to change it.
DEFAULT_MAX_FILE_MB = 64


def max_file_bytes() -> int:
    try:
        return int(float(os.environ.get("OPENPBR_MAX_FILE_MB", DEFAULT_MAX_FILE_MB)) * 1024 * 1024)
    except ValueError:
        return DEFAULT_MAX_FILE_MB * 1024 * 1024


def read_bytes(path: str) -> bytes:
    """The bytes of a regular file no larger than :func:`max_file_bytes`; :class:`ReadError` otherwise.

    Only regular files are opened: a FIFO or a device would block or never end."""
    try:
        info = os.stat(path)
    except OSError as error:
        raise ReadError("unreadable", f"cannot read file: {error.strerror or error}", Location(path)) from None
    if not stat.S_ISREG(info.st_mode):
        raise ReadError("unreadable", "not a regular file", Location(path))
    limit = max_file_bytes()
    if info.st_size > limit:
        raise ReadError("unreadable", f"file is {info.st_size / 2**20:.0f} MiB, above the {limit / 2**20:.0f} MiB limit "
                        "(OPENPBR_MAX_FILE_MB)", Location(path))
    try:
        with open(path, "rb") as handle:
            return handle.read(limit + 1)
    except OSError as error:
        raise ReadError("unreadable", f"cannot read file: {error.strerror or error}", Location(path)) from None


def read_asset(path: str | os.PathLike, allow_outside: tuple[str, ...] = (), included_by: str | None = None) -> Asset:
    """Read one file into an :class:`Asset`; raises :class:`ReadError` when it cannot. What the file
    pulls in (XIncludes, USD sublayers/references/payloads, glTF buffers and images) is read from the
    file's folder or a folder in ``allow_outside`` only (:mod:`openpbr_tools.io.paths`). ``included_by``: the
    MaterialX document that XIncludes this one (read in its composition)."""
    path = os.fspath(path)
    suffix = os.path.splitext(path)[1].lower()
    # Each reader is imported when its suffix is met: chosen at run time, and every reader imports
    # ReadError from this package (a cycle at load time).
    if suffix in MTLX_SUFFIXES:
        from .mtlx.reader import read_mtlx  # lazy: chosen by suffix (see above)

        return read_mtlx(path, allow_outside=tuple(allow_outside), included_by=included_by)
    if suffix in USD_SUFFIXES:
        from .usd.reader import read_usd  # imports pxr only when called

        return read_usd(path, allow_outside=tuple(allow_outside))
    if suffix in GLTF_SUFFIXES:
        from .gltf.reader import read_gltf  # lazy: chosen by suffix (see above)

        return read_gltf(path, tuple(allow_outside))
    raise ReadError("unsupported", f"no reader for files ending in {suffix or '(no suffix)'!r}", Location(path))


PACKAGED_IMAGE_SUFFIXES = GLTF_SUFFIXES  # containers whose embedded images can be read back out


def packaged_image(container: str, member: str, cache: dict | None = None) -> tuple[bytes, str | None]:
    """The bytes and MIME type of image ``member`` stored inside ``container``: ``#/images/N`` of a
    ``.gltf``/``.glb``, or a path inside a ``.usdz`` package (a zip archive, read with
    :mod:`zipfile`); :class:`ReadError` when the container or the image cannot be read, or
    ``member`` names no image. ``cache`` keeps loaded containers between calls."""
    if container.lower().endswith(".usdz"):
        return _usdz_member(container, member)
    match = re.fullmatch(r"#/images/(\d+)", member)
    if match is None or not container.lower().endswith(PACKAGED_IMAGE_SUFFIXES):
        raise ReadError("unsupported", f"{member!r} is not an image of a glTF container", Location(container))
    from .gltf.document import load_document  # lazy, like the readers: only a packaged texture needs it

    cache = {} if cache is None else cache
    if container not in cache:
        cache[container] = load_document(container)
    return cache[container].image_bytes(int(match.group(1)))


def package_member(path: str) -> str:
    """The member a package path names (``textures/n.png`` of ``x.usdz[textures/n.png]``), or ``path``."""
    return path.split("[", 1)[-1].rstrip("]") if path.endswith("]") else path


#: A compressed USDZ member inflating to more than this many times its stored size (and to more than 1 MiB) is
#: refused as a zip bomb. USD stores members uncompressed ("compressed files are not supported"), so any ratio above
#: 1 is already an OPBR1012 finding; a deflated PNG or JPEG hardly shrinks, while a bomb inflates a thousandfold.
MAX_COMPRESSION_RATIO = 100


def _member_bytes(archive, name: str, container) -> bytes:
    """The bytes of package member ``name``, inflated in chunks and never past :func:`max_file_bytes` or
    :data:`MAX_COMPRESSION_RATIO` times its stored size (the sizes the archive declares are checked first, and
    not trusted): :class:`ReadError` for a member beyond either."""
    import zipfile  # lazy: as in _usdz_member

    info = archive.getinfo(name)
    limit = max_file_bytes()
    compressed = info.compress_type != zipfile.ZIP_STORED
    ceiling = min(limit, max(1 << 20, MAX_COMPRESSION_RATIO * info.compress_size)) if compressed else limit

    def refused(size: int) -> ReadError:
        why = (f"above the {limit / 2**20:.0f} MiB limit (OPENPBR_MAX_FILE_MB)" if size > limit else
               f"more than {MAX_COMPRESSION_RATIO} times the {info.compress_size:,} bytes it is compressed to "
               "(a zip bomb; USD reads only uncompressed members)")
        return ReadError("unreadable", f"{name!r} inflates to {size:,} bytes or more, {why}: not read", Location(
            container if isinstance(container, str) else ""))

    if info.file_size > ceiling:
        raise refused(info.file_size)
    chunks, total = [], 0
    with archive.open(info) as stream:
        while chunk := stream.read(1 << 20):
            total += len(chunk)
            if total > ceiling:
                raise refused(total)
            chunks.append(chunk)
    return b"".join(chunks)


def _usdz_member(container: str, member: str) -> tuple[bytes, str | None]:
    import zipfile  # lazy: only a texture packaged in a USDZ needs it

    try:
        with zipfile.ZipFile(container) as archive:
            outer, _, nested = member.lstrip("./").partition("[")
            if nested.endswith("]") and outer.lower().endswith(".usdz") and outer in archive.namelist():
                # a member of a package nested in this one: "parts/b.usdz[textures/a.png]"
                try:
                    return _usdz_member(io.BytesIO(_member_bytes(archive, outer, container)),  # type: ignore[arg-type]
                                        nested[:-1])
                except ReadError as error:
                    raise ReadError(error.kind, f"{member!r}: {error.message}", Location(container)) from None
            data = _member_bytes(archive, package_member(member).lstrip("./"), container)
    except KeyError:
        raise ReadError("unreadable", f"{member!r} is not in the package", Location(container)) from None
    except (OSError, zipfile.BadZipFile) as error:
        raise ReadError("unreadable", f"the package cannot be opened ({error})", Location(container)) from None
    mime = "image/png" if data.startswith(b"\x89PNG") else "image/jpeg" if data.startswith(b"\xff\xd8\xff") else None
    return data, mime


def available_suffixes() -> tuple[str, ...]:
    """Suffixes whose reader is part of this installation (USD and glTF readers arrive as modules)."""
    suffixes = MTLX_SUFFIXES
    if find_spec(f"{__name__}.usd.reader") is not None:
        suffixes += USD_SUFFIXES
    if find_spec(f"{__name__}.gltf.reader") is not None:
        suffixes += GLTF_SUFFIXES
    return suffixes
