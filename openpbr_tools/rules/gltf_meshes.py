"""glTF meshes: what a mesh primitive must provide for the material it uses to render as authored.

A material's textures are sampled at the primitive's texture coordinates and its normal-space effects
(a clear-coat normal map, anisotropy) are oriented by the primitive's tangent space, so two mesh
facts decide whether the material can look right at all:

* the texture-coordinate accessors' formats (glTF 2.0, 3.7.2.1 Meshes: ``TEXCOORD_n`` is ``VEC2`` of
  floats, or of unsigned bytes or shorts with ``normalized: true``; ``KHR_mesh_quantization`` adds
  signed and unnormalised integers), checked on every primitive as the Khronos glTF-Validator does
  (MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT);
* a tangent space where KHR_materials_clearcoat (with ``clearcoatNormalTexture``) or
  KHR_materials_anisotropy requires one: "a mesh primitive using [such] a material MUST have a
  defined tangent space, i.e., it MUST have NORMAL and TANGENT attributes or its base material MUST
  have a normal texture" (each extension's README; the validator's MESH_PRIMITIVE_NO_TANGENT_SPACE).

A missing UV set is OPBR1205 (the glTF family). Only the JSON is read: no accessor data.
"""

from __future__ import annotations

from ..diagnostics import Severity
from ..io.gltf import slots
from ..model import Location
from . import Rule
from .gltf import _PNG_4X4, _gltf

_FLOAT, _BYTE, _UNSIGNED_BYTE, _SHORT, _UNSIGNED_SHORT = 5126, 5120, 5121, 5122, 5123
_COMPONENT_NAMES = {5120: "BYTE", 5121: "UNSIGNED_BYTE", 5122: "SHORT", 5123: "UNSIGNED_SHORT", 5125: "UNSIGNED_INT",
                    5126: "FLOAT"}
QUANTIZATION = "KHR_mesh_quantization"


def _uv_mesh(component_type: int, normalized: bool) -> str:
    flag = ', "normalized": true' if normalized else ""
    return _gltf(
        f'"images": [{{"uri": "{_PNG_4X4}"}}]', '"textures": [{"source": 0}]',
        '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]',
        '"accessors": [{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]}, '
        f'{{"componentType": {component_type}, "count": 3, "type": "VEC2"{flag}}}]',
        '"meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}]',
    )


def _coated_mesh(tangents: bool) -> str:
    tangent = ', "TANGENT": 2' if tangents else ""
    return _gltf(
        '"extensionsUsed": ["KHR_materials_clearcoat"]',
        f'"images": [{{"uri": "{_PNG_4X4}"}}]', '"textures": [{"source": 0}]',
        '"materials": [{"name": "M", "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, '
        '"clearcoatNormalTexture": {"index": 0}}}}]',
        '"accessors": [{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]}, '
        '{"componentType": 5126, "count": 3, "type": "VEC2"}, {"componentType": 5126, "count": 3, "type": "VEC4"}, '
        '{"componentType": 5126, "count": 3, "type": "VEC3"}]',
        f'"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 3, "TEXCOORD_0": 1{tangent}}}, '
        '"material": 0}]}]',
    )


TEXCOORD_FORMAT = Rule(
    "OPBR1217", "gltf-texcoord-accessor-format", Severity.ERROR,
    "A TEXCOORD_n accessor has a format glTF does not allow for texture coordinates.",
    "glTF 2.0 allows VEC2 of FLOAT, or of UNSIGNED_BYTE or UNSIGNED_SHORT with normalized: true "
    "(KHR_mesh_quantization adds BYTE and SHORT, and unnormalised integers). Unsigned bytes without "
    "normalized are read as the integers 0 to 255, so every texture is sampled far outside [0, 1] (or "
    "the viewer rejects the mesh): the Khronos glTF-Validator's MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT.",
    passing=_uv_mesh(_UNSIGNED_BYTE, True), failing=_uv_mesh(_UNSIGNED_BYTE, False),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
NO_TANGENT_SPACE = Rule(
    "OPBR1218", "gltf-no-tangent-space", Severity.ERROR,
    "A primitive uses a clear-coat normal map or an anisotropic material but has no tangent space: no "
    "NORMAL and TANGENT attributes, and no normalTexture to generate tangents from.",
    "KHR_materials_clearcoat (with clearcoatNormalTexture) and KHR_materials_anisotropy require it (MUST): "
    "the coat's normal map and the anisotropy direction are expressed in tangent space, which is then "
    "undefined, so viewers orient them differently or not at all. The Khronos glTF-Validator's "
    "MESH_PRIMITIVE_NO_TANGENT_SPACE (an error) covers the textured cases; the extension texts also the "
    "untextured anisotropy. Export tangents (MikkTSpace), or give the material a normalTexture.",
    passing=_coated_mesh(True), failing=_coated_mesh(False),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

RULES = (TEXCOORD_FORMAT, NO_TANGENT_SPACE)


def check(asset, context):
    """Runs on glTF assets only (rules.FAMILY_FORMATS)."""
    facts = asset.extra.get("gltf", {})
    primitives = facts.get("primitives", ())
    if not primitives:
        return
    yield from _texcoord_formats(asset, facts, primitives, context)
    yield from _tangent_space(asset, primitives, context)


def _allowed(accessor_type, component_type, normalized: bool, quantized: bool) -> bool:
    if accessor_type != "VEC2":
        return False
    if component_type == _FLOAT:
        return True
    if component_type in (_UNSIGNED_BYTE, _UNSIGNED_SHORT):
        return normalized or quantized
    return quantized and component_type in (_BYTE, _SHORT)


def _texcoord_formats(asset, facts, primitives, context):
    quantized = QUANTIZATION in facts.get("extensions_used", ())
    for primitive in primitives:
        for index, (accessor_type, component_type, normalized) in sorted(primitive.get("texcoord_formats", {}).items()):
            if _allowed(accessor_type, component_type, normalized, quantized):
                continue
            name = _COMPONENT_NAMES.get(component_type, repr(component_type))
            shown = f"{accessor_type} of {name}{' (normalized)' if normalized else ''}"
            integer = component_type in (_UNSIGNED_BYTE, _UNSIGNED_SHORT) and not normalized
            yield context.diagnostic(
                TEXCOORD_FORMAT, f"TEXCOORD_{index} is {shown}, which glTF does not allow for texture coordinates"
                + (": read as whole numbers, every texture is sampled outside [0, 1]" if integer else ""),
                Location(asset.path, None, f"{primitive['pointer']}/attributes", f"TEXCOORD_{index}"),
                hint='add "normalized": true to the accessor' if integer and accessor_type == "VEC2"
                else "store texture coordinates as VEC2 of FLOAT (or normalised unsigned bytes or shorts)",
            )


def _needs_tangents(material) -> str | None:
    """What makes ``material`` require a tangent space, or ``None``; a normalTexture provides one."""
    inputs = material.inputs
    if inputs.get("normal") is not None and inputs["normal"].texture is not None:
        return None
    if inputs.get("clearcoat_normal") is not None and inputs["clearcoat_normal"].texture is not None:
        return "its clearcoatNormalTexture"
    strength = inputs.get("anisotropy_strength")
    if strength is not None and (strength.texture is not None or
                                 (isinstance(strength.constant, float) and strength.constant > 0)):
        return f"its {slots.ANISOTROPY}"  # (strength 0, the default, is no anisotropy: nothing to orient)
    return None


def _tangent_space(asset, primitives, context):
    needs = {}
    for material in asset.materials:
        index = material.extra.get("gltf", {}).get("index")
        reason = _needs_tangents(material)
        if isinstance(index, int) and reason:
            needs[index] = (material, reason)
    for primitive in primitives:
        material_index = primitive["material"]
        found = needs.get(material_index) if isinstance(material_index, int) and not isinstance(material_index, bool) else None
        if found is None or (primitive.get("tangents") and primitive.get("normals")):
            continue
        material, reason = found
        lacking = " and ".join(name for name, present in (("NORMAL", primitive.get("normals")),
                                                           ("TANGENT", primitive.get("tangents"))) if not present)
        yield context.diagnostic(
            NO_TANGENT_SPACE, f"primitive {primitive['pointer']} has no {lacking} attribute and material "
            f"{material.name!r} has no normalTexture, but {reason} needs a tangent space",
            Location(asset.path, None, primitive["pointer"], "attributes"),
            hint="export tangents (MikkTSpace) with the mesh, or give the material a normalTexture",
        )
