"""Finding the images a glTF writer embeds or copies, and refusing the ones it must not read.

A texture's file is resolved against the source asset's folder (``source``, else the folder of the
file the texture was read from, else the output's folder). Only files inside that folder, or inside
a folder the caller allows explicitly, are read; URLs are never fetched. Images inside a source
glTF (``#/images/N``, ``Texture.packaged``) are extracted from that file.
"""

from __future__ import annotations

import os
import re

from ...model import Location, Texture
from ...rules.translation import NOT_CARRIED
from ..images import channel_count
from ..paths import Kind, PathGuard, classify


class GltfWriteError(ValueError):
    """The glTF cannot be written as asked (a texture outside the allowed folders, a URL)."""


class ImageResolver:
    """Find, check and load the images textures name; hands each distinct image to the builder once."""

    def __init__(self, builder, source_path, output_path, allow_outside, notes):
        self.builder, self.notes = builder, notes
        self.source_path = source_path
        self.output_dir = os.path.dirname(os.path.abspath(output_path))
        self.allow_outside = tuple(allow_outside)
        self.guards: dict[str, PathGuard] = {}
        self.documents: dict = {}
        self._at: tuple[Location, Location | None] = (Location(source_path or ""), None)

    def folder_of(self, texture: Texture) -> str:
        anchor = self.source_path or (texture.location.file if texture.location and texture.location.file else None)
        return os.path.dirname(os.path.abspath(anchor)) if anchor else self.output_dir

    def locate(self, texture: Texture, owner: str, at: tuple[Location, Location | None] | None = None):
        """A :class:`_Source` for ``texture`` (``None`` with a note when it cannot be used). ``at`` is
        the (source, output) location of the parameter the texture feeds, where notes go."""
        self._at = at or (texture.location or Location(self.source_path or ""), None)
        file = texture.file
        if not file.strip():
            self.lost(f"{owner}: empty texture path, not written")
            return None
        if texture.packaged:
            return self._packaged(texture, owner)
        kind = classify(file)
        if kind is Kind.URL:
            raise GltfWriteError(f"{owner}: texture {file!r} is a URL; the writer never fetches URLs")
        if kind is Kind.NUL:
            raise GltfWriteError(f"{owner}: texture {file!r} contains a NUL character, which no file name can; "
                                 "it is neither read nor embedded")
        if "<UDIM>" in file.upper() or "<UVTILE>" in file.upper():
            self.lost(f"{owner}: UDIM texture {file!r} has no glTF equivalent, not written")
            return None
        folder = self.folder_of(texture)
        guard = self.guard(folder)
        resolved = guard.resolve(file)
        if not resolved.inside:
            raise GltfWriteError(
                f"{owner}: texture {file!r} resolves to {resolved.real or file}, outside the source asset's folder {guard.own_root}; "
                "it is neither read nor embedded unless its folder is allowed (allow_outside / --allow-outside)")
        real = resolved.real
        if not os.path.isfile(real):
            self.lost(f"{owner}: texture {file!r} does not exist, not written")
            return None
        name = resolved.relative if resolved.root == guard.own_root else f"textures/{os.path.basename(real)}"
        return _Source(key=("file", real), image=real, name=name, mime=_mime_of_file(real))

    def lost(self, message: str) -> None:
        """A texture that is not written (OPBR1104) at the parameter :meth:`locate` is working for."""
        location, output = self._at
        self.notes.append(NOT_CARRIED.note(message, location, output))

    def guard(self, folder: str) -> PathGuard:
        """The guard of ``folder`` and the allowed folders (one per folder: their real paths are
        resolved once)."""
        if folder not in self.guards:
            self.guards[folder] = PathGuard(folder, self.allow_outside)
        return self.guards[folder]

    def _packaged(self, texture: Texture, owner: str):
        from .document import ResourceError, load_document

        container = texture.location.file if texture.location else self.source_path
        match = re.fullmatch(r"#/images/(\d+)", texture.file)
        if not container or not container.lower().endswith((".gltf", ".glb")) or match is None:
            self.lost(f"{owner}: {texture.file!r} is inside a package the glTF writer cannot open, not written")
            return None
        if container not in self.documents:
            self.documents[container] = load_document(container)
        try:
            data, mime = self.documents[container].image_bytes(int(match.group(1)))
        except ResourceError as error:
            self.lost(f"{owner}: {texture.file!r} cannot be loaded ({error.message}), not written")
            return None
        stem = os.path.splitext(os.path.basename(container))[0]
        extension = {"image/png": ".png", "image/jpeg": ".jpg"}.get(_sniff(data) or mime or "", ".png")
        return _Source(key=("packaged", os.path.abspath(container), texture.file), image=data,
                       name=f"{stem}_image{match.group(1)}{extension}", mime=_sniff(data) or mime)


class _Source:
    __slots__ = ("key", "image", "name", "mime", "_channels")

    def __init__(self, key, image, name, mime):
        self.key, self.image, self.name, self.mime, self._channels = key, image, name, mime, None

    @property
    def channels(self) -> int:
        if self._channels is None:
            try:
                self._channels = channel_count(self.image)
            except Exception:  # not an image Pillow opens (EXR...): decided when baking
                self._channels = 4
        return self._channels

    @property
    def passes_through(self) -> bool:
        return self.mime in ("image/png", "image/jpeg")

    def data(self) -> bytes:
        if isinstance(self.image, bytes):
            return self.image
        with open(self.image, "rb") as handle:
            return handle.read()


def _sniff(data: bytes) -> str | None:
    if data.startswith(b"\x89PNG\r\n\x1a\n"):
        return "image/png"
    if data.startswith(b"\xff\xd8\xff"):
        return "image/jpeg"
    return None


def _mime_of_file(path: str) -> str | None:
    with open(path, "rb") as handle:
        return _sniff(handle.read(8))
