"""Colour spaces: are colour-space names known, and do colour and data inputs get the right kind.

MaterialX accepts any colour-space name (it warns and skips the conversion); USD stores any name and
treats it as identity. So a misspelt ``srgb_tx`` silently renders a texture unconverted. Colour
inputs (base, specular, coat, fuzz, emission, transmission, subsurface colours) want a colour
space; data inputs (weights, roughness, metalness, IOR, normals, tangents) must be read raw
(``none`` in MaterialX, ``raw`` in USD), or their numbers are bent by a transfer curve.

The OpenPBR specification says colours default to ACEScg when unspecified, while MaterialX's
examples and its default working space are lin_rec709: a document without a colour space is
therefore ambiguous (OPBR501).
"""

from __future__ import annotations

from .. import colorspaces
from ..diagnostics import Severity
from ..io import package_member
from ..model import Location, Texture
from . import Rule, for_each_input

NO_DOCUMENT_COLORSPACE = Rule(
    "OPBR501", "no-document-colorspace", Severity.INFO,
    "OpenPBR colour values are authored but the document states no colour space.",
    "The OpenPBR specification says unspecified colours are ACEScg; MaterialX (the renderer the "
    "document is written for) and most published libraries (MaterialX's examples, PhysicallyBased's "
    "OpenPBR exports) take them as lin_rec709, which is how the file renders there. Another reader "
    "following the specification's words shades the same numbers as ACEScg, more saturated. Set "
    "colorspace on the <materialx> element to say which was meant. Information, not a defect: MaterialX "
    "renders such a file as its authors saw it.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.8, 0.2, 0.1" />\n</open_pbr_surface>',
    failing='<?xml version="1.0"?>\n<materialx version="1.39">\n  <open_pbr_surface name="S" type="surfaceshader">\n    <input name="base_color" type="color3" value="0.8, 0.2, 0.1" />\n  </open_pbr_surface>\n</materialx>\n',
)
UNKNOWN_COLORSPACE = Rule(
    "OPBR502", "unknown-colorspace", Severity.ERROR,
    "A colour-space name the format does not define (wrong case, a vendor/OCIO name, a typo).",
    "MaterialX knows lin_rec709, srgb_texture, acescg, g22_rec709, g18_rec709, g22_ap1, lin_adobergb, "
    "adobergb, lin_displayp3, srgb_displayp3, rec709_display and none. Names such as srgb_tx, sRGB or "
    "'ACES - ACEScg' are silently treated as no conversion. The hint gives the name most likely meant.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.5, 0.5, 0.5" colorspace="srgb_texture" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.5, 0.5, 0.5" colorspace="srgb_tx" />\n</open_pbr_surface>',
)
COLOR_TEXTURE_RAW = Rule(
    "OPBR503", "color-texture-raw", Severity.WARNING,
    "A colour input reads a texture marked as raw data (colorspace none).",
    "An sRGB-encoded albedo read raw renders too bright and desaturated. Mark it srgb_texture (or the "
    "space it was painted in). Not reported for an OpenEXR, Radiance or PFM image, whose values are "
    "scene-linear: read raw, they need no transform.",
    passing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    failing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" colorspace="none" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    example_files=("albedo.png",),
)
DATA_TEXTURE_MANAGED = Rule(
    "OPBR504", "data-texture-colorspace", Severity.ERROR,
    "A data input (roughness, metalness, weights, IOR, normals) reads a colour-managed texture.",
    "A colour-space conversion bends the numbers: an sRGB decode turns a roughness of 0.5 into 0.21. "
    "This often happens by inheritance, when a colour-typed image under a document colour space feeds "
    "a float input through an extract node. Mark the image colorspace=\"none\". A colour-typed data input "
    "(Standard Surface's subsurface_radius, OpenPBR's subsurface_radius_scale) is not reported: MaterialX "
    "colour-manages every color3 input, so an sRGB texture there is decoded as its author intended "
    "(MaterialX's own chess-set example drives subsurface_radius from the base-colour texture). The "
    "alpha of a color4 image is never transformed.",
    passing='<image name="rough" type="color3">\n  <input name="file" type="filename" value="orm.png" colorspace="none" />\n</image>\n<extract name="g" type="float">\n  <input name="in" type="color3" nodename="rough" />\n  <input name="index" type="integer" value="1" />\n</extract>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_roughness" type="float" nodename="g" />\n</open_pbr_surface>',
    failing='<image name="rough" type="color3">\n  <input name="file" type="filename" value="orm.png" colorspace="srgb_texture" />\n</image>\n<extract name="g" type="float">\n  <input name="in" type="color3" nodename="rough" />\n  <input name="index" type="integer" value="1" />\n</extract>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_roughness" type="float" nodename="g" />\n</open_pbr_surface>',
    example_files=("orm.png",),
)

REQUIRED_COLORSPACE = Rule(
    "OPBR505", "required-colorspace", Severity.ERROR,
    "The document's colour space is not the one the project requires (configuration).",
    "Set `required-colorspace = \"acescg\"` in [tool.openpbr] to make every document state the "
    "project's working space; silent without that setting.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<?xml version="1.0"?>\n<materialx version="1.39" colorspace="acescg">\n  <open_pbr_surface name="S" type="surfaceshader" />\n</materialx>\n',
    example_config='required-colorspace = "lin_rec709"\n',
)
TEXTURE_COLORSPACE_NOT_ALLOWED = Rule(
    "OPBR506", "texture-colorspace-not-allowed", Severity.ERROR,
    "A texture uses a colour space the project does not allow (configuration).",
    "Set `allowed-texture-colorspaces = [\"srgb_texture\", \"acescg\", \"none\"]` in [tool.openpbr] "
    "to keep, say, display-referred or Adobe RGB textures out of a pipeline; silent without it.",
    passing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    failing='<image name="albedo" type="color3">\n  <input name="file" type="filename" value="albedo.png" colorspace="adobergb" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="albedo" />\n</open_pbr_surface>',
    example_files=("albedo.png",),
    example_config='allowed-texture-colorspaces = ["srgb_texture", "none"]\n',
)

COLORSPACE_IGNORED = Rule(
    "OPBR507", "colorspace-on-non-colour-image", Severity.WARNING,
    "A float or vector image (roughness, metalness, a normal map) carries a colour space other than none.",
    "MaterialX applies colour transforms only to color3/color4 images (ShaderGraph::populateColorTransformMap), "
    "so colorspace=\"srgb_texture\" on a float or vector3 image is ignored there; UsdMtlx drops it when "
    "writing USD; other renderers honour it and bend the numbers. The same file then renders differently "
    "per renderer: mark the image colorspace=\"none\" (or leave it unset). Reported wherever the image sits, "
    "in a node graph as well as beside the shader, and for MaterialX image shaders in USD.",
    passing='<image name="rough" type="float">\n  <input name="file" type="filename" value="rough.png" colorspace="none" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_roughness" type="float" nodename="rough" />\n</open_pbr_surface>',
    failing='<image name="rough" type="float">\n  <input name="file" type="filename" value="rough.png" colorspace="srgb_texture" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_roughness" type="float" nodename="rough" />\n</open_pbr_surface>',
    example_files=("rough.png",),
)

_INTERFACE_GRAPH = ('<nodegraph name="NG">\n  <input name="albedo_file" type="filename" value="albedo.png"{outer} />\n'
                    '  <image name="albedo" type="color3">\n    <input name="file" type="filename" interfacename="albedo_file"'
                    '{inner} />\n  </image>\n  <output name="out" type="color3" nodename="albedo" />\n</nodegraph>\n'
                    '<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" '
                    'nodegraph="NG" output="out" />\n</open_pbr_surface>')
INTERFACE_COLORSPACE = Rule(
    "OPBR508", "colorspace-on-interface-only", Severity.WARNING,
    "A colour image's file comes through a node graph's (or custom node's) interface input whose colour space "
    "is not the one the image's own file input resolves to.",
    "MaterialX's specification lets the input that defines a file name carry its colour space, and this "
    "toolkit reads the texture so; MaterialX's shader generation, however, takes the colour space of the "
    "image's own file input (its colorspace, else the enclosing scope's), so an srgb_texture tag only on "
    "the interface input is not applied there: MaterialX renders the texture without the sRGB decode "
    "(shown by its GLSL generator, tests/test_red_team_round_two.py). Put the colour space on the image's "
    "file input too, so every reader agrees.",
    passing=_INTERFACE_GRAPH.format(outer=' colorspace="srgb_texture"', inner=' colorspace="srgb_texture"'),
    failing=_INTERFACE_GRAPH.format(outer=' colorspace="srgb_texture"', inner=""),
    example_files=("albedo.png",),
)

RULES = (NO_DOCUMENT_COLORSPACE, UNKNOWN_COLORSPACE, COLOR_TEXTURE_RAW, DATA_TEXTURE_MANAGED,
         REQUIRED_COLORSPACE, TEXTURE_COLORSPACE_NOT_ALLOWED, COLORSPACE_IGNORED, INTERFACE_COLORSPACE)

COLOUR_MANAGED_IMAGE_TYPES = ("color3", "color4")


def check(asset, context):
    if asset.format != "mtlx":
        return  # USD and glTF name colour spaces differently; their rule modules reuse these codes
    yield from _unknown_names(asset, context)
    yield from _policies(asset, context)
    for observation in asset.observations:
        if observation.kind == "interface_colorspace":
            detail = observation.detail
            yield context.diagnostic(
                INTERFACE_COLORSPACE, f"the file comes through {detail['interface']!r}, tagged {detail['colorspace']!r}, "
                f"but MaterialX's shader generation applies the image's own file input's colour space "
                f"({detail['applied']!r})", observation.location,
                hint=f"add colorspace=\"{detail['colorspace']}\" to the image's file input")
    ambiguous = None
    reported = set()  # image nodes already named through a shader input (the message says which input)
    for material, table, entry in for_each_input(asset):
        parameter = table.get(entry.name)
        if parameter is None:
            continue
        texture = entry.texture
        if texture is not None and ignored_colorspace(texture) and _authored_on_texture(texture, asset):
            reported.add(texture.node)
            yield context.diagnostic(
                COLORSPACE_IGNORED, f"{entry.name} reads the {texture.image_type} image {texture.file!r} with colour "
                                    f"space {texture.colorspace!r}, which MaterialX ignores and other renderers apply",
                texture.location or entry.location, hint="set colorspace=\"none\" on the image's file input",
            )
        if parameter.role == "color":
            # only OpenPBR's specification names another default (ACEScg) than MaterialX's lin_rec709:
            # Standard Surface, glTF PBR and UsdPreviewSurface colours are lin_rec709 in MaterialX as elsewhere
            if ambiguous is None and asset.colorspace is None and material.model == "open_pbr_surface" and (
                (texture is None and entry.colorspace is None and entry.constant is not None)
                or (texture is not None and texture.colorspace is None)
            ):
                ambiguous = entry.location
            if texture is not None and colorspaces.is_data(texture.colorspace) and not scene_linear_file(texture.file):
                yield context.diagnostic(
                    COLOR_TEXTURE_RAW, f"{entry.name} reads {texture.file!r} as raw data (colorspace none)",
                    entry.location, hint="mark the image srgb_texture (or the space it was painted in)",
                )
        elif parameter.role in ("data", "normal", "tangent") and texture is not None and parameter.type != "color3":
            if _bends_data(texture, asset):
                inherited = "" if _authored_on_texture(texture, asset) else " (inherited)"
                yield context.diagnostic(
                    DATA_TEXTURE_MANAGED,
                    f"{entry.name} is data but reads {texture.file!r} through colour space {texture.colorspace!r}{inherited}",
                    entry.location, hint="set colorspace=\"none\" on the image's file input",
                )
    for observation in asset.observations:  # images no shader input reads (a displacement's height)
        detail = observation.detail
        if observation.kind == "mtlx_image_colorspace" and detail["node"] not in reported and not _no_transform(
                detail["colorspace"]):
            reported.add(detail["node"])
            yield context.diagnostic(
                COLORSPACE_IGNORED, f"the {detail['type']} image {detail['file']!r} is read with colour space "
                                    f"{detail['colorspace']!r}, which MaterialX ignores and other renderers apply",
                observation.location, hint="set colorspace=\"none\" on the image's file input")
    if ambiguous is not None:
        yield context.diagnostic(
            NO_DOCUMENT_COLORSPACE,
            "colours are authored but the document has no colorspace: OpenPBR says ACEScg, MaterialX assumes lin_rec709",
            Location(asset.path, 1, ""), hint="add colorspace=\"lin_rec709\" (or \"acescg\") to <materialx>",
        )


def _bends_data(texture: Texture, asset) -> bool:
    if texture.image_type not in COLOUR_MANAGED_IMAGE_TYPES or texture.reads_alpha:
        return False  # MaterialX transforms only color3/color4 images, never their alpha
    space = texture.colorspace
    if space is None or colorspaces.is_data(space):
        return False
    working = asset.colorspace or colorspaces.DEFAULT_MATERIALX
    return space != working or space not in ("lin_rec709", "acescg", "lin_adobergb", "lin_displayp3")


def ignored_colorspace(texture: Texture) -> bool:
    """Whether ``texture`` is a float or vector image whose colour space names a transform MaterialX
    would not apply (anything but none/raw)."""
    space = texture.colorspace
    if texture.image_type in COLOUR_MANAGED_IMAGE_TYPES or space is None or texture.reads_alpha:
        return False  # a colour image, or the alpha of one (gltf_colorimage's outa): the space is its RGB's
    return not _no_transform(space)


def _no_transform(space: str) -> bool:
    """Whether a colour-space name asks for no transform (none, raw, auto; MaterialX's or USD's spelling, or an
    OCIO config's Raw role in any case: MaterialX's own TestSuite writes colorspace="Raw" on a normal map)."""
    return colorspaces.is_data(space) or colorspaces.is_data(space, "usd") or \
        space.strip().lower() in ("raw", "auto", "utility - raw")


#: Image formats whose values are scene-linear by convention (OpenEXR: "pixel values are linear"; Radiance RGBE; PFM):
#: read without a transform ("raw", "none"), a colour in them is already in the working space's linear encoding.
SCENE_LINEAR_SUFFIXES = (".exr", ".hdr", ".pfm")


def scene_linear_file(file: str) -> bool:
    """Whether a texture file is a scene-linear floating-point image (by its suffix; inside a package, the member's)."""
    return package_member(file).lower().endswith(SCENE_LINEAR_SUFFIXES)


def _authored_on_texture(texture: Texture, asset) -> bool:
    """Whether the image's colour space is written on the image (not inherited from a graph or the document)."""
    if texture.colorspace_on_image is not None:
        return texture.colorspace_on_image
    return texture.colorspace != asset.colorspace


def _unknown_names(asset, context):
    known = colorspaces.materialx_names()
    seen = set()
    candidates = []
    if asset.colorspace is not None:
        candidates.append((asset.colorspace, asset.colorspace_location or Location(asset.path, 1)))
    for material in asset.materials:
        for entry in material.inputs.values():
            if entry.authored_colorspace:
                candidates.append((entry.authored_colorspace, entry.location))
            texture = entry.texture
            if texture is not None and texture.colorspace and texture.colorspace != asset.colorspace:
                candidates.append((texture.colorspace, texture.location or entry.location))
    for observation in asset.observations:  # a node graph's, a pattern node's input's (the reader's)
        name = observation.detail.get("name") if observation.kind == "node_colorspace" else None
        # a name MaterialX remaps (gamma18), or one it leaves unconverted that means its working space anyway
        # (lin_rec709_scene: MaterialX's colour-management test suite uses it), renders as meant
        if name and colorspaces.materialx_remapped(name) not in known and colorspaces.materialx_name(name) != "lin_rec709":
            candidates.append((name, observation.location))
    for name, location in candidates:
        if name in known or (name, location) in seen:
            continue
        seen.add((name, location))
        guess = colorspaces.suggest(name)
        yield context.diagnostic(
            UNKNOWN_COLORSPACE, f"unknown colour space {name!r}: MaterialX will not convert it",
            location, hint=f"did you mean {guess!r}?" if guess else f"known: {', '.join(sorted(known))}",
        )


def _policies(asset, context):
    required = context.required_colorspace
    if required and asset.colorspace != required:
        stated = repr(asset.colorspace) if asset.colorspace else "none"
        yield context.diagnostic(
            REQUIRED_COLORSPACE, f"document colour space is {stated}; the project requires {required!r}",
            asset.colorspace_location or Location(asset.path, 1), hint=f"set colorspace=\"{required}\" on <materialx>",
        )
    allowed = context.allowed_texture_colorspaces
    if allowed is None:
        return
    seen = set()
    for material in asset.materials:
        for name, texture in material.textures():
            key = (texture.node, texture.colorspace)
            if texture.colorspace and texture.colorspace not in allowed and key not in seen:
                seen.add(key)
                yield context.diagnostic(
                    TEXTURE_COLORSPACE_NOT_ALLOWED,
                    f"{name} reads {texture.file!r} as {texture.colorspace!r}, not one of {sorted(allowed)}",
                    texture.location or material.inputs[name].location,
                )
