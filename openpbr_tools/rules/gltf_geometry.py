"""glTF geometry that changes how a material renders while every validator passes it: a primitive's vertex colour,
the layout and magnitude of its texture coordinates, the texture transforms of one texture set, and animations of
material properties.

* COLOR_0 multiplies the base colour (glTF 2.0, 3.7.2.1: "if a primitive specifies a vertex color using the attribute
  semantic property COLOR_0, then this value acts as an additional linear multiplier to base color"): black on every
  vertex, the material renders black (OPBR1241);
* a KHR_animation_pointer channel "MUST point to a property defined in the asset" (the extension's "Operation"), or
  it animates nothing (OPBR1242; what is defined: :mod:`openpbr_tools.io.gltf.animation_pointers`);
* KHR_texture_transform is defined on a textureInfo, and transforms that texture reference only: a tiling on baseColorTexture alone slides
  the colour off the normal, metallic-roughness and occlusion maps painted on the same UV set (OPBR1243);
* glTF has no UDIM: UV islands laid out in tiles 1001, 1002 ... all sample the one image (OPBR1244);
* float32 coordinates far from 0 are quantised: past the point where that step reaches a texel the texture is
  blocky and swims (OPBR1245).

The vertex data is read by :mod:`openpbr_tools.io.gltf.geometry` (bounded; sparse accessors are not read).
"""

from __future__ import annotations

import base64
import json
import math
import re
import struct

from ..diagnostics import Severity
from ..model import Location
from . import Rule
from .gltf import _PNG_4X4

_QUAD_INDICES = (0, 1, 2, 0, 2, 3)


def _document(vertices: dict, material: dict, indices=_QUAD_INDICES, **members) -> str:
    """A glTF drawing one primitive with ``material``; ``vertices`` maps an attribute to (accessor type, flat floats),
    all in one data-URI buffer; ``members`` are added to the root (JSON values)."""
    data, views, accessors, attributes = b"", [], [], {}
    for name, (kind, values) in vertices.items():
        packed = struct.pack(f"<{len(values)}f", *values)
        width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[kind]
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(packed)})
        accessor = {"bufferView": len(views) - 1, "componentType": 5126, "count": len(values) // width, "type": kind}
        if name in ("POSITION", "input"):
            columns = [values[i::width] for i in range(width)]
            accessor.update({"min": [min(c) for c in columns], "max": [max(c) for c in columns]})
        attributes[name] = len(accessors)
        accessors.append(accessor)
        data += packed
    packed = struct.pack(f"<{len(indices)}H", *indices)
    views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(packed)})
    accessors.append({"bufferView": len(views) - 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"})
    data += packed + bytes(-len(packed) % 4)
    drawn = {k: v for k, v in attributes.items() if k.isupper()}
    root = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": drawn, "indices": len(accessors) - 1, "material": 0}]}],
            "materials": [material], "accessors": accessors, "bufferViews": views,
            "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64,"
                         + base64.b64encode(data).decode("ascii")}],
            "images": [{"uri": _PNG_4X4}], "textures": [{"source": 0}], **members}
    if "animations" in members:
        root["animations"][0]["samplers"] = [{"input": attributes["input"], "output": attributes["output"]}]
    return json.dumps(root, indent=1) + "\n"


_QUAD = (-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0)
_TEXTURED = {"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}


def _coloured(rgb: float) -> str:
    return _document({"POSITION": ("VEC3", _QUAD), "TEXCOORD_0": ("VEC2", (0, 1, 1, 1, 1, 0, 0, 0)),
                      "COLOR_0": ("VEC3", (rgb,) * 12)}, _TEXTURED)


BLACK_VERTEX_COLOUR = Rule(
    "OPBR1241", "gltf-vertex-colour-black", Severity.ERROR,
    "A primitive's COLOR_0 is black (0, 0, 0) on every vertex, so the material it draws renders black.",
    "glTF 2.0 (3.7.2.1): \"if a primitive specifies a vertex color using the attribute semantic property COLOR_0, then "
    "this value acts as an additional linear multiplier to base color\". A COLOR_0 of zeros on every vertex multiplies "
    "the base colour (factor and texture) by 0: the diffuse and metal colour vanish and only the specular highlight "
    "and emission remain (usually an empty vertex-colour layer a DCC exported by default, or one baked from an unlit "
    "scene). The Khronos glTF-Validator does not read "
    "vertex colours. Nothing is reported when the base colour is already black. Remove the attribute, or export the "
    "intended colours.",
    passing=_coloured(1.0), failing=_coloured(0.0),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)


def _animated(pointer: str) -> str:
    extension = {"KHR_animation_pointer": {"pointer": pointer}}
    return _document({"POSITION": ("VEC3", _QUAD), "input": ("SCALAR", (0.0, 1.0)), "output": ("SCALAR", (0.2, 0.8))},
                     {"name": "M", "pbrMetallicRoughness": {"roughnessFactor": 0.5}},
                     extensionsUsed=["KHR_animation_pointer"],
                     animations=[{"channels": [{"sampler": 0, "target": {"path": "pointer", "extensions": extension}}]}])


ANIMATION_POINTER_UNDEFINED = Rule(
    "OPBR1242", "gltf-animation-pointer-undefined", Severity.WARNING,
    "A KHR_animation_pointer channel animates a material property the asset does not define: a name the material "
    "object's schema does not have, an object that is not there, or an absent property without a default.",
    "KHR_animation_pointer (\"Operation\"): \"The JSON Pointer MUST point to a property defined in the asset. A "
    "property is considered defined if it is present in the asset explicitly or if it has a default value and its "
    "enclosing object is present\" (so /materials/0/pbrMetallicRoughness/metallicFactor is valid while "
    "pbrMetallicRoughness is there, even without metallicFactor), and \"Pointers to the asset properties that do not "
    "have a spec-defined default value ... are invalid if the property is not defined in the asset explicitly\". A "
    "pointer to .../pbrMetallicRoughness/roughness (for roughnessFactor), to a KHR_materials_clearcoat object the "
    "material lacks, or to an absent attenuationDistance animates nothing: the wet-to-dry or fade animation never "
    "plays. The Khronos glTF-Validator does not resolve these pointers. Only pointers into /materials are judged "
    "(not extras, whose meaning is the application's); properties of extensions the toolkit does not read are not.",
    passing=_animated("/materials/0/pbrMetallicRoughness/roughnessFactor"),
    failing=_animated("/materials/0/pbrMetallicRoughness/roughness"),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)


_FLAT_NORMAL_4X4 = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mNsaPjPAANMDEgANwc"
                    "AZFMCBygXkuMAAAAASUVORK5CYII=")  # (128, 128, 255): the unperturbed normal


def _texture_set(normal_transform: bool) -> str:
    tiled = {"KHR_texture_transform": {"scale": [4, 4]}}
    normal = {"index": 1, **({"extensions": tiled} if normal_transform else {})}
    return json.dumps({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_texture_transform"],
                       "images": [{"uri": _PNG_4X4}, {"uri": _FLAT_NORMAL_4X4}],
                       "textures": [{"source": 0}, {"source": 1}],
                       "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": tiled}},
                                      "normalTexture": normal}]}, indent=1) + "\n"


BASE_COLOUR_TRANSFORM_ONLY = Rule(
    "OPBR1243", "gltf-texture-transform-base-colour-only", Severity.WARNING,
    "KHR_texture_transform tiles or moves the baseColorTexture, while the material's normal, metallic-roughness and "
    "occlusion textures on the same UV set have no transform.",
    "KHR_texture_transform \"adds offset, rotation, and scale properties to textureInfo structures\" (\"The "
    "KHR_texture_transform extension may be defined on textureInfo structures\"): each texture reference carries its "
    "own transform, and one without it reads the UVs as they are. A transform on baseColorTexture alone moves the colour "
    "and leaves the other maps of the texture set where they were: scaled 4 x 4, the colour repeats sixteen times "
    "over one normal and roughness map, and bumps, gloss and ambient occlusion no longer line up with the planks or "
    "tiles they were painted for. Usually a tiling set in a DCC on the colour node only. Reported only when every "
    "other of those textures reading the same UV set has no transform (an atlas where each texture has its own "
    "transform is not judged) and the base colour's transform is not the identity. The Khronos glTF-Validator does "
    "not compare transforms.",
    passing=_texture_set(True), failing=_texture_set(False),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)


def _islands(right_u: float, width: float) -> str:
    """Two separate quads; the second's UV island starts at ``right_u``."""
    positions = _QUAD + tuple(c + (3 if i % 3 == 0 else 0) for i, c in enumerate(_QUAD))
    uvs = (0, 1, width, 1, width, 0, 0, 0) + (right_u, 1, right_u + width, 1, right_u + width, 0, right_u, 0)
    return _document({"POSITION": ("VEC3", positions), "TEXCOORD_0": ("VEC2", uvs)}, _TEXTURED,
                     indices=_QUAD_INDICES + tuple(i + 4 for i in _QUAD_INDICES))


UDIM_LAYOUT = Rule(
    "OPBR1244", "gltf-uv-udim-layout", Severity.WARNING,
    "A primitive's UV islands lie in separate UDIM tiles (1001, 1002 ...) while its material samples one texture per "
    "slot: glTF has no UDIM, so every tile shows the same image.",
    "glTF 2.0 samples one image per textureInfo (3.8.4); coordinates outside [0, 1] wrap (REPEAT, the default) or "
    "clamp, so a layout made for UDIM, where tile 1002's islands read the 1002 image, reads the one image in glTF "
    "(or its edge pixels under CLAMP_TO_EDGE): half the model shows the wrong part of the wrong texture. Reported when "
    "every triangle lies within one unit square of UV space, the triangles lie in two or more squares of UDIM's grid "
    "(u in 0..10, v downwards from 1 as glTF's V flips), and either two or more squares hold UV islands of their own "
    "(islands: triangles joined by edges whose ends share position and coordinates) or a texture on that UV set reads "
    "an image named for a UDIM tile (hull_basecolor.1001.png). A tiling layout, a floor mapped 0..4 continuously to "
    "repeat its texture, is one island across squares (or its triangles cross the squares' edges) and is not "
    "reported; nor are textures with a KHR_texture_transform on that set. The Khronos glTF-Validator does not read UV "
    "layouts. Repack the UDIM tiles into one atlas (or split the material per tile) before exporting to glTF.",
    passing=_islands(0.5, 0.5), failing=_islands(1.0, 1.0),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)


def _offset(shift: float) -> str:
    uvs = (shift, 1, shift + 1, 1, shift + 1, 0, shift, 0)
    return _document({"POSITION": ("VEC3", _QUAD), "TEXCOORD_0": ("VEC2", uvs)}, _TEXTURED)


UV_PRECISION = Rule(
    "OPBR1245", "gltf-uv-float-precision", Severity.WARNING,
    "A primitive's texture coordinates are so far from 0 that float32 cannot resolve a texel of the textures that "
    "read them (an accumulated tile offset, such as u = 262144).",
    "glTF texture coordinates are float32 (3.7.2.1, 3.11): at |u| = 2^k the step between two representable values is "
    "2^(k-23), so at u = 262144 (2^18) it is 1/32, two texels of a 64-pixel map and 64 of a 2048-pixel one. "
    "Interpolated across a triangle, such coordinates land on a coarse grid: the texture renders blocky and swims as "
    "the view moves, though REPEAT makes the integer offset itself harmless. Reported when the float32 step at the "
    "largest |u| or |v| (numpy.spacing), times the texture's width or height and its KHR_texture_transform scale, "
    "reaches one texel. The Khronos glTF-Validator does not judge magnitudes. Subtract the integer offset (a whole "
    "number of tiles, which REPEAT does not see) from the coordinates.",
    passing=_offset(0.0), failing=_offset(float(1 << 22)),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

RULES = (BLACK_VERTEX_COLOUR, ANIMATION_POINTER_UNDEFINED, BASE_COLOUR_TRANSFORM_ONLY, UDIM_LAYOUT, UV_PRECISION)

#: The textures that share the base colour's texture set (its UV layout): gltf_pbr parameter -> glTF textureInfo.
_TEXTURE_SET = {"normal": "normalTexture", "metallic": "metallicRoughnessTexture", "roughness": "metallicRoughnessTexture",
                "occlusion": "occlusionTexture"}
#: A UDIM tile number just before a file name's extension (``.1001.png``, ``_1002.exr``).
_UDIM_NAME = re.compile(r"(?:^|[._ -])(1[0-9]{3})\.[A-Za-z0-9]+$")
#: One texel or more between neighbouring float32 coordinates (OPBR1245).
PRECISION_TEXELS = 1.0


def check(asset, context):
    """Runs on glTF assets only (rules.FAMILY_FORMATS)."""
    facts = asset.extra.get("gltf", {})
    for problem in facts.get("animation_pointers", ()):
        yield _undefined_pointer(asset, problem, context)
    materials = {material.extra.get("gltf", {}).get("index"): material for material in asset.materials}
    for material in asset.materials:
        yield from _texture_set_transform(material, context)
    images = facts.get("images", ())
    image_of = {use["pointer"]: images[use["image"]] for use in facts.get("texture_uses", ())
                if isinstance(use.get("image"), int) and use["image"] < len(images)}
    reported: set = set()
    for primitive in facts.get("primitives", ()):
        index = primitive.get("material")
        material = materials.get(index) if isinstance(index, int) and not isinstance(index, bool) else None
        geometry = primitive.get("geometry")
        if material is None or not geometry:
            continue
        yield from _black_colour(asset, primitive, geometry, material, reported, context)
        for number, uv_set in sorted(geometry["uv_sets"].items()):
            textures = [t for t in _textures(material) if (t.texcoord or 0) == number]
            if textures:
                yield from _uv_layout(asset, primitive, number, uv_set, textures, material, reported, context)
                yield from _uv_precision(asset, primitive, number, uv_set, textures, image_of, reported, context)


def _textures(material):
    seen = set()
    for entry in material.inputs.values():
        texture = entry.texture
        if texture is not None and texture.node not in seen:
            seen.add(texture.node)
            yield texture


def _undefined_pointer(asset, problem, context):
    target, name, enclosing = problem["target"], problem["property"], problem["enclosing"]
    why = {"enclosing_absent": f"{enclosing} is not in the asset, so its {name!r} is not defined",
           "unknown": f"the object at {enclosing} has no property {name!r} in its schema",
           "no_default": f"{name!r} is absent from {enclosing} and has no default value"}[problem["reason"]]
    hint = {"enclosing_absent": f"add {enclosing} to the asset, or point the channel at a property the asset defines",
            "unknown": f"point the channel at a property of {enclosing} (a factor such as roughnessFactor)",
            "no_default": f"write {name} in {enclosing}, so the animation has a property to drive"}[problem["reason"]]
    return context.diagnostic(
        ANIMATION_POINTER_UNDEFINED, f"animation channel pointer {target!r} names no property defined in the asset: {why}; "
        "the channel animates nothing", Location(asset.path, None, problem["pointer"], "pointer"), hint=hint)


def _black_colour(asset, primitive, geometry, material, reported, context):
    black = geometry.get("black_colour")
    if not black or (black["accessor"], material.name) in reported:
        return
    base = material.inputs.get("base_color")
    if base is not None and base.texture is None and base.constant == (0.0, 0.0, 0.0):
        return  # already black: the vertex colour changes nothing
    reported.add((black["accessor"], material.name))
    yield context.diagnostic(
        BLACK_VERTEX_COLOUR, f"COLOR_0 (accessor {black['accessor']}) of primitive {primitive['pointer']} is (0, 0, 0) on "
        f"all {black['count']} vertices: it multiplies the base colour of {material.name!r}, which renders black",
        Location(asset.path, None, f"{primitive['pointer']}/attributes", "COLOR_0"),
        hint="remove the COLOR_0 attribute (an empty vertex-colour layer), or export the intended vertex colours")


def _transformed(texture) -> bool:
    return texture.uv is not None and not texture.uv.is_identity


def _gltf_scale(uv) -> tuple[float, float]:
    """KHR_texture_transform's scale from the place2d one (its reciprocal, :mod:`openpbr_tools.io.gltf.uv`); a place2d
    scale of 0 (a glTF scale beyond float range) is an infinite glTF scale."""
    if uv is None:
        return 1.0, 1.0
    return tuple(1.0 / s if s else float("inf") for s in uv.scale)


def _texture_set_transform(material, context):
    base = material.inputs.get("base_color")
    if base is None or base.texture is None or not _transformed(base.texture):
        return
    texcoord = base.texture.texcoord or 0
    others = {name: material.inputs[p].texture for p, name in _TEXTURE_SET.items()
              if material.inputs.get(p) is not None and material.inputs[p].texture is not None
              and (material.inputs[p].texture.texcoord or 0) == texcoord}
    if not others or any(_transformed(texture) for texture in others.values()):
        return
    names = sorted(others)
    scale = _gltf_scale(base.texture.uv)
    yield context.diagnostic(
        BASE_COLOUR_TRANSFORM_ONLY, f"{material.name}: baseColorTexture has a KHR_texture_transform (scale "
        f"{scale[0]:g} x {scale[1]:g}) but {', '.join(names)} on the same UV set {texcoord} ha{'s' if len(names) == 1 else 've'} "
        "none: the colour slides off the other maps of its texture set",
        Location(material.location.file, None, f"{base.texture.node}/extensions/KHR_texture_transform", None),
        hint=f"give {', '.join(names)} the same KHR_texture_transform as baseColorTexture (or remove it from the base colour)")


def _udim_named(texture) -> str | None:
    """The UDIM tile number an image's file name ends in (``hull_basecolor.1001.png``), or ``None``."""
    found = _UDIM_NAME.search(texture.file.replace("\\", "/").rsplit("/", 1)[-1])
    return found.group(1) if found and int(found.group(1)) >= 1001 else None


def _uv_layout(asset, primitive, number, uv_set, textures, material, reported, context):
    layout = uv_set.get("udim_tiles")
    if not layout or any(_transformed(t) for t in textures) or ("udim", uv_set["accessor"]) in reported:
        return
    named = next((t for t in textures if _udim_named(t)), None)
    if len(layout["tiles_with_own_islands"]) < 2 and named is None:
        return  # tiles without islands of their own and no UDIM image: a mapping that runs across tiles (tiling)
    reported.add(("udim", uv_set["accessor"]))
    tiles = layout["tiles"]
    evidence = (f" (and {named.node.rsplit('/', 1)[-1]} reads the UDIM tile image {named.file!r})" if named is not None
                else f" (tiles {', '.join(map(str, layout['tiles_with_own_islands']))} hold UV islands of their own)")
    yield context.diagnostic(
        UDIM_LAYOUT, f"TEXCOORD_{number} of primitive {primitive['pointer']} keeps every triangle inside one UDIM tile, "
        f"in tiles {', '.join(map(str, tiles))}{evidence}, but glTF has no UDIM: {material.name!r} samples one image per "
        f"texture, so the triangles in tiles other than {_udim_named(named) if named is not None else tiles[0]} show that "
        "tile's image, not their own",
        Location(asset.path, None, f"{primitive['pointer']}/attributes", f"TEXCOORD_{number}"),
        hint="repack the UDIM tiles into one 0..1 atlas (and its textures into one image) before exporting to glTF")


def _uv_precision(asset, primitive, number, uv_set, textures, image_of, reported, context):
    import numpy  # lazy: only for a primitive whose UV sets were read

    if ("precision", uv_set["accessor"]) in reported:
        return
    worst = None
    for texture in textures:
        image = image_of.get(texture.node) or {}
        size = (image.get("width"), image.get("height"))
        if not all(isinstance(s, int) and s > 0 for s in size):
            continue
        scale = tuple(abs(s) for s in _gltf_scale(texture.uv))
        if not all(math.isfinite(s) for s in scale):
            continue  # (a scale beyond float range is an invalid property, OPBR1210's)
        if texture.uv is not None and texture.uv.rotate:
            scale = (max(scale),) * 2  # (rotated, either axis of the image may run along u)
            size = (max(size),) * 2
        for axis in (0, 1):
            step = float(numpy.spacing(numpy.float32(uv_set["largest"][axis])))
            texels = step * scale[axis] * size[axis]
            if worst is None or texels > worst[0]:
                worst = (texels, axis, step, texture, size[axis])
    if worst is None or worst[0] < PRECISION_TEXELS:
        return
    reported.add(("precision", uv_set["accessor"]))
    texels, axis, step, texture, pixels = worst
    yield context.diagnostic(
        UV_PRECISION, f"TEXCOORD_{number} of primitive {primitive['pointer']} reaches |{'uv'[axis]}| = "
        f"{uv_set['largest'][axis]:g}, where float32 steps by {step:g}: {texels:g} texels of the {pixels}-pixel "
        f"{texture.node.rsplit('/', 1)[-1]}, which renders blocky and swims",
        Location(asset.path, None, f"{primitive['pointer']}/attributes", f"TEXCOORD_{number}"),
        hint="subtract the whole-tile offset from the texture coordinates (REPEAT does not see it) and re-export")
