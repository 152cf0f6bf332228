"""Where a USD output's textures are: re-anchored at the output's folder for a layer (.usda, .usdc), or
packaged into a .usdz, which carries what it names (``packaged_files``: package path -> real path, for the
packaging step of :mod:`.writer`). A package takes only files inside the source asset's folder (or one
allowed), as :mod:`openpbr_tools.io.paths` decides; a ``<UDIM>`` set is packaged as its tiles, as
``UsdUtils.CreateNewUsdzPackage`` packages one, and a MaterialX ``<UVTILE>`` set is packaged by its tiles' UDIM
numbers, as USD substitutes ``<UDIM>`` only (:mod:`openpbr_tools.io.tiles`).
"""

from __future__ import annotations

import os

from ...model import Texture
from ...rules.translation import CONVERTED, NOT_CARRIED
from ..image_files import damage
from ..paths import Kind, Resolved, classify
from ..tiles import TILE_TOKENS, matching_tiles, tile_name


class UsdWriteError(ValueError):
    """The USD cannot be written as asked (a texture to package from outside the allowed folders)."""


class TextureFiles:
    """The texture-file half of the USD writer (a mixin: ``package``, ``source_dir``, ``target_dir``, ``guard``,
    ``target``, ``packaged_files`` and ``note`` are the writer's)."""

    def texture_path(self, texture: Texture, owner: str) -> str:
        file = texture.file
        kind = classify(file) if file else Kind.EMPTY
        if kind is Kind.URL and self.package and file[:5].lower() == "file:":  # a local file outside, as an
            raise UsdWriteError(f"{owner}: texture {file!r} is a file URL, a file outside the source asset's folder "
                                "by another name; a .usdz carries its textures, and this one is not packaged "
                                "(an absolute path is refused alike)")  # absolute path; a web or data URL stays named
        if kind in (Kind.EMPTY, Kind.URL):
            return file
        if texture.packaged and kind is Kind.RELATIVE:
            self.note(NOT_CARRIED, f"{owner}: {file!r} is inside the source package and is not copied")
            return file
        if not self.package:
            if "<UVTILE>" in file:  # (the tiles are other files, named for MaterialX: nothing to rename them)
                self.note(NOT_CARRIED, f"{owner}: {file!r} names its tiles with MaterialX's <UVTILE>, which USD does "
                          "not substitute (it knows <UDIM> only): USD renderers find no tile; rename the tiles by "
                          "their UDIM numbers (u1_v1 is 1001) or write a .usdz, which packages them so named")
            if kind is Kind.RELATIVE:  # re-anchored at the output's folder (only referenced, never read)
                absolute = os.path.normpath(os.path.join(self.source_dir, file))
                return os.path.relpath(absolute, self.target_dir).replace(os.sep, "/")
            return self.target.resolve(file).relative or file
        if TILE_TOKENS.search(file):
            return self.packaged_tiles(file, kind, owner)
        resolved = self.inside_or_refused(file, kind, owner)
        real = resolved.real
        if not os.path.isfile(real):
            self.note(NOT_CARRIED, f"{owner}: {file!r} does not exist and is not packaged")
            return file
        found = damage(real)
        if found is not None:
            self.note(NOT_CARRIED, f"{owner}: {file!r} is {found.detail} and is not packaged")
            return file
        return self.packaged_as(resolved, os.path.basename(real))

    def inside_or_refused(self, file: str, kind: Kind, owner: str) -> Resolved:
        """``file`` resolved, which a .usdz output packages: inside the source asset's folder or an allowed one,
        else :class:`UsdWriteError` (a package carries what it names)."""
        resolved = self.guard.resolve(file)
        if not resolved.inside:
            where = f"resolves to {resolved.real}" if resolved.real else \
                "is not a path (it holds a NUL byte)" if kind is Kind.NUL else f"is a {kind.value} path"
            raise UsdWriteError(
                f"{owner}: texture {file!r} {where}, outside the source asset's folder {self.guard.own_root}; "
                "it is not packaged into the .usdz unless its folder is allowed (allow_outside / --allow-outside)")
        return resolved

    def packaged_tiles(self, file: str, kind: Kind, owner: str) -> str:
        """A UDIM or UVTILE set packaged into the .usdz: every tile on disk (each inside the allowed folders,
        as a single texture), named by its UDIM number, as UsdUtils.CreateNewUsdzPackage packages a <UDIM>
        path; a <UVTILE> set is renamed so (USD substitutes <UDIM> only). The package path of the set."""
        folder, pattern = os.path.split(file.replace("\\", "/"))
        real_folder = self.inside_or_refused(folder or ".", kind, owner).real
        try:
            names = [n for n in os.listdir(real_folder) if os.path.isfile(os.path.join(real_folder, n))]
        except OSError:
            names = []
        named = pattern.replace("<UVTILE>", "<UDIM>")
        packaged = None
        for name, number in matching_tiles(pattern, names):
            tile = f"{folder}/{name}" if folder else name
            resolved = self.inside_or_refused(tile, kind, owner)  # (a tile may be a link out of the folder)
            found = damage(resolved.real)
            if found is not None:
                self.note(NOT_CARRIED, f"{owner}: tile {tile!r} is {found.detail} and is not packaged")
                continue
            packaged = self.packaged_as(resolved, tile_name(named, number), pattern=named)
        if packaged is None:
            self.note(NOT_CARRIED, f"{owner}: no tile of {file!r} exists, so none is packaged")
            return file
        if named != pattern:
            self.note(CONVERTED, f"{owner}: the <UVTILE> tiles of {file!r} are packaged by their UDIM numbers "
                      f"({packaged}), as USD substitutes <UDIM> only")
        return packaged

    def packaged_as(self, resolved: Resolved, name: str, pattern: str | None = None) -> str:
        """Package the file ``resolved`` names as ``name`` in the .usdz: at its place in the source asset's folder,
        else in ``textures/``, renamed when another file already has that name; the package path (of the tile set,
        ``pattern``, for a tile)."""
        real = resolved.real
        folder = os.path.dirname(resolved.relative) if resolved.root == self.guard.own_root else "textures"
        inside = f"{folder}/{name}" if folder else name
        stem, suffix = os.path.splitext(inside)
        count = 1
        while self.packaged_files.get(inside, real) != real:
            count += 1
            inside = f"{stem}_{count}{suffix}"
        self.packaged_files[inside] = real
        if pattern is None:
            return inside
        return f"{folder}/{pattern}" if folder else pattern
