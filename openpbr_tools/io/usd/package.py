"""USDZ packages as usd-core reads them: the entries of the zip archive, and whether their names
are safe.

usd-core walks the local file headers from the start of the archive (it ignores the central
directory), so :func:`package_entries` does too, and refuses an archive usd-core would misread or
one too big to be safe (more than :data:`MAX_PACKAGE_ENTRIES` entries, a stored entry declaring a
size it does not store, entries declaring more than ``OPENPBR_MAX_FILE_MB`` uncompressed: a zip
bomb). :func:`unsafe_entry_name` says why an entry name would escape a folder it is extracted to
(the kinds of reference come from :mod:`openpbr_tools.io.paths`). :func:`read_layer_bytes` reads a
layer, inside a package when its identifier is package-relative.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from ...model import Location
from .. import ReadError, max_file_bytes, read_bytes
from ..paths import Kind, classify, climbs

#: A USDZ with more entries than this is refused.
MAX_PACKAGE_ENTRIES = 10_000
ZIP_MAGIC = b"PK\x03\x04"
_LOCAL_HEADER = struct.Struct("<IHHHHHIIIHH")


@dataclass(frozen=True, slots=True)
class PackageEntry:
    """A file in a USDZ as usd-core sees it: usd-core walks the local file headers from the start
    of the archive (it ignores the central directory), so this does too."""

    name: str
    method: int
    stored_size: int
    declared_size: int
    data: memoryview


def package_entries(data: bytes) -> list[PackageEntry]:
    """The entries of a USDZ's bytes, in order; raises :class:`ValueError` with the reason when
    the archive is one usd-core would misread or one too big to be safe."""
    entries, offset, view = [], 0, memoryview(data)
    while offset + _LOCAL_HEADER.size <= len(data):
        fields = _LOCAL_HEADER.unpack_from(data, offset)
        signature, method, stored, declared, name_length, extra_length = (fields[0], fields[3], fields[7], fields[8],
                                                                           fields[9], fields[10])
        start = offset + _LOCAL_HEADER.size + name_length + extra_length
        if signature != 0x04034B50 or start + stored > len(data):
            break  # where usd-core stops reading entries as well
        name = bytes(view[offset + _LOCAL_HEADER.size: offset + _LOCAL_HEADER.size + name_length]).decode("utf-8", "replace")
        if method == 0 and declared != stored:
            raise ValueError(f"entry {name!r} declares {declared} bytes but stores {stored}")
        entries.append(PackageEntry(name, method, stored, declared, view[start: start + stored]))
        if len(entries) > MAX_PACKAGE_ENTRIES:
            raise ValueError(f"more than {MAX_PACKAGE_ENTRIES} entries")
        offset = start + stored
    declared_total = sum(e.declared_size for e in entries)
    if declared_total > max_file_bytes():
        raise ValueError(f"its entries declare {declared_total / 2**20:.0f} MiB uncompressed, above the "
                         f"{max_file_bytes() / 2**20:.0f} MiB limit (OPENPBR_MAX_FILE_MB)")
    return entries


#: The file types a USDZ package may hold (OpenUSD's usdz specification; usd-core's FileExtensionValidator,
#: pxr/usdValidation/usdUtilsValidators): layers, PNG/JPEG/EXR/AVIF images and M4A/MP3/WAV audio.
USDZ_EXTENSIONS = frozenset({"usda", "usdc", "usd", "usdz", "png", "jpg", "jpeg", "exr", "avif", "m4a", "mp3", "wav"})


#: Image formats a texture may be in but a USDZ package may not hold: an error, as the texture does not load in a
#: conforming viewer. Other files a package may not hold (a LICENSE.txt) render nothing: usd-core's warning says so.
DISALLOWED_IMAGE_EXTENSIONS = frozenset({"tga", "tif", "tiff", "bmp", "gif", "webp", "psd", "hdr", "ktx", "ktx2", "dds",
                                         "jp2", "tx", "tex", "sgi", "rgb", "iff"})


def disallowed_entry_type(name: str) -> str | None:
    """Why a USDZ entry is an image in a format a package may not hold (a TGA or TIFF texture) or a MaterialX
    document (whose materials a conforming viewer does not compose), or ``None``."""
    suffix = name.rsplit(".", 1)[-1].lower() if "." in name.rsplit("/", 1)[-1] else ""
    if suffix == "mtlx" and not name.endswith("/"):  # content, not a stray file: the materials do not load
        return ("is a MaterialX document, which a USDZ package may not hold (layers, PNG, JPEG, EXR, AVIF and audio "
                "only): conforming viewers do not compose the materials it holds")
    if suffix in USDZ_EXTENSIONS or suffix not in DISALLOWED_IMAGE_EXTENSIONS or name.endswith("/"):
        return None
    return (f"is a .{suffix} file, which a USDZ package may not hold (layers, PNG, JPEG, EXR, AVIF and audio only): "
            "conforming viewers do not load it") if suffix else None


def unsafe_entry_name(name: str) -> str | None:
    """Why a USDZ entry name would escape a folder it is extracted to, or ``None``."""
    if classify(name) in (Kind.ABSOLUTE, Kind.DRIVE, Kind.UNC):
        return "is an absolute path"
    if climbs(name):
        return "climbs out of the package with '..'"
    if "\\" in name:
        return "contains a backslash"
    return None


def read_layer_bytes(path: str) -> bytes:
    """The bytes of the file a layer identifier names (inside a package when package-relative)."""
    from pxr import Ar  # lazy: pxr (0.1-0.2 s) only once the stage guard has required it

    if Ar.IsPackageRelativePath(path):
        outer, inner = Ar.SplitPackageRelativePathOuter(path)
        try:
            entries = package_entries(read_layer_bytes(outer))
        except ValueError as error:
            raise ReadError("not_usd", f"not a usable USDZ package: {error}", Location(outer)) from None
        for entry in entries:
            if entry.name == inner:
                return bytes(entry.data)
        raise ReadError("not_usd", f"the package has no file {inner!r}", Location(outer))
    return read_bytes(path)
