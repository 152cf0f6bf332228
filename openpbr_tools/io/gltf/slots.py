"""Where each ``gltf_pbr`` parameter lives in a glTF material, shared by the glTF reader, writer and rules.

A :class:`Slot` names the JSON object holding the parameter (the material itself,
``pbrMetallicRoughness`` or a ``KHR_materials_*`` extension object), its factor property and its
texture property, and which channels of the texture feed it. The channels and colour encodings
are glTF 2.0's (specification section 3.9 and each extension's README):

* ``baseColorTexture``: RGB (sRGB) base colour, A alpha; ``metallicRoughnessTexture``: B metallic,
  G roughness; ``occlusionTexture``: R; ``emissiveTexture``: RGB (sRGB);
* clearcoat R, clearcoat roughness G; sheen colour RGB (sRGB), sheen roughness A; specular A,
  specular colour RGB (sRGB); transmission R; volume thickness G; iridescence R, iridescence
  thickness G; anisotropy RG direction and B strength; diffuse transmission A, its colour RGB (sRGB).

Factor defaults matter when a texture is authored without its factor: an ``emissiveTexture``
without ``emissiveFactor`` is multiplied by (0, 0, 0), a ``clearcoatTexture`` without
``clearcoatFactor`` by 0.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

CORE = ""
PBR = "pbrMetallicRoughness"

CLEARCOAT = "KHR_materials_clearcoat"
SHEEN = "KHR_materials_sheen"
SPECULAR = "KHR_materials_specular"
TRANSMISSION = "KHR_materials_transmission"
VOLUME = "KHR_materials_volume"
IOR = "KHR_materials_ior"
IRIDESCENCE = "KHR_materials_iridescence"
ANISOTROPY = "KHR_materials_anisotropy"
EMISSIVE_STRENGTH = "KHR_materials_emissive_strength"
DISPERSION = "KHR_materials_dispersion"
DIFFUSE_TRANSMISSION = "KHR_materials_diffuse_transmission"
UNLIT = "KHR_materials_unlit"
SPECULAR_GLOSSINESS = "KHR_materials_pbrSpecularGlossiness"
TEXTURE_TRANSFORM = "KHR_texture_transform"
VARIANTS = "KHR_materials_variants"  # (on the root and on primitives: no material extension despite its name)
MESH_QUANTIZATION = "KHR_mesh_quantization"
DRACO = "KHR_draco_mesh_compression"
# Extensions no file may list as optional: KHR_mesh_quantization "must [be specified] in extensionsRequired - the
# extension is not optional" (its README; the Khronos glTF-Validator's NON_REQUIRED_EXTENSION).
NEVER_OPTIONAL = (MESH_QUANTIZATION,)

# Material extensions the gltf_pbr node carries (read into inputs, written from them).
INTERPRETED_MATERIAL_EXTENSIONS = (CLEARCOAT, SHEEN, SPECULAR, TRANSMISSION, VOLUME, IOR, IRIDESCENCE,
                                   ANISOTROPY, EMISSIVE_STRENGTH, DISPERSION)
# Extensions that do not change how a material or its textures look: geometry, scene, metadata.
NEUTRAL_EXTENSIONS = (DRACO, MESH_QUANTIZATION, "EXT_meshopt_compression",
                      "KHR_lights_punctual", "EXT_mesh_gpu_instancing", "KHR_animation_pointer",
                      VARIANTS, "KHR_xmp_json_ld", "KHR_node_visibility")
# Everything the toolkit reads correctly when a file lists it in extensionsRequired.
# (EXT_texture_webp: the reader follows its image source, and WebP decodes; KTX2 from
# KHR_texture_basisu does not, so that one is not understood. KHR_materials_unlit: a conversion reads
# it as what it renders, emission of the base colour over a black base: translate/gltf.py;
# KHR_materials_pbrSpecularGlossiness: by the published spec-gloss -> metal-rough solve, translate/spec_gloss.py.)
UNDERSTOOD_EXTENSIONS = frozenset(INTERPRETED_MATERIAL_EXTENSIONS + (TEXTURE_TRANSFORM, "EXT_texture_webp", UNLIT,
                                                                   SPECULAR_GLOSSINESS)
                                  + NEUTRAL_EXTENSIONS)

# KHR_materials_unlit and KHR_materials_pbrSpecularGlossiness each state that the other material
# extensions "must not be used on a material that also uses" them (the Exclusions section of every
# KHR_materials_* README; KHR_materials_emissive_strength excludes only unlit).
EXCLUDED_WITH_UNLIT = INTERPRETED_MATERIAL_EXTENSIONS + (DIFFUSE_TRANSMISSION,)
EXCLUDED_WITH_SPECULAR_GLOSSINESS = tuple(e for e in EXCLUDED_WITH_UNLIT if e != EMISSIVE_STRENGTH)

ALPHA_MODES = ("OPAQUE", "MASK", "BLEND")  # gltf_pbr alpha_mode 0, 1, 2

SRGB = "srgb_texture"
DATA = "none"


@dataclass(frozen=True, slots=True)
class Slot:
    """One gltf_pbr parameter as glTF stores it.

    ``container`` is ``""`` for the material object, ``"pbrMetallicRoughness"`` or an extension
    name. ``factor`` is the factor property (``None`` when the parameter has none); for
    ``base_color`` and ``alpha`` it is ``baseColorFactor`` and ``factor_components`` picks RGB or A.
    ``texture`` is the textureInfo property; ``channels`` the texture channels that feed the
    parameter; ``colour`` whether the texture is sRGB-encoded colour.
    """

    parameter: str
    container: str
    factor: str | None
    default: object
    texture: str | None = None
    channels: tuple[int, ...] | None = None
    colour: bool = False
    factor_components: slice | None = None
    texture_kind: str = "textureInfo"  # or normalTextureInfo / occlusionTextureInfo

    @property
    def colorspace(self) -> str:
        return SRGB if self.colour else DATA

    @property
    def image_type(self) -> str:
        if self.texture_kind == "normalTextureInfo":
            return "vector3"
        return "color4" if self.channels and 3 in self.channels else "color3"


SLOTS: tuple[Slot, ...] = (
    Slot("base_color", PBR, "baseColorFactor", (1.0, 1.0, 1.0), "baseColorTexture", (0, 1, 2), True, slice(0, 3)),
    Slot("alpha", PBR, "baseColorFactor", 1.0, "baseColorTexture", (3,), False, slice(3, 4)),
    Slot("metallic", PBR, "metallicFactor", 1.0, "metallicRoughnessTexture", (2,)),
    Slot("roughness", PBR, "roughnessFactor", 1.0, "metallicRoughnessTexture", (1,)),
    Slot("normal", CORE, None, None, "normalTexture", None, texture_kind="normalTextureInfo"),
    Slot("occlusion", CORE, None, None, "occlusionTexture", (0,), texture_kind="occlusionTextureInfo"),
    Slot("emissive", CORE, "emissiveFactor", (0.0, 0.0, 0.0), "emissiveTexture", (0, 1, 2), True),
    Slot("alpha_mode", CORE, "alphaMode", "OPAQUE"),
    Slot("alpha_cutoff", CORE, "alphaCutoff", 0.5),
    Slot("clearcoat", CLEARCOAT, "clearcoatFactor", 0.0, "clearcoatTexture", (0,)),
    Slot("clearcoat_roughness", CLEARCOAT, "clearcoatRoughnessFactor", 0.0, "clearcoatRoughnessTexture", (1,)),
    Slot("clearcoat_normal", CLEARCOAT, None, None, "clearcoatNormalTexture", None, texture_kind="normalTextureInfo"),
    Slot("sheen_color", SHEEN, "sheenColorFactor", (0.0, 0.0, 0.0), "sheenColorTexture", (0, 1, 2), True),
    Slot("sheen_roughness", SHEEN, "sheenRoughnessFactor", 0.0, "sheenRoughnessTexture", (3,)),
    Slot("specular", SPECULAR, "specularFactor", 1.0, "specularTexture", (3,)),
    Slot("specular_color", SPECULAR, "specularColorFactor", (1.0, 1.0, 1.0), "specularColorTexture", (0, 1, 2), True),
    Slot("transmission", TRANSMISSION, "transmissionFactor", 0.0, "transmissionTexture", (0,)),
    Slot("thickness", VOLUME, "thicknessFactor", 0.0, "thicknessTexture", (1,)),
    Slot("attenuation_distance", VOLUME, "attenuationDistance", None),
    Slot("attenuation_color", VOLUME, "attenuationColor", (1.0, 1.0, 1.0)),
    Slot("ior", IOR, "ior", 1.5),
    Slot("iridescence", IRIDESCENCE, "iridescenceFactor", 0.0, "iridescenceTexture", (0,)),
    Slot("iridescence_ior", IRIDESCENCE, "iridescenceIor", 1.3),
    # Thickness: mix(iridescenceThicknessMinimum, iridescenceThicknessMaximum, texture.g), or the
    # maximum without a texture (handled specially by the reader and the writer).
    Slot("iridescence_thickness", IRIDESCENCE, "iridescenceThicknessMaximum", 400.0, "iridescenceThicknessTexture", (1,)),
    Slot("anisotropy_strength", ANISOTROPY, "anisotropyStrength", 0.0, "anisotropyTexture", (2,)),
    Slot("anisotropy_rotation", ANISOTROPY, "anisotropyRotation", 0.0),
    Slot("emissive_strength", EMISSIVE_STRENGTH, "emissiveStrength", 1.0),
    Slot("dispersion", DISPERSION, "dispersion", 0.0),
)

#: KHR_materials_pbrSpecularGlossiness, read into the glTF state (``extra["gltf"]["spec_gloss"]``, by the name
#: of the UsdPreviewSurface specular-workflow input each is read as: translate/spec_gloss.py). Each slot's
#: ``parameter`` is the gltf_pbr parameter of the same kind whose table entry the reader checks it by.
SPECULAR_GLOSSINESS_SLOTS = (
    ("diffuseColor", Slot("base_color", SPECULAR_GLOSSINESS, "diffuseFactor", (1.0, 1.0, 1.0), "diffuseTexture",
                          (0, 1, 2), True, slice(0, 3))),
    ("opacity", Slot("alpha", SPECULAR_GLOSSINESS, "diffuseFactor", 1.0, "diffuseTexture", (3,), False, slice(3, 4))),
    ("specularColor", Slot("base_color", SPECULAR_GLOSSINESS, "specularFactor", (1.0, 1.0, 1.0),
                           "specularGlossinessTexture", (0, 1, 2), True)),
    ("glossiness", Slot("roughness", SPECULAR_GLOSSINESS, "glossinessFactor", 1.0, "specularGlossinessTexture", (3,))),
)

#: KHR_materials_diffuse_transmission, which the gltf_pbr node does not carry (kept as data, the Material's
#: ``extra``): its properties and the channels each texture feeds (its README: the strength "stored in the alpha (A)
#: channel", the colour "in the RGB channels and encoded in sRGB").
DIFFUSE_TRANSMISSION_SLOTS = (
    Slot("diffuse_transmission", DIFFUSE_TRANSMISSION, "diffuseTransmissionFactor", 0.0, "diffuseTransmissionTexture",
         (3,)),
    Slot("diffuse_transmission_color", DIFFUSE_TRANSMISSION, "diffuseTransmissionColorFactor", (1.0, 1.0, 1.0),
         "diffuseTransmissionColorTexture", (0, 1, 2), True),
)

SLOT_BY_PARAMETER = {slot.parameter: slot for slot in SLOTS}

IRIDESCENCE_THICKNESS_MINIMUM = ("iridescenceThicknessMinimum", 100.0)

#: The properties each material JSON object may hold besides its slots' factors and textures (glTF 2.0's
#: material.schema.json, material.pbrMetallicRoughness.schema.json and textureInfo schemas, and each
#: extension's schema): the Khronos glTF-Validator reports any other as UNEXPECTED_PROPERTY.
COMMON_PROPERTIES = ("extensions", "extras")
OTHER_PROPERTIES = {
    CORE: ("name", "pbrMetallicRoughness", "doubleSided"),
    IRIDESCENCE: (IRIDESCENCE_THICKNESS_MINIMUM[0],),
    DIFFUSE_TRANSMISSION: tuple(name for slot in DIFFUSE_TRANSMISSION_SLOTS for name in (slot.factor, slot.texture)),
    UNLIT: (),
}
TEXTURE_INFO_PROPERTIES = {"textureInfo": ("index", "texCoord"), "normalTextureInfo": ("index", "texCoord", "scale"),
                           "occlusionTextureInfo": ("index", "texCoord", "strength")}
TEXTURE_TRANSFORM_PROPERTIES = ("offset", "rotation", "scale", "texCoord")


@functools.cache
def object_properties() -> dict[str, tuple[frozenset, dict[str, str]]]:
    """Per material JSON object (a :class:`Slot` container name), the properties its schema defines and,
    for each textureInfo property among them, its kind (``textureInfo``, ``normalTextureInfo``...)."""
    found: dict[str, tuple[set, dict]] = {}
    for slot in SLOTS + tuple(slot for _, slot in SPECULAR_GLOSSINESS_SLOTS):
        names, textures = found.setdefault(slot.container, (set(COMMON_PROPERTIES), {}))
        names.update(name for name in (slot.factor, slot.texture) if name)
        if slot.texture:
            textures[slot.texture] = slot.texture_kind
    for container, names in OTHER_PROPERTIES.items():
        known, textures = found.setdefault(container, (set(COMMON_PROPERTIES), {}))
        known.update(names)
        textures.update({name: "textureInfo" for name in names if name.endswith("Texture")})
    return {container: (frozenset(names), textures) for container, (names, textures) in found.items()}


ANISOTROPY_DIRECTION_DEFAULT = (1.0, 0.5)  # RG encoding of the direction (1, 0): (d + 1) / 2

# Image formats a texture extension adds to glTF's core PNG and JPEG (specification 3.8.2).
EXTENSION_MIME_TYPES = {"image/webp": "EXT_texture_webp", "image/ktx2": "KHR_texture_basisu"}


def wrap_to_address() -> dict[int, str]:
    """Sampler wrap enums (specification 5.26) -> MaterialX address modes."""
    import pygltflib  # lazy: pygltflib costs ~70 ms, and the rules import this module at every start-up

    return {pygltflib.REPEAT: "periodic", pygltflib.CLAMP_TO_EDGE: "clamp", pygltflib.MIRRORED_REPEAT: "mirror"}


def sampler_filters() -> dict[str, tuple[int, ...]]:
    """The filters a sampler's magFilter and minFilter may take (sampler.schema.json): NEAREST and LINEAR
    magnify; minifying adds the four mipmap modes (a mipmap mode as magFilter is the Khronos validator's
    VALUE_NOT_IN_LIST)."""
    import pygltflib  # lazy: as in wrap_to_address

    magnify = (pygltflib.NEAREST, pygltflib.LINEAR)
    return {"magFilter": magnify,
            "minFilter": magnify + (pygltflib.NEAREST_MIPMAP_NEAREST, pygltflib.LINEAR_MIPMAP_NEAREST,
                                    pygltflib.NEAREST_MIPMAP_LINEAR, pygltflib.LINEAR_MIPMAP_LINEAR)}


def address_to_wrap() -> dict[str, int]:
    """MaterialX address modes -> sampler wrap enums; ``constant`` (a border colour) has no glTF
    equivalent and becomes CLAMP_TO_EDGE (the writer notes it)."""
    import pygltflib  # lazy: as in wrap_to_address

    return {"periodic": pygltflib.REPEAT, "clamp": pygltflib.CLAMP_TO_EDGE, "mirror": pygltflib.MIRRORED_REPEAT,
            "constant": pygltflib.CLAMP_TO_EDGE}


def core_mime_types() -> tuple[str, ...]:
    import pygltflib  # lazy: as in wrap_to_address

    return tuple(pygltflib.IMAGE_MIMETYPES)
