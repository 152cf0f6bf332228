"""The images a glTF writer embeds or copies: located by :class:`openpbr_tools.io.images.ImageLocator`
(the one path guard decides what may be read; URLs are never fetched; images inside a source glTF
are extracted from it), with what glTF adds: a UDIM set has no glTF equivalent, a texture that
cannot be read is reported (OPBR1104) at the parameter it feeds and left out, and one that must not
be read refuses the whole output (:class:`GltfWriteError`).
"""

from __future__ import annotations

import os

from ...model import Location, Texture
from ...rules.translation import NOT_CARRIED
from ..images import ImageLocator, ImageRefused, ImageSource, ImageUnavailable
from ..paths import Kind, classify


class GltfWriteError(ValueError):
    """The glTF cannot be written as asked (a texture outside the allowed folders, a URL)."""


class ImageResolver:
    """Find, check and load the images textures name; ``notes`` receives what is left out."""

    def __init__(self, source_path, output_path, allow_outside, notes):
        self.notes = notes
        self.locator = ImageLocator(source_path, os.path.dirname(os.path.abspath(output_path)), allow_outside)
        self.source_path = source_path

    def locate(self, texture: Texture, owner: str, at: tuple[Location, Location | None] | None = None) -> ImageSource | None:
        """The image of ``texture`` (``None`` with a note when it cannot be used). ``at`` is the
        (source, output) location of the parameter the texture feeds, where notes go."""
        at = at or (texture.location or Location(self.source_path or ""), None)
        file = texture.file
        if file.strip() and not texture.packaged and classify(file) not in (Kind.URL, Kind.NUL) and \
                ("<UDIM>" in file or "<UVTILE>" in file):
            self.notes.append(NOT_CARRIED.note(f"{owner}: UDIM texture {file!r} has no glTF equivalent, not written", *at))
            return None
        try:
            return self.locator.locate(texture, owner)
        except ImageRefused as error:
            raise GltfWriteError(str(error)) from None
        except ImageUnavailable as error:
            self.notes.append(NOT_CARRIED.note(str(error), *at))
            return None
