"""Readers and writers: the only code that knows a file format.

:func:`read_asset` picks the reader from the file's suffix. Heavy modules (``pxr``, OpenImageIO)
are imported by the reader that needs them, never here.
"""

from __future__ import annotations

import os

from ..model import Asset, Location

MTLX_SUFFIXES = (".mtlx",)
USD_SUFFIXES = (".usda", ".usdc", ".usd", ".usdz")
GLTF_SUFFIXES = (".gltf", ".glb")


class ReadError(Exception):
    """Input that cannot be read at all. ``kind`` is ``unreadable`` (I/O, encoding),
    ``not_materialx`` / ``not_usd`` / ``not_gltf`` (wrong or broken format) or ``unsupported``
    (a suffix no reader handles); the rules map kinds to codes."""

    def __init__(self, kind: str, message: str, location: Location):
        super().__init__(message)
        self.kind = kind
        self.message = message
        self.location = location


SUPPORTED_SUFFIXES = MTLX_SUFFIXES + USD_SUFFIXES + GLTF_SUFFIXES


def read_asset(path: str | os.PathLike) -> Asset:
    """Read one file into an :class:`Asset`; raises :class:`ReadError` when it cannot."""
    path = os.fspath(path)
    suffix = os.path.splitext(path)[1].lower()
    if suffix in MTLX_SUFFIXES:
        from .mtlx_reader import read_mtlx

        return read_mtlx(path)
    if suffix in USD_SUFFIXES:
        from .usd_reader import read_usd  # imports pxr only when called

        return read_usd(path)
    if suffix in GLTF_SUFFIXES:
        from .gltf_reader import read_gltf

        return read_gltf(path)
    raise ReadError("unsupported", f"no reader for files ending in {suffix or '(no suffix)'!r}", Location(path))


def available_suffixes() -> tuple[str, ...]:
    """Suffixes whose reader is part of this installation (USD and glTF readers arrive as modules)."""
    from importlib.util import find_spec

    suffixes = MTLX_SUFFIXES
    if find_spec(f"{__name__}.usd_reader") is not None:
        suffixes += USD_SUFFIXES
    if find_spec(f"{__name__}.gltf_reader") is not None:
        suffixes += GLTF_SUFFIXES
    return suffixes
