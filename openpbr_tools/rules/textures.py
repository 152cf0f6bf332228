"""Textures: do referenced images exist, can they be read, and do they fit the input they feed.

Paths are resolved as MaterialX resolves them: the ``fileprefix`` in effect, then relative to the
document's folder. ``<UDIM>`` (and ``<UVTILE>``) paths need at least one matching tile on disk.
A texture's output type after channel selection must match the input (a colour image cannot feed
``base_metalness`` without an ``extract``), and tangent-space normal maps need a ``normalmap`` decode.

One module because its rules are one pass over each material's textures that shares the image look-ups
(:func:`image_of`, the package cache, the files already checked or measured); split, each half would repeat them.
"""

from __future__ import annotations

import math
import os
import posixpath
import re

from ..diagnostics import Severity
from ..io import ReadError, package_member, packaged_image
from ..io.image_files import damage
from ..io.images import channel_count, image_size
from ..io.paths import Kind, classify, leaves
from ..io.tiles import TILE_TOKENS, matching_tiles, name_regex
from ..io.usd.types import is_eight_bit
from ..model import Texture
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
    "OPBR703", "normal-map-without-normalmap", Severity.ERROR,
    "A normal input reads a PNG, JPEG or other [0, 1] image directly, without a normalmap node.",
    "geometry_normal expects a world-space unit vector; a tangent-space normal map stores (n+1)/2 in "
    "tangent space and must be decoded by a normalmap node first. A PNG, JPEG, TGA, BMP or GIF image "
    "holds values in [0, 1] only, so read directly it can be no unit normal in any space: every normal tilts "
    "towards +X+Y+Z. Another format (EXR, HDR, TIFF), which may hold world-space normals, is OPBR710.",
    passing='<image name="nrm" type="vector3">\n  <input name="file" type="filename" value="normal.png" colorspace="none" />\n</image>\n<normalmap name="decode" type="vector3">\n  <input name="in" type="vector3" nodename="nrm" />\n</normalmap>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="geometry_normal" type="vector3" nodename="decode" />\n</open_pbr_surface>',
    failing='<image name="nrm" type="vector3">\n  <input name="file" type="filename" value="normal.png" colorspace="none" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="geometry_normal" type="vector3" nodename="nrm" />\n</open_pbr_surface>',
    example_files=("normal.png",),
)
UNSAFE_PATH = Rule(
    "OPBR704", "texture-path-outside-asset", Severity.WARNING,
    "A texture path (or a glTF image or buffer URI) is absolute, climbs out of the asset's folder, is a URL, or "
    "escapes the folder through a symbolic link.",
    "Such an asset does not survive being copied, packaged (USDZ, GLB) or checked out elsewhere; "
    "`openpbr convert` will not read or embed such files unless --allow-outside is given. A glTF buffer there is "
    "not read either, so the meshes it holds are not checked.",
    passing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    failing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="../shared/albedo.png" colorspace="srgb_texture" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    example_files=("albedo.png",),
)
_ALBEDO = ('<image name="albedo" type="color3">\n  <input name="file" type="filename" value="{}" colorspace="srgb_texture" />'
           '\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" '
           'nodename="albedo" />\n</open_pbr_surface>')
SHARED_FOLDER = Rule(
    "OPBR723", "texture-path-shared-folder", Severity.INFO,
    "A MaterialX or USD texture path climbs out of the asset's folder with '..' to an image that is there (a "
    "studio's shared texture folder, MaterialX's ../../../Images): not read.",
    "Relative paths into a shared folder are how MaterialX's own example library and USD asset repositories "
    "(usd-wg's ../_common) are laid out, and they resolve wherever the tree is checked out, so this is no "
    "defect. The validator still reads nothing outside the asset's folder: the image's content is not checked "
    "unless the folder that holds both is validated (a folder named on the command line is the tree its files "
    "may read from) or --allow-outside names it. glTF, a delivery format, keeps OPBR704; an absolute path, a "
    "URL, a symbolic link or a '..' to nothing is OPBR704 too.",
    passing=_ALBEDO.format("albedo.png"), failing=_ALBEDO.format("../shared/albedo.png"),
    passing_name="looks/doc.mtlx", failing_name="looks/doc.mtlx",
    example_files=("looks/albedo.png", "shared/albedo.png"),
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

_LFS_POINTER = (b"version https://git-lfs.github.com/spec/v1\n"
                b"oid sha256:4d7a214614ab2935c943f9e0ff69d22eadbb8f32b1258daaa5e2ca24d17e2393\nsize 1048576\n")
UNREADABLE_TEXTURE = Rule(
    "OPBR707", "texture-unreadable", Severity.ERROR,
    "A texture file exists but is no readable image: empty, text (a Git LFS pointer, an HTML page), a "
    "PNG or JPEG cut short or with damaged data, or a file that cannot be opened (permission denied).",
    "Renderers show such a texture as black, magenta or a half-grey image, or skip it with a log line, so "
    "the asset renders wrong without failing. A Git LFS pointer is a checkout made without `git lfs pull`; "
    "an HTML page a download that failed. A PNG's chunks and CRCs are checked and a JPEG is decoded at 1/8 "
    "scale (Pillow), so a file cut short is found without decoding it at full size; other formats are "
    "judged by their header. (The Khronos glTF-Validator reads images' headers only: it finds what the "
    "header shows, not a file cut short after it.)",
    passing=MISSING_TEXTURE.passing, failing=MISSING_TEXTURE.passing,
    example_files=("albedo.png",), failing_files=(("albedo.png", _LFS_POINTER),),
)
UNRECOGNISED_TEXTURE = Rule(
    "OPBR708", "texture-format-unrecognised", Severity.WARNING,
    "A texture file is in no image format this machine recognises.",
    "The bytes match no image format Pillow opens nor the signature of OpenEXR, Radiance HDR, KTX, Ptex, "
    "JPEG 2000, JPEG XL, AVIF/HEIF, DPX, Cineon or Basis: most likely a damaged or mislabelled file, "
    "which renderers skip. A warning rather than an error because a renderer may know a format this "
    "machine does not (the Khronos glTF-Validator's IMAGE_UNRECOGNIZED_FORMAT is a warning too).",
    passing=MISSING_TEXTURE.passing, failing=MISSING_TEXTURE.passing,
    example_files=("albedo.png",), failing_files=(("albedo.png", bytes(range(7, 256, 3)) * 4),),
)
GREY_NORMAL_MAP = Rule(
    "OPBR709", "normal-map-greyscale", Severity.WARNING,
    "A normal map's image has one channel (greyscale, or greyscale and alpha): most likely a height or bump "
    "map in the normal slot.",
    "A tangent-space normal map stores a direction in three channels (X, Y and Z as red, green and blue); a "
    "greyscale image read as one gives every texel the same tilted or flat normal, so the surface detail is "
    "wrong or gone. Use the normal map itself, or feed a height map through a bump node (MaterialX "
    "heighttonormal) instead.",
    passing=NORMAL_WITHOUT_DECODE.passing, failing=NORMAL_WITHOUT_DECODE.passing,
    example_files=("normal.png",), failing_files=(("normal.png", bytes.fromhex(
        "89504e470d0a1a0a0000000d49484452000000040000000408000000008c9ac1a2000000104944415478da636c60606060624021"
        "0009e40088ba17e1d00000000049454e44ae426082")),),
)

FLOAT_NORMAL_WITHOUT_DECODE = Rule(
    "OPBR710", "float-normal-map-without-normalmap", Severity.WARNING,
    "A normal input reads an image that may hold signed values (EXR, HDR, TIFF) directly, without a normalmap node.",
    "Unlike a PNG or JPEG, a floating-point image can store world-space unit normals with negative components, "
    "which geometry_normal takes as they are (a baked world-space normal map). A tangent-space normal map "
    "must be decoded by a normalmap node first: check which the image holds.",
    passing=NORMAL_WITHOUT_DECODE.passing.replace("normal.png", "normal.exr"),
    failing=NORMAL_WITHOUT_DECODE.failing.replace("normal.png", "normal.exr"),
    example_files=("normal.exr",),
)

_TILED = ('<tiledimage name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" '
          'colorspace="srgb_texture" />\n  <input name="uvtiling" type="vector2" value="{tiling}" />\n</tiledimage>\n'
          '<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n'
          '</open_pbr_surface>')

ZERO_UV_SCALE = Rule(
    "OPBR711", "uv-scale-zero", Severity.ERROR,
    "An image's coordinates are scaled by 0 in u or v (a tiledimage's uvtiling, a place2d's or UsdTransform2d's "
    "scale): the texture collapses to one texel, or a line of them, across the surface.",
    "tiledimage multiplies the coordinates by uvtiling, so a tiling of 0 maps every point to the same texel; "
    "place2d divides by its scale, so a 0 scale divides by zero (MaterialX's stdlib node definitions). Usually "
    "an unset tiling exported as 0. glTF's KHR_texture_transform scale of 0 is OPBR1210. An error, "
    "as OPBR1016 (a UsdUVTexture without coordinates) is: the texture the author painted does not show at all.",
    passing=_TILED.format(tiling="4, 4"), failing=_TILED.format(tiling="0, 0"), example_files=("albedo.png",),
)

_TWO_READS = ('<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" '
              'colorspace="srgb_texture" />\n</image>\n<image name="rough" type="float">\n  <input name="file" '
              'type="filename" value="{file}" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n'
              '  <input name="base_color" type="color3" nodename="albedo" />\n'
              '  <input name="specular_roughness" type="float" nodename="rough" />\n</open_pbr_surface>')

COLOUR_IMAGE_AS_DATA = Rule(
    "OPBR712", "colour-image-read-as-data", Severity.WARNING,
    "One image feeds a colour input as a colour and a float input (roughness, metalness, opacity, a weight) "
    "through its red, green or blue channel.",
    "A colour image's channels are colours, not a roughness or a mask: an auto-assign script picked the base "
    "colour file for the roughness slot (oak_roughness.png sat beside it), or a cut-out reads the leaf's red "
    "channel because the image has no alpha. Packing data beside a colour goes in the alpha channel (Unity's "
    "smoothness in albedo alpha), which is not reported.",
    passing=_TWO_READS.format(file="rough.png"), failing=_TWO_READS.format(file="albedo.png"),
    example_files=("albedo.png", "rough.png"),
)

#: The largest texture Direct3D 11/12 (D3D11_REQ_TEXTURE2D_U_OR_V_DIMENSION) and Apple GPUs under Metal load.
GPU_TEXTURE_LIMIT = 16384

TEXTURE_TOO_LARGE = Rule(
    "OPBR713", "texture-too-large", Severity.WARNING,
    f"An image is wider or taller than {GPU_TEXTURE_LIMIT} pixels.",
    f"Direct3D 11/12 (D3D11_REQ_TEXTURE2D_U_OR_V_DIMENSION) and Metal on Apple GPUs load textures of at most "
    f"{GPU_TEXTURE_LIMIT} pixels a side: a larger one fails to load or is downscaled by the renderer, and a "
    "400-megapixel scan costs over a gigabyte of memory per channel set. Usually a source scan exported at full "
    "resolution.",
    passing=_TILED.format(tiling="1, 1"), failing=_TILED.format(tiling="1, 1").replace("albedo.png", "huge.png"),
    example_files=("albedo.png", "huge.png"),
    failing_files=(("huge.png", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\x00\x00N \x00\x00\x00\x04\x08\x02\x00\x00\x00"),),
)

RULES = (MISSING_TEXTURE, IMAGE_TYPE_MISMATCH, NORMAL_WITHOUT_DECODE, UNSAFE_PATH, SHARED_FOLDER, EMPTY_PATH,
         PLACE2D_WITHOUT_TEXCOORD, UNREADABLE_TEXTURE, UNRECOGNISED_TEXTURE, GREY_NORMAL_MAP, FLOAT_NORMAL_WITHOUT_DECODE, ZERO_UV_SCALE,
         COLOUR_IMAGE_AS_DATA, TEXTURE_TOO_LARGE)

# Case-sensitive, as MaterialX (UDIM_TOKEN, UV_TILE_TOKEN) and OpenUSD (UsdShadeUdimUtils) substitute them:
# "<udim>" is read as part of a file name, so its tiles are never found.
_TILE_TOKENS = TILE_TOKENS
_MISCASED_TOKEN = re.compile(r"<(udim|uvtile)>", re.IGNORECASE)
# Not portable whatever they resolve to: a URL, or a path not relative to the asset (io.paths).
_NOT_RELATIVE = (Kind.URL, Kind.ABSOLUTE, Kind.DRIVE, Kind.UNC)


def resolve(asset_path: str, file: str) -> str:
    """The path MaterialX would open for ``file`` referenced from ``asset_path`` (anything but a
    relative reference, as :func:`openpbr_tools.io.paths.classify` defines it, is returned as is)."""
    if classify(file) is not Kind.RELATIVE:
        return file
    return os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(asset_path)), file))


def tiled(asset, file: str) -> bool:
    """Whether ``file`` names tiles (``<UDIM>``, ``<UVTILE>``): in MaterialX and USD; a glTF URI names one file,
    tokens and all (the Khronos glTF-Validator's IO_ERROR; the red team's F#16: its tiles were found)."""
    return asset.format != "gltf" and bool(_TILE_TOKENS.search(file))


def exists(path: str, context, tiles_named: bool = True) -> bool:
    if not (tiles_named and _TILE_TOKENS.search(path)):
        return context.file_exists(path)
    return bool(tiles(path, context))


def _in_package(asset, texture) -> bool:
    """Whether the packaged ``texture`` is an entry of the asset's package: one of its tiles at least, for a
    tile set (a .usdz packages a <UDIM> set as its tiles, as UsdUtils.CreateNewUsdzPackage does)."""
    members = asset.extra.get("package_files", ())
    if not tiled(asset, texture.file):
        return texture.file in members
    folder, pattern = posixpath.split(texture.file)
    names = [posixpath.basename(m) for m in members if posixpath.dirname(m) == folder]
    return bool(matching_tiles(pattern, names))


def tiles(path: str, context) -> list[str]:
    """The files a ``<UDIM>``/``<UVTILE>`` path names on disk, in name order."""
    folder, pattern = os.path.split(path)
    regex = name_regex(pattern)
    try:
        return [os.path.join(folder, name) for name in sorted(context.list_dir(folder or ".")) if regex.match(name)]
    except OSError:
        return []


def output_type(texture) -> str:
    if texture.normal_map is not None:
        return "vector3"
    if texture.channels is not None and len(texture.channels) == 1:
        return "float"
    if texture.channels is not None and len(texture.channels) == 3 and texture.image_type[-1:] == "4":
        return texture.image_type[:-1] + "3"  # a color4 image converted to color3
    return texture.image_type


def check(asset, context):
    checked_files: set[str] = set()
    containers: dict = {}  # packaged_image's cache of loaded packages
    sized: set[str] = set()
    normal_files: set[str] = set()  # files judged as normal maps (OPBR709), once each
    yield from _colour_read_as_data(asset, context)
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
        if texture.file not in sized:
            sized.add(texture.file)
            image = image_of(asset, texture, context, containers)
            size = image_size(image) if image is not None else None
            if size is not None and max(size) > GPU_TEXTURE_LIMIT:
                yield context.diagnostic(
                    TEXTURE_TOO_LARGE, f"{entry.name}: {texture.file!r} is {size[0]} x {size[1]} pixels, beyond the "
                    f"{GPU_TEXTURE_LIMIT} a side GPUs load", where, hint=f"downscale it to {GPU_TEXTURE_LIMIT} or less")
        if texture.uv is not None and any(v in (0.0, math.inf) for v in texture.uv.scale) and not _gltf(texture):
            # (a tiledimage's tiling and a UsdTransform2d's scale multiply the coordinates: read as place2d's dividing
            # scale, so the authored factor is its inverse; the red team's F#13 was told "(1, inf)" for a scale (1, 0))
            tiled = texture.node_category in ("tiledimage", "UsdUVTexture")
            factors = tuple(1.0 / v for v in texture.uv.scale) if tiled else tuple(texture.uv.scale)
            yield context.diagnostic(
                ZERO_UV_SCALE, f"{entry.name}: {texture.node!r} "
                f"{'tiles' if texture.node_category == 'tiledimage' else 'scales'} its coordinates by "
                f"({factors[0]:g}, {factors[1]:g}): the texture collapses to one texel "
                "(a tiling of 0) or divides by zero (a scale of 0)", where, hint="set the tiling or scale to 1 (no tiling)")
        if texture.constant_uv:
            yield context.diagnostic(
                PLACE2D_WITHOUT_TEXCOORD, f"{entry.name}: {texture.node!r} is placed by a place2d without a texcoord "
                "input, so MaterialX reads one texel everywhere", where,
                hint="connect a texcoord node (index 0) to the place2d's texcoord input")
        if parameter is not None and parameter.role == "normal" and texture.normal_map is None:
            inner = package_member(texture.file)
            eight_bit = is_eight_bit(inner) or inner.lower().endswith(".webp")
            yield context.diagnostic(
                NORMAL_WITHOUT_DECODE if eight_bit else FLOAT_NORMAL_WITHOUT_DECODE,
                f"{entry.name} reads {texture.file!r} without a normalmap decode"
                + (": the image format holds no unit normal (every value is in [0, 1])" if eight_bit else ""),
                entry.location, hint="insert a normalmap node between the image and the input",
            )
        if texture.normal_map is not None or (parameter is not None and parameter.role == "normal"):
            normal_files.add(texture.file)
            yield from _grey_normal_map(asset, texture, f"{entry.name}: the normal map", where, context, containers)
    for observation in (o for o in asset.observations if o.kind == "mtlx_normalmap_image"):
        # an image a normalmap decodes that no input reads as a texture (a computed texcoord)
        file, node = observation.detail["file"], observation.detail["node"]
        if file not in normal_files:
            normal_files.add(file)
            yield from _grey_normal_map(asset, Texture(file=file, node=node), f"{observation.detail['normalmap']} "
                                        "decodes", observation.location, context, containers)
    for observation in (o for o in asset.observations if o.kind == "mtlx_image_file"):
        # the files of images no input reads as a texture (a computed texcoord, a procedural graph): the same checks
        file, node = observation.detail["file"], observation.detail["node"]
        if not any(checked == file or checked_node == node for checked_node, checked in checked_files):  # (as a texture)
            yield from _check_path(asset, Texture(file=file, node=node), observation.location, context, checked_files)


def _grey_normal_map(asset, texture, what: str, where, context, containers):
    channels = _channels(asset, texture, context, containers)
    if channels in (1, 2):
        yield context.diagnostic(
            GREY_NORMAL_MAP, f"{what} {texture.file!r} is a greyscale image ({channels} "
            f"channel{'s' if channels > 1 else ''}), not a normal map", where,
            hint="use the normal map, or turn a height map into normals with a heighttonormal node")


def _check_path(asset, texture, where, context, checked_files):
    file = texture.file
    key = (texture.node, file)
    if key in checked_files:
        return
    checked_files.add(key)
    if texture.packaged:  # inside the asset's own package (USDZ): look there, not on disk
        if not _gltf(texture) and classify(file) in _NOT_RELATIVE:  # (the red team's B19: as for a .usda's)
            yield context.diagnostic(UNSAFE_PATH, f"texture path {file!r} points outside the package", where,
                                     hint="package the texture and name it relative to the layer")
        if not _in_package(asset, texture):
            yield context.diagnostic(MISSING_TEXTURE, f"the embedded image {file!r} has no data to read: its bufferView "
                                     "or buffer is missing or broken (reported at the buffer)" if _gltf(texture)
                                     else f"texture not found in the package: {file!r}", where)
        elif not _gltf(texture):
            yield from _damaged(_packaged(asset, file, {}), file, where, context)
        return
    kind = classify(file)
    if kind is Kind.NUL:
        yield context.diagnostic(UNSAFE_PATH, f"texture path {file!r} contains a NUL character", where)
        return
    guard = context.guard(asset.path)
    resolved = guard.resolve(file)
    allowed_elsewhere = resolved.inside and resolved.root != guard.own_root  # --allow-outside
    shared = kind not in _NOT_RELATIVE and leaves(file) and not _gltf(texture) and resolved.path is not None \
        and os.path.isfile(resolved.path)  # (a stat, nothing read)
    if shared and not allowed_elsewhere:
        yield context.diagnostic(
            SHARED_FOLDER, f"texture path {file!r} climbs out of the asset's folder to an image that is there: not read",
            where, hint="validate the folder that holds both, or pass --allow-outside to check the image too")
        return
    if (kind in _NOT_RELATIVE or leaves(file)) and not allowed_elsewhere:
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
    # A drive or UNC path names no file on this system (resolved.path is None): not found. Where it is
    # looked for is where the system opens it: symbolic links resolved before ".." (the guard's real path).
    if resolved.path is None or not exists(resolved.real or resolve(asset.path, file), context, tiled(asset, file)):
        what = "no UDIM tile matches" if tiled(asset, file) else "texture not found"
        miscased = [m.group(0) for m in _MISCASED_TOKEN.finditer(file) if not _TILE_TOKENS.fullmatch(m.group(0))]
        hint = (f"tile tokens are case-sensitive: {miscased[0]!r} is read as part of the file name; "
                f"write {miscased[0].upper()!r}") if miscased else None
        yield context.diagnostic(MISSING_TEXTURE, f"{what}: {file!r}", where, hint=hint)
    elif not tiled(asset, file) and os.path.isdir(resolved.real or resolve(asset.path, file)):
        # an empty file name under a fileprefix ("textures/" + ""), or a path cut short: a folder loads no image
        yield context.diagnostic(MISSING_TEXTURE, f"texture path {file!r} names a folder, not an image file", where,
                                 hint="name the image file (an image node without one renders its default)")
    elif resolved.inside and not _gltf(texture):  # a glTF's images are judged by the glTF family, used or not
        readable, outside = _files(asset, file, context)
        for name, real in outside:
            yield context.diagnostic(
                UNSAFE_PATH, f"texture tile {name!r} leads through a symbolic link to {real}, outside the asset's folder",
                where, hint="copy the tile into the asset's folder instead of linking it")
        for name, real in readable:
            yield from _damaged(real, name, where, context)


def _colour_read_as_data(asset, context):
    """OPBR712: per material, an image read as a colour by a colour input and through a colour channel (R, G or
    B, not A) by a float input."""
    for material in asset.materials:
        colours, data = {}, []
        for name, texture in material.textures():
            entry = material.inputs[name]
            if texture.normal_map is not None or not texture.file.strip():
                continue
            if (entry.type or "").startswith("color") and (texture.channels is None or len(texture.channels) == 3):
                colours.setdefault(texture.file, name)
            elif entry.type == "float" and (texture.channels is None or texture.channels[0] in (0, 1, 2)):
                data.append((name, texture, entry))
        for name, texture, entry in data:
            if texture.file in colours:
                channel = "RGB"[texture.channels[0]] if texture.channels else "R"
                yield context.diagnostic(
                    COLOUR_IMAGE_AS_DATA, f"{name} reads channel {channel} of {texture.file!r}, which "
                    f"{colours[texture.file]} reads as a colour: a colour image read as data", entry.location,
                    hint=f"point {name} at its own map (or pack the data in the image's alpha channel)")


def _gltf(texture) -> bool:
    return texture.node_category == "gltf_texture"


def _files(asset, file: str, context) -> tuple[list[tuple[str, str]], list[tuple[str, str]]]:
    """(readable, outside): the files ``file`` names as (name, real path) -- every tile of a UDIM path --
    split by the path guard. Only a readable one may be opened: its real path (symbolic links resolved
    before "..", as the system opens it) is a regular file inside the asset's folder or an allowed one."""
    guard = context.guard(asset.path)
    if tiled(asset, file):
        folder, pattern = os.path.dirname(file), guard.resolve(file)
        names = [(f"{file} (tile {os.path.basename(tile)})", os.path.join(folder, os.path.basename(tile)))
                 for tile in tiles(pattern.real or resolve(asset.path, file), context)]
    else:
        names = [(file, file)]
    readable, outside = [], []
    for name, reference in names:
        resolved = guard.resolve(reference)
        if not resolved.inside:
            outside.append((name, resolved.real or reference))
        elif resolved.real and context.file_exists(resolved.real) and os.path.isfile(resolved.real):
            readable.append((name, resolved.real))  # (isfile: not a folder, a FIFO or a device)
    return readable, outside


def _packaged(asset, file: str, containers: dict) -> bytes | None:
    try:
        return packaged_image(asset.path, file, containers)[0]
    except ReadError:
        return None  # the package itself is reported by the reader


def _damaged(image, file: str, where, context):
    found = damage(image) if image is not None else None
    if found is not None:
        yield damage_diagnostic(context, found, f"texture {file!r}", where, REMEDY)


def damage_diagnostic(context, found, subject: str, where, remedy: dict):
    """The finding for an image that is no readable image (:func:`~openpbr_tools.io.image_files.damage`):
    OPBR708 for bytes in no known format, else OPBR707; ``remedy`` gives the hint per kind (key ``None``:
    the default)."""
    rule = UNRECOGNISED_TEXTURE if found.kind == "unrecognised" else UNREADABLE_TEXTURE
    return context.diagnostic(rule, f"{subject} is {found.detail}", where, hint=remedy.get(found.kind, remedy[None]))


_LFS_REMEDY = "fetch or re-export the real image (for a Git LFS pointer: git lfs pull)"
REMEDY = {"text": _LFS_REMEDY, "empty": "re-export the image", "corrupt": "re-export or re-download the image",
          "unreadable": "give the user running the renderer read permission on the file (chmod a+r)",
          "unrecognised": "re-export the image as PNG, JPEG or OpenEXR", None: "re-export the image"}
EMBEDDED_REMEDY = {"text": _LFS_REMEDY, None: "re-export or re-embed the image"}  # a glTF's images


def image_of(asset, texture, context, containers: dict) -> str | bytes | None:
    """The image ``texture`` reads (the first tile of a UDIM path) as a path or bytes, or ``None`` when
    it may not or cannot be read (outside the asset's folder, a URL, missing, not in the package)."""
    file = texture.file
    if not file.strip():
        return None
    if texture.packaged:
        return _packaged(asset, file, containers) if file in asset.extra.get("package_files", ()) else None
    readable, _ = _files(asset, file, context)  # a URL, a drive or UNC path: outside, never readable
    return readable[0][1] if readable else None


def _channels(asset, texture, context, containers: dict) -> int | None:
    """How many channels the image ``texture`` reads has, or ``None`` when it cannot be told."""
    image = image_of(asset, texture, context, containers)
    if image is None:
        return None
    try:
        return channel_count(image)
    except Exception:  # noqa: BLE001 - not an image Pillow opens: OPBR707/OPBR708 say so where it matters
        return None
