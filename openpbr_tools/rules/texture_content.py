"""What a texture file holds against how the material reads it (the red team's round five): a file whose bytes
are another format than its name says, a scene-linear image decoded as sRGB, a UDIM set without its first tile,
an OpenEXR layer the file does not have, an unsigned image read as a tangent, a rotation written in the other angle
unit (radians for place2d's degrees, degrees for KHR_texture_transform's and anisotropyRotation's radians), and
a packed occlusion-roughness-metalness map read through its occlusion channel (OPBR712).

Formats are judged from the first bytes (:data:`SIGNATURES`); an OpenEXR file's layers from its header, read by
OpenImageIO (the images extra; without it the layer is not judged). Nothing is decoded."""

from __future__ import annotations

import math
import os
import re

from .. import colorspaces
from ..diagnostics import Severity
from ..io.image_files import head_of
from ..io.usd.types import is_eight_bit
from ..model import Location
from . import Rule, for_each_input
from .textures import COLOUR_IMAGE_AS_DATA, _TILE_TOKENS, _files, _gltf, tiles

#: (first bytes, format) of the image formats a texture file name promises by its suffix.
SIGNATURES = ((b"\x89PNG\r\n\x1a\n", "PNG"), (b"\xff\xd8\xff", "JPEG"), (b"v/1\x01", "OpenEXR"),
              (b"II*\x00", "TIFF"), (b"MM\x00*", "TIFF"), (b"#?RADIANCE", "Radiance HDR"), (b"#?RGBE", "Radiance HDR"),
              (b"GIF8", "GIF"), (b"BM", "BMP"), (b"RIFF", "WebP"), (b"8BPS", "PSD"))
SUFFIXES = {".png": "PNG", ".jpg": "JPEG", ".jpeg": "JPEG", ".exr": "OpenEXR", ".tif": "TIFF", ".tiff": "TIFF",
            ".hdr": "Radiance HDR", ".gif": "GIF", ".bmp": "BMP", ".webp": "WebP", ".psd": "PSD"}
#: formats that hold scene-linear floating-point values (OpenEXR's and Radiance's convention)
LINEAR_FORMATS = ("OpenEXR", "Radiance HDR")

_PNG_NAME = '<image name="albedo" type="color3">\n  <input name="file" type="filename" value="{file}" colorspace="srgb_texture" />\n</image>\n'
_SHADER = ('<open_pbr_surface name="S" type="surfaceshader">\n  <input name="{input}" type="{type}" nodename="{node}" />\n'
           '</open_pbr_surface>')
_TIFF = b"II*\x00\x08\x00\x00\x00" + b"\x00" * 24

CONTENT_NOT_SUFFIX = Rule(
    "OPBR714", "texture-content-not-suffix", Severity.ERROR,
    "A texture file holds another image format than its name's suffix says (a TIFF named .png).",
    "Loaders that choose their decoder by the suffix (MaterialX's stb_image loader, browsers and engines that trust "
    "the name or the MIME type derived from it) fail on the file or show garbage; only loaders that sniff the "
    "content (OpenImageIO) read it, so the asset renders in one tool and not the next. Usually a file renamed "
    "instead of re-exported.",
    passing=_PNG_NAME.format(file="albedo.tif") + _SHADER.format(input="base_color", type="color3", node="albedo"),
    failing=_PNG_NAME.format(file="albedo.png") + _SHADER.format(input="base_color", type="color3", node="albedo"),
    example_files=("albedo.tif", "albedo.png"), failing_files=(("albedo.png", _TIFF),),
)

LINEAR_IMAGE_AS_SRGB = Rule(
    "OPBR715", "linear-image-decoded-as-srgb", Severity.WARNING,
    "An OpenEXR or Radiance HDR image is tagged with an sRGB-encoded colour space (srgb_texture, a gamma 2.2 one).",
    "OpenEXR and Radiance files hold scene-linear floating-point values by convention (the OpenEXR documentation: "
    "\"pixel values are linear\"); MaterialX's colour management applies the tag as authored, so its GLSL runs the "
    "sRGB decode (NG_srgb_texture_to_lin_rec709) on values that are already linear: mid-tones darken, highlights "
    "above 1 are bent. Tag it with the linear space it was rendered in (lin_rec709, acescg).",
    passing=_PNG_NAME.format(file="albedo.exr").replace("srgb_texture", "lin_rec709")
    + _SHADER.format(input="base_color", type="color3", node="albedo"),
    failing=_PNG_NAME.format(file="albedo.exr") + _SHADER.format(input="base_color", type="color3", node="albedo"),
    example_files=("albedo.exr",),
)

FIRST_TILE_MISSING = Rule(
    "OPBR716", "udim-first-tile-missing", Severity.WARNING,
    "A UDIM (or UVTILE) texture set has tiles, but not the first one (1001, u1_v1), which UVs in [0, 1] read.",
    "MaterialX and USD resolve <UDIM> per point from its UV: coordinates in the unit square read tile 1001. A set "
    "exported from 1002 on (a tile deleted, a renumbering, a missing download) leaves every surface in the 0-1 "
    "square with the image's default, usually black.",
    passing=_PNG_NAME.format(file="albedo.<UDIM>.png") + _SHADER.format(input="base_color", type="color3", node="albedo"),
    failing=_PNG_NAME.format(file="tile.<UDIM>.png") + _SHADER.format(input="base_color", type="color3", node="albedo"),
    example_files=("albedo.1001.png", "albedo.1002.png", "tile.1002.png"),
)

LAYER_MISSING = Rule(
    "OPBR717", "exr-layer-missing", Severity.WARNING,
    "An image node's layer names a layer (channel prefix) the OpenEXR file does not have.",
    "MaterialX reads the channels \"<layer>.R\", \"<layer>.G\"... of a multi-layer OpenEXR file; with no such "
    "channels the image renders its default. Usually a layer renamed in the compositing or baking tool "
    "(diffuse for albedo). Judged from the file's header (OpenImageIO's channel names).",
    passing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="layers.exr" />\n</image>\n'
    + _SHADER.format(input="base_color", type="color3", node="albedo"),
    failing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="layers.exr" />\n'
    '  <input name="layer" type="string" value="albedo" />\n</image>\n'
    + _SHADER.format(input="base_color", type="color3", node="albedo"),
    example_files=("layers.exr",),
)

_TANGENT = ('<image name="flow" type="vector3">\n  <input name="file" type="filename" value="flow.png" />\n</image>\n{extra}'
            '<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_roughness_anisotropy" type="float" '
            'value="0.8" />\n  <input name="geometry_tangent" type="vector3" nodename="{node}" />\n</open_pbr_surface>')
_DECODED = ('<multiply name="scaled" type="vector3">\n  <input name="in1" type="vector3" nodename="flow" />\n'
            '  <input name="in2" type="vector3" value="2, 2, 2" />\n</multiply>\n<subtract name="decoded" type="vector3">\n'
            '  <input name="in1" type="vector3" nodename="scaled" />\n  <input name="in2" type="vector3" value="1, 1, 1" />\n'
            '</subtract>\n')
TANGENT_FROM_UNSIGNED = Rule(
    "OPBR718", "tangent-from-unsigned-image", Severity.WARNING,
    "A tangent input (geometry_tangent, geometry_coat_tangent, Standard Surface's tangent) reads an 8-bit image "
    "(PNG, JPEG) directly, whose values are all in [0, 1], or reads a normal map through a normalmap node (a normal, "
    "not a tangent).",
    "A tangent is a direction with signed components; a flow or direction map stores them as 0.5 + 0.5 t. Read "
    "without the decode (2 t - 1, a multiply and a subtract, or a normalmap node in tangent space), every tangent "
    "points into the positive octant and the anisotropic highlight runs along the wrong direction (MaterialX's "
    "GLSL passes the value as it is).",
    passing=_TANGENT.format(extra=_DECODED, node="decoded"), failing=_TANGENT.format(extra="", node="flow"),
    example_files=("flow.png",),
)

_PLACED = ('<texcoord name="uv" type="vector2" />\n<place2d name="turned" type="vector2">\n'
           '  <input name="texcoord" type="vector2" nodename="uv" />\n  <input name="rotate" type="float" value="{rotate}" />\n'
           '</place2d>\n<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" '
           'colorspace="srgb_texture" />\n  <input name="texcoord" type="vector2" nodename="turned" />\n</image>\n')
ROTATION_UNIT = Rule(
    "OPBR719", "texture-rotation-unit", Severity.WARNING,
    "A texture-space rotation is written in the other angle unit: a multiple of pi/12, pi/8 or pi/18 in radians "
    "(1.5708, 0.7854, 0.3927) where place2d rotate or UsdTransform2d rotation take degrees, or a multiple of 15 degrees from 15 to 360 "
    "(90, 45) where glTF's KHR_texture_transform rotation or KHR_materials_anisotropy's anisotropyRotation (the "
    "anisotropy direction's turn in the tangent frame) takes radians.",
    "MaterialX's place2d and UsdPreviewSurface's UsdTransform2d take degrees (MaterialX's GLSL converts with "
    "mx_radians), while glTF's KHR_texture_transform (\"Rotate the UVs by this many radians\") and most scripting "
    "APIs take radians: 1.5708 meant as a quarter turn rotates the texture by 1.6 degrees, and a glTF rotation of 90 "
    "(a DCC's degrees) by 90 radians, 116.6 degrees past 14 turns. KHR_materials_anisotropy's anisotropyRotation is "
    "likewise \"measured in radians counter-clockwise from the tangent\" (its README; the draft KHR_materials_coat's "
    "coatAnisotropyRotation follows it): 90 meant as a quarter turn brushes the highlight at 116.6 degrees instead. No "
    "radian value needs more than a full turn (2 pi), so a glTF rotation is reported only when it is a multiple of 15 "
    "from 15 to 360 (the angles a UI offers in degrees); another whole number (7) is left alone.",
    passing=_PLACED.format(rotate="90") + _SHADER.format(input="base_color", type="color3", node="albedo"),
    failing=_PLACED.format(rotate="1.5708") + _SHADER.format(input="base_color", type="color3", node="albedo"),
    example_files=("albedo.png",),
)

_SMOOTH = ('<image name="mask" type="color4">\n  <input name="file" type="filename" value="{file}" />\n</image>\n'
           '<extract name="a" type="float">\n  <input name="in" type="color4" nodename="mask" />\n'
           '  <input name="index" type="integer" value="3" />\n</extract>\n')
SMOOTHNESS_AS_ROUGHNESS = Rule(
    "OPBR721", "smoothness-read-as-roughness", Severity.WARNING,
    "A roughness input reads a smoothness (glossiness) map as it is: a file named for smoothness or gloss, or the "
    "alpha of a Unity mask map (its smoothness), with no inversion.",
    "Unity's HDRP mask map holds smoothness in its alpha (R metallic, G occlusion, B detail mask, A smoothness) and "
    "glossiness maps hold 1 - roughness: read as roughness without 1 - x, polished parts render matte and matte "
    "parts glossy. Invert it on the way (an invert node, or scale -1 and bias 1).",
    passing=_SMOOTH.format(file="oak_MaskMap.png") + '<invert name="rough" type="float">\n  <input name="in" type="float" '
    'nodename="a" />\n</invert>\n' + _SHADER.format(input="specular_roughness", type="float", node="rough"),
    failing=_SMOOTH.format(file="oak_MaskMap.png") + _SHADER.format(input="specular_roughness", type="float", node="a"),
    example_files=("oak_MaskMap.png",),
)

_TAGGED = ('<image name="albedo" type="color3">\n  <input name="file" type="filename" value="{file}" '
           'colorspace="acescg" />\n</image>\n')
SRGB_IMAGE_AS_LINEAR = Rule(
    "OPBR722", "srgb-image-tagged-linear", Severity.WARNING,
    "A colour input reads an 8-bit PNG that declares itself sRGB-encoded (its sRGB chunk) with a linear colour space "
    "(acescg, lin_rec709): the sRGB curve is never removed.",
    "A PNG's sRGB chunk says its values are sRGB-encoded (the PNG specification, 11.3.3.5); MaterialX applies the "
    "tag as authored, so an acescg tag runs only the AP1 to Rec.709 matrix on encoded values: the albedo renders too "
    "bright and washed out (its GLSL calls NG_acescg_to_lin_rec709 and no sRGB decode). Tag it srgb_texture (or the "
    "encoded space it was painted in).",
    passing=_TAGGED.format(file="albedo.png").replace("acescg", "srgb_texture")
    + _SHADER.format(input="base_color", type="color3", node="albedo"),
    failing=_TAGGED.format(file="albedo.png") + _SHADER.format(input="base_color", type="color3", node="albedo"),
    example_files=("albedo.png",),
    failing_files=(("albedo.png", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\x00\x00\x00\x01\x00\x00\x00\x01\x08\x02\x00\x00"
                                  b"\x00\x90wS\xde\x00\x00\x00\x01sRGB\x00\xae\xce\x1c\xe9\x00\x00\x00\x0cIDATx\x9cc8Q"
                                  b"\xa1\x01\x00\x03t\x01i\xcb\xfa\xd0\xd7\x00\x00\x00\x00IEND\xaeB`\x82"),),
)

RULES = (CONTENT_NOT_SUFFIX, LINEAR_IMAGE_AS_SRGB, FIRST_TILE_MISSING, LAYER_MISSING, TANGENT_FROM_UNSIGNED,
         ROTATION_UNIT, SMOOTHNESS_AS_ROUGHNESS, SRGB_IMAGE_AS_LINEAR)

_TANGENT_INPUTS = ("geometry_tangent", "geometry_coat_tangent", "tangent", "coat_tangent")
#: a packed map named for glTF's occlusion-roughness-metalness layout (R occlusion): "oak_ORM.png", "arm"
_OCCLUSION_FIRST = re.compile(r"(?:^|[_\-. ])(orm|arm|occlusionroughnessmetal(?:lic|ness)?)(?:[_\-. ]|$)", re.IGNORECASE)
# radians of the angles a UI offers (10, 15 and 22.5 degree steps): as degrees, a tilt no one types to four decimals
_RADIANS = tuple(sorted({k * math.pi / n for n in (8, 12, 18) for k in range(1, 2 * n + 1)}))
_DEGREE_STEPS = frozenset(range(15, 361, 15))  # the angles a UI offers, in degrees: none is a plausible radian value


def check(asset, context):
    if asset.format == "gltf":
        for material in asset.materials:
            yield from _anisotropy_rotation_in_degrees(material, context)
    seen: set = set()
    for material, table, entry in for_each_input(asset):
        texture = entry.texture
        if texture is not None and _gltf(texture) and texture.node not in seen:
            seen.add(texture.node)
            yield from _rotation_in_degrees(asset, texture, context)
        if texture is None or not texture.file.strip() or _gltf(texture):
            continue
        where = texture.location or entry.location
        key = (texture.node, texture.file)
        first = key not in seen
        seen.add(key)
        files = _readable(asset, texture, context) if first else []
        # the file a texture reads (a UDIM set's first tile) and its format from its first bytes, read once
        image = files[0] if files else None
        found = _format(image[1]) if image is not None else None
        if first:
            yield from _content(image, found, texture, where, context)
            yield from _first_tile(asset, texture, where, context)
            yield from _layer(image, found, texture, where, context)
            yield from _rotation(texture, where, context)
        if entry.name in _TANGENT_INPUTS and texture.normal_map is None and texture.scale is None \
                and texture.bias is None and is_eight_bit(texture.file):
            yield context.diagnostic(
                TANGENT_FROM_UNSIGNED, f"{entry.name} reads {texture.file!r} as it is: an 8-bit image holds values in "
                "[0, 1], so every tangent points into the positive octant", entry.location,
                hint="decode it first (multiply by 2, subtract 1), or feed a world-space tangent")
        elif entry.name in _TANGENT_INPUTS and texture.normal_map is not None:
            yield context.diagnostic(
                TANGENT_FROM_UNSIGNED, f"{entry.name} reads the normal map {texture.file!r} through a normalmap node: "
                "that gives the shading normal, perpendicular to the tangent plane, not a tangent", entry.location,
                hint="feed the tangent a tangent (a flow map decoded to [-1, 1]); the normal map goes to geometry_normal")
        if entry.name in _ROUGHNESS_INPUTS and _smoothness(texture):
            yield context.diagnostic(
                SMOOTHNESS_AS_ROUGHNESS, f"{entry.name} reads {texture.file!r}"
                + (f" channel {'RGBA'[texture.channels[0]]}" if texture.channels else "")
                + ", a smoothness (glossiness) map, as it is: smooth areas render rough", entry.location,
                hint="invert it (an invert node, or a scale of -1 and a bias of 1)")
        if first and found == "PNG" and parameter_role(table, entry.name) == "color":
            yield from _declared_srgb(image, texture, entry, context)
        if entry.type == "float" and texture.channels in (None, (0,)) and texture.image_type in ("float", None) \
                and entry.name != "occlusion" and _OCCLUSION_FIRST.search(os.path.splitext(os.path.basename(texture.file))[0]):
            yield context.diagnostic(
                COLOUR_IMAGE_AS_DATA, f"{entry.name} reads channel R of {texture.file!r}, a packed occlusion-roughness-"
                "metalness map whose R is the occlusion (a float image reads the first channel)", entry.location,
                hint="read G (roughness) or B (metalness) with an extract node, or a separate3's outg / outb")


_ROUGHNESS_INPUTS = ("specular_roughness", "coat_roughness", "fuzz_roughness", "roughness")
_SMOOTHNESS_NAME = re.compile(r"(smooth|gloss)", re.IGNORECASE)


def _smoothness(texture) -> bool:
    """A texture that holds smoothness read without an inversion (its scale not negative)."""
    stem = os.path.splitext(os.path.basename(texture.file))[0]
    inverted = texture.scale is not None and isinstance(texture.scale, (int, float)) and texture.scale < 0
    if inverted or texture.image_type not in ("float", "color4", "color3", None):
        return False
    mask_alpha = "maskmap" in stem.lower() and texture.channels == (3,)
    return mask_alpha or bool(_SMOOTHNESS_NAME.search(stem))


def parameter_role(table, name: str) -> str | None:
    parameter = table.get(name)
    return parameter.role if parameter is not None else None


def _declared_srgb(image, texture, entry, context):
    """OPBR722: an 8-bit PNG (``image``: (name, path)) with an sRGB chunk read through a linear colour space."""
    if colorspaces.transfer(colorspaces.materialx_name(texture.colorspace)) != "linear":
        return
    name, real = image
    try:
        from PIL import Image  # lazy: Pillow only for a PNG a colour input reads through a linear space

        with Image.open(real) as opened:
            declared = "srgb" in opened.info and opened.mode in ("RGB", "RGBA", "P", "L", "LA")
    except (OSError, ValueError):
        return
    if declared:
        yield context.diagnostic(
            SRGB_IMAGE_AS_LINEAR, f"{entry.name} reads {name!r}, whose sRGB chunk declares sRGB-encoded values, "
            f"through the linear colour space {texture.colorspace!r}: the sRGB curve is never removed",
            entry.location, hint="tag it srgb_texture")


def _readable(asset, texture, context) -> list[tuple[str, str]]:
    if texture.packaged:
        return []
    readable, _ = _files(asset, texture.file, context)
    return readable


def _format(path: str) -> str | None:
    head = head_of(path, 16)
    return next((name for signature, name in SIGNATURES if head.startswith(signature)), None)


def _content(image, found, texture, where, context):
    """OPBR714 and OPBR715 for ``image`` ((name, path), or None), whose first bytes say it is ``found``."""
    if image is None:
        return
    name, real = image
    promised = SUFFIXES.get(os.path.splitext(real)[1].lower())
    if promised and found and found != promised:
        yield context.diagnostic(
            CONTENT_NOT_SUFFIX, f"texture {name!r} is a {found} image named as {promised}: loaders that pick the "
            "decoder by the name fail on it", where, hint=f"re-export it as {promised}, or name it for what it is")
    elif found in LINEAR_FORMATS and texture.colorspace not in (None, "auto") and \
            colorspaces.encoded(colorspaces.materialx_name(texture.colorspace)):
        yield context.diagnostic(
            LINEAR_IMAGE_AS_SRGB, f"texture {name!r} is {found} (scene-linear) but tagged "
            f"{texture.colorspace!r}: its values are decoded as sRGB", where,
            hint="tag it with the linear colour space it holds (lin_rec709, acescg)")


def _first_tile(asset, texture, where, context):
    token = _TILE_TOKENS.search(texture.file)
    if token is None or texture.packaged or asset.format == "gltf":  # (a glTF URI names one file: rules.textures)
        return
    guard = context.guard(asset.path)
    pattern = guard.resolve(texture.file)
    if not pattern.inside:
        return
    found = [os.path.basename(t) for t in tiles(pattern.real or texture.file, context)]
    first = "1001" if token.group(0) == "<UDIM>" else "u1_v1"
    expected = os.path.basename(texture.file).replace(token.group(0), first)
    if found and expected not in found:
        yield context.diagnostic(
            FIRST_TILE_MISSING, f"texture {texture.file!r} has {len(found)} tile(s) but not {expected!r}, which UVs in "
            "[0, 1] read: the surface there renders the image's default", where,
            hint=f"restore tile {first}, or move the UVs to the tiles that exist")


def _layer(image, found, texture, where, context):
    if not texture.layer or found != "OpenEXR":
        return
    name, real = image
    channels = _exr_channels(real)
    if channels is None:
        return
    prefix = texture.layer + "."
    if not any(channel.startswith(prefix) for channel in channels):
        layers = sorted({c.rsplit(".", 1)[0] for c in channels if "." in c})
        yield context.diagnostic(
            LAYER_MISSING, f"texture {name!r} has no layer {texture.layer!r}"
            + (f" (its layers: {', '.join(layers)})" if layers else " (it has no layers, only the channels "
               + ", ".join(channels[:6]) + ")"), where, hint="name one of the file's layers")


def _exr_channels(path: str) -> list[str] | None:
    try:
        import OpenImageIO as oiio  # lazy: the images extra; only a file an image node reads a layer of
    except ImportError:
        return None
    found = oiio.ImageInput.open(path)
    if found is None:
        oiio.geterror()
        return None
    names = []
    subimage = 0
    while found.seek_subimage(subimage, 0):
        names += list(found.spec().channelnames)
        subimage += 1
    found.close()
    return names


def degrees_as_radians(rotation: float) -> int | None:
    """The whole degrees a glTF angle (radians) looks typed in, or ``None``: a multiple of 15 degrees from 15 to 360,
    each beyond the 2 pi any radian value needs (a 7 is some turn in radians, seen in files; 90 a quarter turn)."""
    turned = abs(rotation)
    if math.isfinite(turned) and abs(turned - round(turned)) < 1e-6 and round(turned) in _DEGREE_STEPS:
        return round(rotation)
    return None


def _rotation_in_degrees(asset, texture, context):
    """A KHR_texture_transform rotation typed in degrees (:func:`degrees_as_radians`)."""
    if texture.uv is None:
        return
    rotation = -math.radians(texture.uv.rotate)  # the file's radians (io.gltf.uv: rotate = -degrees(rotation))
    shown = degrees_as_radians(rotation)
    if shown is not None:
        yield context.diagnostic(
            ROTATION_UNIT, f"{texture.node}: KHR_texture_transform rotation {shown} is {shown} radians, "
            f"{abs(rotation) / (2 * math.pi):.1f} turns: {shown} degrees written where glTF takes radians?",
            Location(asset.path, None, f"{texture.node}/extensions/KHR_texture_transform", "rotation"),
            hint=f"write {math.radians(shown):.6g} (the radians of {shown} degrees)")


_ANISOTROPY_ROTATIONS = (("anisotropy_rotation", "KHR_materials_anisotropy", "anisotropyRotation"),
                         ("coat_anisotropy_rotation", "KHR_materials_coat", "coatAnisotropyRotation"))


def _anisotropy_rotation_in_degrees(material, context):
    """KHR_materials_anisotropy's anisotropyRotation (and the draft KHR_materials_coat's coatAnisotropyRotation),
    "measured in radians", typed in degrees (:func:`degrees_as_radians`)."""
    drafts = ((material.extra.get("gltf") or {}).get("drafts") or {})
    for name, extension, property_name in _ANISOTROPY_ROTATIONS:
        entry = material.inputs.get(name) if name == "anisotropy_rotation" else drafts.get(extension, {}).get(name)
        value = entry.constant if entry is not None else None
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            continue
        shown = degrees_as_radians(float(value))
        if shown is not None:
            yield context.diagnostic(
                ROTATION_UNIT, f"{material.name}: {extension} {property_name} {shown} is {shown} radians, "
                f"{abs(value) / (2 * math.pi):.1f} turns: {shown} degrees written where the extension takes radians?",
                entry.location, hint=f"write {math.radians(shown):.6g} (the radians of {shown} degrees)")


def _rotation(texture, where, context):
    rotate = abs(texture.uv.rotate) if texture.uv is not None else 0.0
    if 0.0 < rotate <= 2 * math.pi + 1e-3 and rotate != round(rotate) and \
            any(abs(rotate - r) < 5e-4 for r in _RADIANS):
        yield context.diagnostic(
            ROTATION_UNIT, f"{texture.node!r} rotates its coordinates by {rotate:g} degrees: "
            f"{math.degrees(rotate):.4g} degrees written in radians?", where,
            hint=f"the node takes degrees: write {math.degrees(rotate):.4g}")
