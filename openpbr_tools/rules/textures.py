"""Textures: do referenced images exist, and do they fit the input they feed.

Paths are resolved as MaterialX resolves them: the ``fileprefix`` in effect, then relative to the
document's folder. ``<UDIM>`` (and ``<UVTILE>``) paths need at least one matching tile on disk.
A texture's output type after channel selection must match the input (a colour image cannot feed
``base_metalness`` without an ``extract``), and tangent-space normal maps need a ``normalmap`` decode.
"""

from __future__ import annotations

import os
import re

from ..diagnostics import Severity
from ..io.paths import Kind, classify, climbs
from . import Rule, for_each_input

MISSING_TEXTURE = Rule(
    "OPBR701", "missing-texture", Severity.ERROR,
    "A referenced image file does not exist (for UDIM paths: no tile exists).",
    "Renderers fall back to the image node's default (often black) without failing, so the asset "
    "renders wrong rather than not at all. Paths resolve relative to the document's folder after fileprefix.",
    passing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    failing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="missing.png" colorspace="srgb_texture" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    example_files=("albedo.png",),
)
IMAGE_TYPE_MISMATCH = Rule(
    "OPBR702", "image-type-mismatch", Severity.ERROR,
    "An image's output type (after channel selection) differs from the input it feeds.",
    "A color3 image wired straight into a float input is rejected by strict readers and read as its "
    "first channel by lenient ones. Select the channel with an extract node, or declare the image float.",
    passing='<image name="metal" type="float">\n  <input name="file" type="filename" value="metal.png" colorspace="none" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_metalness" type="float" nodename="metal" />\n</open_pbr_surface>',
    failing='<image name="metal" type="color3">\n  <input name="file" type="filename" value="metal.png" colorspace="none" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_metalness" type="float" nodename="metal" />\n</open_pbr_surface>',
    example_files=("metal.png",),
)
NORMAL_WITHOUT_DECODE = Rule(
    "OPBR703", "normal-map-without-normalmap", Severity.WARNING,
    "A normal input reads an image directly, without a normalmap node.",
    "geometry_normal expects a world-space unit vector; a tangent-space normal map stores (n+1)/2 in "
    "tangent space and must be decoded by a normalmap node first.",
    passing='<image name="nrm" type="vector3">\n  <input name="file" type="filename" value="normal.png" colorspace="none" />\n</image>\n<normalmap name="decode" type="vector3">\n  <input name="in" type="vector3" nodename="nrm" />\n</normalmap>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="geometry_normal" type="vector3" nodename="decode" />\n</open_pbr_surface>',
    failing='<image name="nrm" type="vector3">\n  <input name="file" type="filename" value="normal.png" colorspace="none" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="geometry_normal" type="vector3" nodename="nrm" />\n</open_pbr_surface>',
    example_files=("normal.png",),
)
UNSAFE_PATH = Rule(
    "OPBR704", "texture-path-outside-asset", Severity.WARNING,
    "A texture path is absolute, climbs out of the asset's folder, is a URL, or escapes the folder "
    "through a symbolic link.",
    "Such an asset does not survive being copied, packaged (USDZ, GLB) or checked out elsewhere; "
    "`openpbr convert` will not read or embed such files unless --allow-outside is given.",
    passing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    failing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="../shared/albedo.png" colorspace="srgb_texture" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    example_files=("albedo.png",),
)
EMPTY_PATH = Rule(
    "OPBR705", "empty-texture-path", Severity.ERROR,
    "An image node with an empty or missing file input.",
    "The image node always returns its default value; usually a texture lost in export.",
    passing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    failing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    example_files=("albedo.png",),
)
PLACE2D_WITHOUT_TEXCOORD = Rule(
    "OPBR706", "place2d-without-texcoord", Severity.WARNING,
    "A place2d feeding an image has no texcoord connected, so every point reads the same texel.",
    "MaterialX's place2d (ND_place2d_vector2) gives texcoord no default geometric property: unconnected, "
    "it is the constant (0, 0), and MaterialX's renderers (checked with its GLSL renderer) show the texture "
    "as one flat colour, where image alone would default to the mesh's UV0. Connect a texcoord node.",
    passing='<texcoord name="uv0" type="vector2" />\n<place2d name="tile" type="vector2">\n  <input name="texcoord" type="vector2" nodename="uv0" />\n  <input name="scale" type="vector2" value="2, 2" />\n</place2d>\n<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />\n  <input name="texcoord" type="vector2" nodename="tile" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    failing='<place2d name="tile" type="vector2">\n  <input name="scale" type="vector2" value="2, 2" />\n</place2d>\n<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />\n  <input name="texcoord" type="vector2" nodename="tile" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    example_files=("albedo.png",),
)

RULES = (MISSING_TEXTURE, IMAGE_TYPE_MISMATCH, NORMAL_WITHOUT_DECODE, UNSAFE_PATH, EMPTY_PATH, PLACE2D_WITHOUT_TEXCOORD)

_TILE_TOKENS = re.compile(r"<UDIM>|<UVTILE>", re.IGNORECASE)
# Not portable whatever they resolve to: a URL, or a path not relative to the asset (io.paths).
_NOT_RELATIVE = (Kind.URL, Kind.ABSOLUTE, Kind.DRIVE, Kind.UNC)


def resolve(asset_path: str, file: str) -> str:
    """The path MaterialX would open for ``file`` referenced from ``asset_path`` (anything but a
    relative reference, as :func:`openpbr_tools.io.paths.classify` defines it, is returned as is)."""
    if classify(file) is not Kind.RELATIVE:
        return file
    return os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(asset_path)), file))


def exists(path: str, context) -> bool:
    if not _TILE_TOKENS.search(path):
        return context.file_exists(path)
    folder, pattern = os.path.split(path)
    regex = re.compile("^" + _TILE_TOKENS.sub(lambda m: r"\d{4}" if m.group(0).upper() == "<UDIM>" else r"u\d+_v\d+",
                                               re.escape(pattern).replace(r"\<", "<").replace(r"\>", ">")) + "$")
    try:
        return any(regex.match(name) for name in context.list_dir(folder or "."))
    except OSError:
        return False


def output_type(texture) -> str:
    if texture.normal_map is not None:
        return "vector3"
    if texture.channels is not None and len(texture.channels) == 1:
        return "float"
    return texture.image_type


def check(asset, context):
    checked_files: set[str] = set()
    for material, table, entry in for_each_input(asset):
        texture = entry.texture
        if texture is None:
            continue
        parameter = table.get(entry.name)
        where = texture.location or entry.location
        if not texture.file.strip():
            yield context.diagnostic(EMPTY_PATH, f"{entry.name}: image {texture.node!r} has no file", where)
        else:
            yield from _check_path(asset, texture, where, context, checked_files)
        expected = entry.type or (parameter.type if parameter else None)
        produced = output_type(texture)
        if expected and produced != expected and not (expected == "vector3" and produced == "color3" and texture.normal_map is not None):
            yield context.diagnostic(
                IMAGE_TYPE_MISMATCH, f"{entry.name} is {expected} but {texture.node!r} produces {produced}",
                entry.location, hint="add an extract node, or declare the image with the input's type",
            )
        if texture.constant_uv:
            yield context.diagnostic(
                PLACE2D_WITHOUT_TEXCOORD, f"{entry.name}: {texture.node!r} is placed by a place2d without a texcoord "
                "input, so MaterialX reads one texel everywhere", where,
                hint="connect a texcoord node (index 0) to the place2d's texcoord input")
        if parameter is not None and parameter.role == "normal" and texture.normal_map is None:
            yield context.diagnostic(
                NORMAL_WITHOUT_DECODE, f"{entry.name} reads {texture.file!r} without a normalmap decode",
                entry.location, hint="insert a normalmap node between the image and the input",
            )


def _check_path(asset, texture, where, context, checked_files):
    file = texture.file
    key = (texture.node, file)
    if key in checked_files:
        return
    checked_files.add(key)
    if texture.packaged:  # inside the asset's own package (USDZ): look there, not on disk
        if file not in asset.extra.get("package_files", ()):
            yield context.diagnostic(MISSING_TEXTURE, f"texture not found in the package: {file!r}", where)
        return
    kind = classify(file)
    if kind is Kind.NUL:
        yield context.diagnostic(UNSAFE_PATH, f"texture path {file!r} contains a NUL character", where)
        return
    guard = context.guard(asset.path)
    resolved = guard.resolve(file)
    allowed_elsewhere = resolved.inside and resolved.root != guard.own_root  # --allow-outside
    if (kind in _NOT_RELATIVE or climbs(file)) and not allowed_elsewhere:
        yield context.diagnostic(
            UNSAFE_PATH, f"texture path {file!r} points outside the asset's folder", where,
            hint="copy the texture next to the asset and use a relative path",
        )
    elif not resolved.inside:
        yield context.diagnostic(
            UNSAFE_PATH, f"texture path {file!r} leads through a symbolic link to {resolved.real}, outside the asset's folder",
            where, hint="copy the texture into the asset's folder instead of linking it",
        )
    if kind is Kind.URL:
        return
    # A drive or UNC path names no file on this system (resolved.path is None): not found.
    if resolved.path is None or not exists(resolve(asset.path, file), context):
        what = "no UDIM tile matches" if _TILE_TOKENS.search(file) else "texture not found"
        yield context.diagnostic(MISSING_TEXTURE, f"{what}: {file!r}", where)
