"""USD colour spaces, for the ``usd`` rule family (:mod:`openpbr_tools.rules.usd`, which registers
the rule defined here in its ``RULES``): a colour-space name from the wrong naming scheme
(OPBR1004) or unknown (OPBR502), colour textures read raw (OPBR503), data textures bent by a
colour transform (OPBR504), and the project's colour-space policies (OPBR505, OPBR506) for stages.

Colour-space names come in three schemes and each place wants one: ``Usd.ColorSpaceAPI`` and
USD-native shaders want USD names, the inputs of MaterialX shaders want MaterialX names, and
UsdUVTexture's ``sourceColorSpace`` wants ``raw``, ``sRGB`` or ``auto``. The policies are stated in
MaterialX names, so USD names and UsdUVTexture tokens are compared through their MaterialX
equivalents. A texture's bit depth is judged from its file's suffix; the image is not opened.
"""

from __future__ import annotations

import os

import difflib

from .. import colorspaces
from ..diagnostics import Severity
from ..io.images import image_layout
from ..io.usd.types import UV_TEXTURE_ID, is_eight_bit
from ..model import Location, Texture
from . import Rule, for_each_input
from . import colorspace as colorspace_rules
from .colorspace import (COLOR_TEXTURE_RAW, COLORSPACE_IGNORED, DATA_TEXTURE_MANAGED, UNKNOWN_COLORSPACE, ignored_colorspace,
                         scene_linear_file)
from .usd_examples import openpbr_example

def _materialx_image_example(colorspace: str) -> str:
    """An OpenPBR stage whose base colour reads a MaterialX image tagged ``colorspace``."""
    return openpbr_example(
        "color3f inputs:base_color.connect = </M/albedo.outputs:out>",
        extra='\n    def Shader "albedo"\n    {\n        uniform token info:id = "ND_image_color3"\n'
              f'        asset inputs:file = @albedo.png@ (\n            colorSpace = "{colorspace}"\n        )\n'
              "        color3f outputs:out\n    }\n",
    )


COLORSPACE_SCHEME = Rule(
    "OPBR1004", "usd-colorspace-scheme", Severity.ERROR,
    "A colour-space name from the wrong naming scheme: a MaterialX name where USD wants a USD name, "
    "or the reverse.",
    "Usd.ColorSpaceAPI and USD-native shaders take USD names (srgb_rec709_scene, lin_ap1_scene, raw); "
    "MaterialX shaders' inputs take MaterialX names (srgb_texture, acescg, none); UsdUVTexture's "
    "sourceColorSpace takes raw, sRGB or auto. A name from the other scheme is stored and treated as no "
    "conversion: MaterialX 1.39.5 prints 'Unsupported color space transform' and skips it, MaterialX's "
    "main branch refuses to generate the shader (#2954). The hint gives the equivalent name in the right "
    "scheme. A USD name that MaterialX 1.39.4+ maps to its own on a MaterialX shader's input is OPBR1014 "
    "(info), not this; USD's raw on a float or vector image is no finding (MaterialX converts colour "
    "outputs only, and no conversion is what raw asks for).",
    passing=_materialx_image_example("srgb_texture"),
    failing=openpbr_example(
        "color3f inputs:base_color.connect = </M/albedo.outputs:rgb>",
        extra='\n    def Shader "albedo"\n    {\n        uniform token info:id = "UsdUVTexture"\n'
              '        asset inputs:file = @albedo.png@\n        token inputs:sourceColorSpace = "srgb_texture"\n'
              "        float3 outputs:rgb\n    }\n",
    ),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",), example_files=("albedo.png",),
)
REMAPPED_NAME = Rule(
    "OPBR1014", "usd-colorspace-name-remapped", Severity.INFO,
    "A MaterialX shader's input in USD carries a USD (Gf) colour-space name that MaterialX maps to its own.",
    "OpenUSD passes colorSpace metadata to MaterialX unchanged (hdMtlx), and MaterialX 1.39.4 and newer "
    "map Gf names to theirs in the default colour management system (srgb_rec709_scene to srgb_texture, "
    "lin_rec709_scene to lin_rec709, ...), so the texture renders correctly there; MaterialX before 1.39.4 "
    "does not know the name and skips the conversion. UsdMtlx writes MaterialX names: prefer them.",
    passing=_materialx_image_example("srgb_texture"),
    failing=_materialx_image_example("srgb_rec709_scene"),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",), example_files=("albedo.png",),
)


# -- colour-space names ---------------------------------------------------------------------------

def colorspace_name(detail, where, context):
    name, scheme = detail["name"], detail["scheme"]
    materialx, usd = colorspaces.materialx_names(), colorspaces.usd_names()
    if scheme == "usd":
        if name in usd:
            return
        if name in materialx:
            meant = colorspaces.usd_equivalent(name)
            yield context.diagnostic(
                COLORSPACE_SCHEME, f"{name!r} is a MaterialX colour-space name; {detail['owner']} takes USD names",
                where, hint=f"use {meant!r}" if meant else "use a USD colour-space name (Gf.ColorSpaceNames)",
            )
            return
        guess = colorspaces.suggest(name, "usd")
        yield context.diagnostic(
            UNKNOWN_COLORSPACE, f"unknown colour space {name!r}: USD treats it as no conversion", where,
            hint=f"did you mean {guess!r}?" if guess else "use a USD colour-space name (Gf.ColorSpaceNames)",
        )
    elif scheme == "materialx":
        if name in materialx:
            return
        if detail.get("colour_output") is False and colorspaces.is_data(name, "usd"):
            return  # USD's "no conversion" on a float or vector image: MaterialX converts colour outputs only
        if name in usd:
            meant = colorspaces.materialx_equivalent(name) or ("none" if colorspaces.is_data(name, "usd") else None)
            if colorspaces.materialx_equivalent(name) and not colorspaces.is_data(name, "usd"):
                yield context.diagnostic(
                    REMAPPED_NAME, f"{name!r} is a USD colour-space name: MaterialX 1.39.4 and newer read it as "
                                   f"{meant!r}, older MaterialX skips the conversion", where, hint=f"use {meant!r}",
                )
                return
            yield context.diagnostic(
                COLORSPACE_SCHEME,
                f"{name!r} is a USD colour-space name; inputs of MaterialX shaders take MaterialX names", where,
                hint=f"use {meant!r}" if meant else "use a MaterialX colour-space name",
            )
            return
        guess = colorspaces.suggest(name)
        yield context.diagnostic(
            UNKNOWN_COLORSPACE, f"unknown colour space {name!r}: MaterialX will not convert it", where,
            hint=f"did you mean {guess!r}?" if guess else f"known: {', '.join(sorted(materialx))}",
        )
    else:  # UsdUVTexture sourceColorSpace
        tokens = colorspaces.usd_uvtexture_names()
        if name in tokens:
            return
        if name in materialx or name in usd:
            meant = "raw" if (colorspaces.is_data(name) or colorspaces.is_data(name, "usd")) else (
                "sRGB" if _is_encoded(name) else "raw")
            yield context.diagnostic(
                COLORSPACE_SCHEME, f"sourceColorSpace takes raw, sRGB or auto, not the colour-space name {name!r}",
                where, hint=f"use {meant!r}",
            )
            return
        guess = difflib.get_close_matches(name, tokens, n=1, cutoff=0.5)
        yield context.diagnostic(
            UNKNOWN_COLORSPACE, f"sourceColorSpace {name!r} is not raw, sRGB or auto", where,
            hint=f"did you mean {guess[0]!r}?" if guess else "use raw, sRGB or auto",
        )


def _is_encoded(name: str | None) -> bool:
    """True for colour spaces with a non-linear transfer curve (sRGB, gamma 2.2 ...), in any scheme."""
    if not name:
        return False
    for candidate in (name, colorspaces.materialx_equivalent(name)):
        if colorspaces.transfer(candidate) is not None:
            return colorspaces.encoded(candidate)
    return name == "sRGB" or name.startswith(("srgb_", "g18_", "g22_", "g24_"))


# -- colour-managed textures ------------------------------------------------------------------------

def colour_managed_textures(asset, context):
    for material, table, entry in for_each_input(asset):
        parameter = table.get(entry.name)
        texture = entry.texture
        if parameter is None or texture is None:
            continue
        space = texture.colorspace
        if texture.node_category != UV_TEXTURE_ID and ignored_colorspace(texture):
            yield context.diagnostic(
                COLORSPACE_IGNORED, f"{entry.name} reads the {texture.image_type} image {texture.file!r} with colour "
                                    f"space {space!r}, which MaterialX ignores and other renderers apply",
                texture.location or entry.location, hint='set colorSpace = "none" on the image\'s inputs:file',
            )
        if parameter.role == "color":
            if space is not None and (colorspaces.is_data(space) or colorspaces.is_data(space, "usd")) \
                    and not scene_linear_file(texture.file):
                yield context.diagnostic(
                    COLOR_TEXTURE_RAW, f"{entry.name} reads {texture.file!r} as raw data ({space})", entry.location,
                    hint="read it as sRGB (sourceColorSpace = \"sRGB\", or colorSpace \"srgb_texture\" on a MaterialX image)",
                )
        elif parameter.role in ("data", "normal", "tangent"):
            why = _bends(texture, asset, context)
            if why:
                yield context.diagnostic(
                    DATA_TEXTURE_MANAGED, f"{entry.name} is data but reads {texture.file!r} {why}", entry.location,
                    hint='set sourceColorSpace = "raw"' if texture.node_category == UV_TEXTURE_ID
                    else 'set colorSpace = "none" on the image\'s inputs:file',
                )


def _bends(texture: Texture, asset, context) -> str | None:
    if texture.reads_alpha:
        return None
    space = texture.colorspace
    if texture.node_category == UV_TEXTURE_ID:
        if space == "sRGB" or (space not in ("raw", "sRGB", "auto", None) and _is_encoded(space)):
            return f"through colour space {space!r}"
        if space in (None, "auto") and _auto_decodes_srgb(texture, asset, context):
            return "with sourceColorSpace auto, which decodes 8-bit RGB(A) images as sRGB"
        return None
    if texture.image_type in ("color3", "color4") and _is_encoded(space):
        return f"through colour space {space!r}"
    return None


def _auto_decodes_srgb(texture: Texture, asset, context) -> bool:
    """Whether Storm reads the image as sRGB under ``sourceColorSpace = "auto"``. OpenUSD's image
    readers (pxr/imaging/hio/stbImage.cpp and plugin/hioOiio/oiioImage.cpp, IsColorSpaceSRGB) decide
    from the file: a PNG ``gAMA`` of 1/2.2 means sRGB and 1.0 linear (stb); otherwise only images
    with 3 or 4 channels are sRGB, read as 8 bits (stb reads every PNG and JPEG at 8 bits, so a
    16-bit RGB PNG is decoded as sRGB too). A greyscale roughness map is therefore read raw. The suffix
    decides for a packaged image and for one that does not decode; one that cannot be opened here (outside
    the folders allowed, missing) is not judged: its channels are unknown (the red team's G/F7: 16-bit
    greyscale maps beside the folder, a false error)."""
    if not texture.packaged and texture.file:
        resolved = context.guard(asset.path).resolve(texture.file)
        real = resolved.real if resolved.inside else None  # the file the system opens (links before "..")
        if not (real and os.path.isfile(real)):
            return False
        layout = image_layout(real)
        if layout is None:
            return is_eight_bit(texture.file)
        channels, _, gamma = layout
        if gamma is not None and abs(gamma - 0.45455) < 0.1:
            return True
        if gamma is not None and abs(gamma - 1.0) < 0.1:
            return False
        return channels in (3, 4)
    return is_eight_bit(texture.file)


def colour_policies(asset, context):
    """The project's colour-space policies (OPBR505, OPBR506), stated in MaterialX names: USD names
    and UsdUVTexture tokens are compared through their MaterialX equivalents. A stage without a
    colour space is in USD's default, lin_rec709_scene."""
    required_rule = getattr(colorspace_rules, "REQUIRED_COLORSPACE", None)
    allowed_rule = getattr(colorspace_rules, "TEXTURE_COLORSPACE_NOT_ALLOWED", None)
    required = getattr(context, "required_colorspace", None)
    if required and required_rule is not None:
        stated = _as_materialx(asset.colorspace or "lin_rec709_scene")
        if stated != required:
            meant = colorspaces.usd_equivalent(required)
            yield context.diagnostic(
                required_rule, f"stage colour space is {asset.colorspace or 'lin_rec709_scene (USD default)'!r}; "
                               f"the project requires {required!r}",
                asset.colorspace_location or Location(asset.path), hint=(
                    f'apply Usd.ColorSpaceAPI to the default prim with colorSpace:name = "{meant}"' if meant else None),
            )
    allowed = getattr(context, "allowed_texture_colorspaces", None)
    if allowed is None or allowed_rule is None:
        return
    seen = set()
    for material in asset.materials:
        for name, texture in material.textures():
            space = _as_materialx(texture.colorspace)
            if space and space not in allowed and texture.node not in seen:
                seen.add(texture.node)
                yield context.diagnostic(
                    allowed_rule, f"{name} reads {texture.file!r} as {texture.colorspace!r}, not one of {sorted(allowed)}",
                    texture.location or material.inputs[name].location,
                )


def _as_materialx(name: str | None) -> str | None:
    """A colour-space name of any scheme as MaterialX names it (``None`` for UsdUVTexture's auto)."""
    if name in (None, "auto"):
        return None
    if name in colorspaces.materialx_names():
        return name
    if name == "sRGB":
        return "srgb_texture"
    if colorspaces.is_data(name, "usd"):
        return "none"
    return colorspaces.materialx_equivalent(name) or name
