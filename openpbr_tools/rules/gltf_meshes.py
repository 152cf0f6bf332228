"""glTF meshes: what a mesh primitive must provide for the material it uses to render as authored.

A material's textures are sampled at the primitive's texture coordinates and its normal-space effects
(a clear-coat normal map, anisotropy) are oriented by the primitive's tangent space, so two mesh
facts decide whether the material can look right at all:

* the formats of the accessors the material reads through (glTF 2.0, 3.7.2.1 Meshes: ``NORMAL`` is ``VEC3``
  and ``TANGENT`` ``VEC4`` of floats; ``TEXCOORD_n`` ``VEC2`` and ``COLOR_n`` ``VEC3`` or ``VEC4`` of floats,
  or of unsigned bytes or shorts with ``normalized: true``; ``KHR_mesh_quantization`` adds normalised signed
  bytes and shorts to NORMAL and TANGENT and signed and unnormalised integers to TEXCOORD_n; accessor.schema.json:
  ``normalized`` "MUST NOT be set to true for accessors with FLOAT or UNSIGNED_INT component type"), checked on every primitive as the Khronos glTF-Validator
  does (MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT, ACCESSOR_NORMALIZED_INVALID): :data:`ATTRIBUTE_FORMATS`;
* a tangent space where KHR_materials_clearcoat (with ``clearcoatNormalTexture``) or
  KHR_materials_anisotropy requires one: "a mesh primitive using [such] a material MUST have a
  defined tangent space, i.e., it MUST have NORMAL and TANGENT attributes or its base material MUST
  have a normal texture" (each extension's README; the validator's MESH_PRIMITIVE_NO_TANGENT_SPACE); and on
  every primitive, NORMAL beside TANGENT: "When normals are not specified, client implementations MUST
  calculate flat normals and the provided tangents (if present) MUST be ignored" (3.7.2.1; the validator's
  MESH_PRIMITIVE_TANGENT_WITHOUT_NORMAL).

and, on the primitive too,

* its TANGENT ``w``, the handedness of the tangent basis: "a sign value (-1 or +1)" (3.7.2.1; the bitangent
  is ``cross(normal, tangent.xyz) * w``), read from the accessor data (the reader's
  ``tangent_signs``, bounded: :mod:`openpbr_tools.io.gltf.accessors`), as the Khronos validator does
  (ACCESSOR_INVALID_SIGN);
* its KHR_materials_variants mappings: "across the entire mappings array, each variant index must be used
  no more than one time" (the validator's KHR_MATERIALS_VARIANTS_NON_UNIQUE_VARIANT); a mapping's material
  or variant index that names nothing is OPBR802. Variants are presented to users and selected by name, so
  two variants of one name are reported too.

and, where the material has a normalTexture, whether the primitive provides the tangent space it is read in (NORMAL
and TANGENT; else the viewer generates one: OPBR1235, the validator's MESH_PRIMITIVE_GENERATED_TANGENT_SPACE), and
whether the anisotropy and clear-coat normal textures read the normal texture's UV set, whose tangent space theirs is
(OPBR1236).

One module because every rule here judges a primitive against the material it draws (the reader's primitive facts),
and their examples share its mesh builders; split, each half would import the other's.

A missing UV set, or UV sets not numbered 0, 1, 2 ..., is OPBR1205 (the glTF family); NaN values and normals not of unit length are OPBR1231 (the
gltf_structure family). Apart from the tangent signs only the JSON is read.
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
QUANTIZATION = slots.MESH_QUANTIZATION

_FLOATS = ((_FLOAT, False),)
_UNSIGNED_NORMALIZED = ((_UNSIGNED_BYTE, True), (_UNSIGNED_SHORT, True))
_SIGNED_NORMALIZED = ((_BYTE, True), (_SHORT, True))
_INTEGERS = tuple((c, n) for c in (_BYTE, _UNSIGNED_BYTE, _SHORT, _UNSIGNED_SHORT) for n in (False, True))
#: semantic -> (accessor types, (componentType, normalized) allowed, those KHR_mesh_quantization adds): glTF 2.0's
#: table in 3.7.2.1 and the extension's "Extending Mesh Attributes".
ATTRIBUTE_FORMATS = {
    "NORMAL": (("VEC3",), _FLOATS, _SIGNED_NORMALIZED),
    "TANGENT": (("VEC4",), _FLOATS, _SIGNED_NORMALIZED),
    "TEXCOORD_": (("VEC2",), _FLOATS + _UNSIGNED_NORMALIZED, _INTEGERS),
    "COLOR_": (("VEC3", "VEC4"), _FLOATS + _UNSIGNED_NORMALIZED, ()),
}


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


ATTRIBUTE_FORMAT = Rule(
    "OPBR1217", "gltf-attribute-accessor-format", Severity.ERROR,
    "A TEXCOORD_n, COLOR_n, NORMAL or TANGENT accessor has a format glTF does not allow for its attribute (a "
    "VEC3 TANGENT, unnormalised unsigned bytes, a FLOAT accessor marked normalized).",
    "glTF 2.0 (3.7.2.1) allows TEXCOORD_n as VEC2 of FLOAT, or of UNSIGNED_BYTE or UNSIGNED_SHORT with normalized: "
    "true (KHR_mesh_quantization adds BYTE and SHORT, and unnormalised integers); COLOR_n likewise as VEC3 or VEC4; "
    "NORMAL as VEC3 and TANGENT as VEC4 of FLOAT (the extension adds normalised BYTE and SHORT); and normalized "
    "\"MUST NOT be set to true for accessors with FLOAT or UNSIGNED_INT component type\" (accessor.schema.json). "
    "Unsigned bytes without normalized are read as the integers 0 to 255, so every texture is sampled far outside [0, 1] and vertex colours multiply the base colour by up to 255; a VEC3 "
    "TANGENT has no w, the handedness the bitangent needs, so the normal map is mirrored or the mesh refused; a "
    "FLOAT marked normalized is refused or read as it is, depending on the loader. The Khronos glTF-Validator: "
    "MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT (and ACCESSOR_NORMALIZED_INVALID), errors.",
    passing=_uv_mesh(_UNSIGNED_BYTE, True), failing=_uv_mesh(_UNSIGNED_BYTE, False),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
NO_TANGENT_SPACE = Rule(
    "OPBR1218", "gltf-no-tangent-space", Severity.ERROR,
    "A primitive uses a clear-coat normal map or an anisotropic material but has no tangent space: no "
    "NORMAL and TANGENT attributes, and no normalTexture to generate tangents from; or a primitive has TANGENT "
    "without NORMAL.",
    "KHR_materials_clearcoat (with clearcoatNormalTexture) and KHR_materials_anisotropy require it (MUST): "
    "the coat's normal map and the anisotropy direction are expressed in tangent space, which is then "
    "undefined, so viewers orient them differently or not at all. The Khronos glTF-Validator's "
    "MESH_PRIMITIVE_NO_TANGENT_SPACE (an error) covers the textured cases; the extension texts also the "
    "untextured anisotropy. Export tangents (MikkTSpace), or give the material a normalTexture. "
    "A primitive with TANGENT but no NORMAL loses the tangents it carries: \"When normals are not specified, client "
    "implementations MUST calculate flat normals and the provided tangents (if present) MUST be ignored\" (glTF "
    "2.0, 3.7.2.1), so the normal map is oriented by generated tangents, not the exported ones, and shades faceted "
    "(usually normals stripped by a decimation step; the validator's MESH_PRIMITIVE_TANGENT_WITHOUT_NORMAL, which "
    "it reports as a warning).",
    passing=_coated_mesh(True), failing=_coated_mesh(False),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

def _variants(first: list, second: list, names=("Red", "Blue")) -> str:
    return _gltf(
        '"extensionsUsed": ["KHR_materials_variants"]',
        '"extensions": {"KHR_materials_variants": {"variants": [' + ", ".join(f'{{"name": "{n}"}}' for n in names) + ']}}',
        '"materials": [{"name": "red"}, {"name": "blue"}]',
        '"accessors": [{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]}]',
        '"meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0, "extensions": {"KHR_materials_variants": '
        f'{{"mappings": [{{"material": 0, "variants": {first}}}, {{"material": 1, "variants": {second}}}]}}}}}}]}}]',
    )


# One triangle with normals (0, 0, 1) and tangents (1, 0, 0, w) in one little-endian float buffer.
_TANGENTS_PLUS = ("AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AACAPwAA"
                  "AAAAAAAAAACAPwAAgD8AAAAAAAAAAAAAgD8AAIA/AAAAAAAAAAAAAIA/")
_TANGENTS_ZERO = ("AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AAAAAAAAAAAAAIA/AACAPwAA"
                  "AAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAAAA")


def _tangent_mesh(data: str) -> str:
    return _gltf(
        f'"buffers": [{{"byteLength": 120, "uri": "data:application/octet-stream;base64,{data}"}}]',
        '"bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 72}, {"buffer": 0, "byteOffset": 72, "byteLength": 48}]',
        '"accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}, '
        '{"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"}, '
        '{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC4"}]',
        '"materials": [{"name": "M"}]',
        '"meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TANGENT": 2}, "material": 0}]}]',
    )


VARIANT_MAPPED_TWICE = Rule(
    "OPBR1225", "gltf-variant-mapped-twice", Severity.ERROR,
    "A primitive's KHR_materials_variants mappings name one variant in two mappings (with two materials).",
    "KHR_materials_variants: \"across the entire mappings array, each variant index must be used no more than one "
    "time\". Selecting the variant then has two materials to choose from for the primitive, and viewers pick "
    "either (the Khronos glTF-Validator's KHR_MATERIALS_VARIANTS_NON_UNIQUE_VARIANT, an error).",
    passing=_variants("[0]", "[1]"), failing=_variants("[0]", "[0, 1]"),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
VARIANT_NAME_TWICE = Rule(
    "OPBR1226", "gltf-variant-name-duplicate", Severity.WARNING,
    "Two KHR_materials_variants variants have the same name.",
    "KHR_materials_variants lists the variants an application presents to its users, each by its name (\"each "
    "with a name property\"); the schema does not require the names to differ, but a configurator or API that "
    "selects a variant by name reaches only one of two variants named alike. Usually a copied variant not "
    "renamed.",
    passing=_variants("[0]", "[1]"), failing=_variants("[0]", "[1]", names=("Red", "Red")),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
TANGENT_SIGN = Rule(
    "OPBR1227", "gltf-tangent-w-not-sign", Severity.ERROR,
    "A TANGENT accessor holds a w component that is not +1 or -1.",
    "glTF 2.0 (3.7.2.1): TANGENT is XYZW \"where ... the W component is a sign value (-1 or +1) indicating "
    "handedness of the tangent basis\", and the bitangent \"MUST be computed\" as cross(normal, tangent.xyz) * w; "
    "a w of 0 collapses the bitangent, so the normal map (and a clear-coat normal map or anisotropy) shades "
    "wrong. The Khronos glTF-Validator reports each run of such vertices (ACCESSOR_INVALID_SIGN, an error). "
    "The first million or so vertices of an accessor are read.",
    passing=_tangent_mesh(_TANGENTS_PLUS), failing=_tangent_mesh(_TANGENTS_ZERO),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)



def _normal_mapped(tangents: bool) -> str:
    tangent = ', "TANGENT": 2' if tangents else ""
    return _gltf(
        f'"images": [{{"uri": "{_PNG_4X4}"}}]', '"textures": [{"source": 0}]',
        '"materials": [{"name": "M", "normalTexture": {"index": 0}}]',
        '"accessors": [{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]}, '
        '{"componentType": 5126, "count": 3, "type": "VEC2"}, {"componentType": 5126, "count": 3, "type": "VEC4"}, '
        '{"componentType": 5126, "count": 3, "type": "VEC3"}]',
        f'"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 3, "TEXCOORD_0": 1{tangent}}}, '
        '"material": 0}]}]',
    )


GENERATED_TANGENTS = Rule(
    "OPBR1235", "gltf-tangent-space-generated", Severity.WARNING,
    "A primitive draws a normal-mapped material (normalTexture) without TANGENT (or NORMAL) attributes: the viewer "
    "generates the tangent space the normal map is read in.",
    "glTF 2.0 (3.7.2.1): \"When tangents are not specified, client implementations SHOULD calculate tangents using "
    "default MikkTSpace algorithms with the specified vertex positions, normals, and texture coordinates associated "
    "with the normal texture\" (and flat normals first when NORMAL is missing). Common and legal, most of Khronos' "
    "own sample models do it; but a normal map reads as baked only where the baker's tangents are the viewer's, so a "
    "map baked in another tangent space (or on another triangulation) shows seams and wrongly lit bumps, and viewers "
    "that do not implement MikkTSpace differ from those that do. The Khronos glTF-Validator warns "
    "(MESH_PRIMITIVE_GENERATED_TANGENT_SPACE: \"runtime-generated tangent space may be non-portable across "
    "implementations\"). Export the tangents the map was baked with (MikkTSpace) to pin it down.",
    passing=_normal_mapped(True), failing=_normal_mapped(False),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)


def _anisotropic(texcoord: int) -> str:
    return _gltf(
        '"extensionsUsed": ["KHR_materials_anisotropy"]',
        f'"images": [{{"uri": "{_PNG_4X4}"}}]', '"textures": [{"source": 0}]',
        '"materials": [{"name": "M", "normalTexture": {"index": 0}, "extensions": {"KHR_materials_anisotropy": '
        f'{{"anisotropyStrength": 0.5, "anisotropyTexture": {{"index": 0, "texCoord": {texcoord}}}}}}}}}]',
    )


TANGENT_UV_SET = Rule(
    "OPBR1236", "gltf-tangent-texture-uv-set", Severity.WARNING,
    "An anisotropyTexture or clearcoatNormalTexture reads another UV set (texCoord) than the material's "
    "normalTexture.",
    "A mesh has one tangent space, the one of the normal texture's UV set: glTF 2.0 (3.7.2.1) computes missing "
    "tangents from \"the texture coordinates associated with the normal texture\", and exported TANGENTs follow "
    "that UV layout too. The anisotropy direction (KHR_materials_anisotropy: red and green \"in tangent, bitangent "
    "space\") and a clear-coat normal map are read in that tangent space, so painted on another UV set they point "
    "wherever the two layouts differ in orientation: a rotated or mirrored highlight, a coat lit from the wrong side. "
    "The Khronos glTF-Validator warns (KHR_MATERIALS_ANISOTROPY_ANISOTROPY_TEXTURE_TEXCOORD, "
    "KHR_MATERIALS_CLEARCOAT_CLEARCOAT_NORMAL_TEXTURE_TEXCOORD). Without a normalTexture nothing is compared.",
    passing=_anisotropic(0), failing=_anisotropic(1),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

RULES = (ATTRIBUTE_FORMAT, NO_TANGENT_SPACE, VARIANT_MAPPED_TWICE, VARIANT_NAME_TWICE, TANGENT_SIGN, GENERATED_TANGENTS,
         TANGENT_UV_SET)


def check(asset, context):
    """Runs on glTF assets only (rules.FAMILY_FORMATS)."""
    facts = asset.extra.get("gltf", {})
    yield from _variant_names(asset, facts, context)
    for material in asset.materials:
        yield from _tangent_uv_sets(material, context)
    primitives = facts.get("primitives", ())
    if not primitives:
        return
    yield from _attribute_formats(asset, facts, primitives, context)
    yield from _tangent_space(asset, primitives, context)
    yield from _generated_tangents(asset, primitives, context)
    yield from _tangents_without_normals(asset, primitives, context)
    yield from _tangent_signs(asset, primitives, context)


def _variant_names(asset, facts, context):
    variants = facts.get("variants") or {}
    first: dict[str, str] = {}
    for pointer, name in variants.get("names", ()):
        if name in first:
            yield context.diagnostic(
                VARIANT_NAME_TWICE, f"variant {pointer.rsplit('/', 1)[-1]} is named {name!r}, as variant "
                f"{first[name].rsplit('/', 1)[-1]} is: selecting {name!r} by name reaches only one of them",
                Location(asset.path, None, pointer, "name"), hint="give each variant its own name")
        else:
            first[name] = pointer
    for primitive in variants.get("mappings", ()):
        seen: dict[int, str] = {}
        for where, variant in primitive["variants"]:
            if variant in seen and seen[variant] != where:
                yield context.diagnostic(
                    VARIANT_MAPPED_TWICE, f"variant {variant} is mapped by {seen[variant].rsplit('/', 1)[-1]} and by "
                    f"{where.rsplit('/', 1)[-1]} of {primitive['pointer']}: each variant may be used once per primitive",
                    Location(asset.path, None, where, "variants"), hint="keep the variant in one mapping")
            seen.setdefault(variant, where)


def _tangent_signs(asset, primitives, context):
    reported = set()  # an accessor shared by primitives is reported once
    for primitive in primitives:
        signs = primitive.get("tangent_signs")
        if not signs or not signs["invalid"] or signs["accessor"] in reported:
            continue
        reported.add(signs["accessor"])
        yield context.diagnostic(
            TANGENT_SIGN, f"TANGENT accessor {signs['accessor']} has {signs['invalid']} of {signs['checked']} w components "
            f"that are not +1 or -1 (first: {signs['value']:g}): the bitangent, and with it the normal map, is wrong there",
            Location(asset.path, None, f"{primitive['pointer']}/attributes", "TANGENT"),
            hint="re-export the tangents (MikkTSpace) with w = +1 or -1, the handedness")


def _allowed(semantic: str, accessor_type, component_type, normalized: bool, quantized: bool) -> bool:
    types, core, extended = ATTRIBUTE_FORMATS[semantic]
    return accessor_type in types and ((component_type, normalized) in core or
                                       (quantized and (component_type, normalized) in extended))


def _semantic(name: str) -> str | None:
    return name if name in ("NORMAL", "TANGENT") else next((s for s in ("TEXCOORD_", "COLOR_") if name.startswith(s)), None)


def _attribute_formats(asset, facts, primitives, context):
    quantized = QUANTIZATION in facts.get("extensions_used", ())
    for primitive in primitives:
        for name, (accessor_type, component_type, normalized) in sorted(primitive.get("attribute_formats", {}).items()):
            semantic = _semantic(name)
            if semantic is None or _allowed(semantic, accessor_type, component_type, normalized, quantized):
                continue
            yield context.diagnostic(
                ATTRIBUTE_FORMAT, _format_message(name, semantic, accessor_type, component_type, normalized),
                Location(asset.path, None, f"{primitive['pointer']}/attributes", name),
                hint=_format_hint(semantic, accessor_type, component_type, normalized))


def _format_message(name: str, semantic: str, accessor_type, component_type, normalized: bool) -> str:
    shown = f"{accessor_type} of {_COMPONENT_NAMES.get(component_type, repr(component_type))}"
    shown += " (normalized)" if normalized else ""
    what = {"TEXCOORD_": "texture coordinates", "COLOR_": "vertex colours", "NORMAL": "normals", "TANGENT": "tangents"}[semantic]
    message = f"{name} is {shown}, which glTF does not allow for {what}"
    if normalized and component_type not in (_BYTE, _UNSIGNED_BYTE, _SHORT, _UNSIGNED_SHORT):
        return message + ": only byte and short accessors can be normalized"
    if component_type in (_UNSIGNED_BYTE, _UNSIGNED_SHORT) and not normalized and semantic in ("TEXCOORD_", "COLOR_"):
        return message + (": read as whole numbers, every texture is sampled outside [0, 1]" if semantic == "TEXCOORD_"
                          else ": read as whole numbers, the colours multiply the base colour by up to 255")
    if semantic == "TANGENT" and accessor_type == "VEC3":
        return message + ": it has no w, the handedness the bitangent needs"
    return message


def _format_hint(semantic: str, accessor_type, component_type, normalized: bool) -> str:
    if normalized and component_type not in (_BYTE, _UNSIGNED_BYTE, _SHORT, _UNSIGNED_SHORT):
        return 'remove "normalized": true from the accessor'
    types, _, _ = ATTRIBUTE_FORMATS[semantic]
    if component_type in (_UNSIGNED_BYTE, _UNSIGNED_SHORT) and not normalized and accessor_type in types:
        return 'add "normalized": true to the accessor'
    if semantic == "TANGENT":
        return "export tangents as VEC4 of FLOAT, w the handedness (+1 or -1; MikkTSpace)"
    return {"TEXCOORD_": "store texture coordinates as VEC2 of FLOAT (or normalised unsigned bytes or shorts)",
            "COLOR_": "store vertex colours as VEC3 or VEC4 of FLOAT (or normalised unsigned bytes or shorts)",
            "NORMAL": "store normals as VEC3 of FLOAT"}[semantic]


def _tangents_without_normals(asset, primitives, context):
    for primitive in primitives:
        if primitive.get("tangents") and not primitive.get("normals"):
            yield context.diagnostic(
                NO_TANGENT_SPACE, f"primitive {primitive['pointer']} has TANGENT but no NORMAL: loaders compute flat "
                "normals and must ignore the tangents, so the exported tangent space is lost",
                Location(asset.path, None, f"{primitive['pointer']}/attributes", "TANGENT"),
                hint="export the normals with the mesh (or drop the tangents)")


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


def _generated_tangents(asset, primitives, context):
    """OPBR1235: one finding per normal-mapped material, at the first primitive drawing it without a tangent space."""
    mapped = {material.extra.get("gltf", {}).get("index"): material for material in asset.materials
              if material.inputs.get("normal") is not None and material.inputs["normal"].texture is not None}
    lacking: dict[int, list[dict]] = {}
    for primitive in primitives:
        index = primitive["material"]
        if isinstance(index, int) and not isinstance(index, bool) and index in mapped and \
                not (primitive.get("tangents") and primitive.get("normals")):
            lacking.setdefault(index, []).append(primitive)
    for index, found in lacking.items():
        first = found[0]
        more = f" (and {len(found) - 1} more)" if len(found) > 1 else ""
        if not first.get("normals"):
            lacks = ("has TANGENT but no NORMAL, so loaders ignore its tangents and compute flat normals" if
                     first.get("tangents") else "has neither NORMAL nor TANGENT (flat normals are computed first)")
        else:
            lacks = "has no TANGENT attribute"
        yield context.diagnostic(
            GENERATED_TANGENTS, f"material {mapped[index].name!r} has a normalTexture, but primitive {first['pointer']}{more} "
            f"{lacks}: the viewer generates the tangent space (MikkTSpace, as glTF asks), and the normal map shades as "
            "baked only if it was baked in that same tangent space",
            Location(asset.path, None, first["pointer"], "material"),
            hint="export the tangents the normal map was baked with (MikkTSpace) with the mesh")


_TANGENT_SPACE_TEXTURES = (("anisotropy_strength", "anisotropyTexture"), ("clearcoat_normal", "clearcoatNormalTexture"))


def _tangent_uv_sets(material, context):
    """OPBR1236: an anisotropy or clear-coat normal texture on another UV set than the normalTexture."""
    normal = material.inputs.get("normal")
    if normal is None or normal.texture is None:
        return
    normal_set = normal.texture.texcoord or 0
    for parameter, name in _TANGENT_SPACE_TEXTURES:
        entry = material.inputs.get(parameter)
        if entry is None or entry.texture is None or (entry.texture.texcoord or 0) == normal_set:
            continue
        yield context.diagnostic(
            TANGENT_UV_SET, f"{material.name}: {name} reads UV set {entry.texture.texcoord or 0} but normalTexture UV set "
            f"{normal_set}, whose tangent space the {'anisotropy direction' if parameter.startswith('anisotropy') else 'coat normal map'} "
            "is read in: where the two UV layouts differ in orientation it points the wrong way",
            Location(material.location.file, None, entry.texture.node, "texCoord"),
            hint=f"paint {name} on UV set {normal_set}, as the normal texture")
