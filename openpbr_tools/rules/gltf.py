"""glTF: checks that only make sense for glTF assets (extension declarations, exclusive material
extensions, texture coordinates, images, embedded resources).

The glTF reader fills the same model as the MaterialX reader (``gltf_pbr`` materials), so the generic
families judge glTF materials too: a factor outside its range is OPBR301 (here also a factor that
multiplies a texture: ``roughnessFactor`` 1.5 is as wrong with a texture as without), a property of
the wrong JSON type OPBR202, a texture, image, sampler or default-scene index that points nowhere OPBR802, an
image file that does not exist OPBR701, an image URI that is absolute, climbs out of the asset's
folder (with ``..`` or through a symbolic link) or is a URL OPBR704 (such an image is never opened),
an empty URI OPBR705. A file the reader refuses (not JSON, not UTF-8, a bad GLB container, JSON
nested more than 128 levels, above ``OPENPBR_MAX_FILE_MB``) is OPBR002 or OPBR001 and exit code 2. Colour spaces are implied by the texture slot in
glTF (colour textures sRGB, data textures linear), so the colour-space family does not apply.

One module because the family's rules read one set of facts (the glTF reader's) and their examples share
its builders; split, each half would import the other's.
"""

from __future__ import annotations

import difflib
import re
from functools import lru_cache

from .. import tables
from ..diagnostics import Severity
from ..io.gltf import drafts, slots
from ..model import Location, Texture
from ..resources import load_json
from . import Rule, constant_or_default
from .ranges import HARD_RANGE
from .textures import EMBEDDED_REMEDY, UNSAFE_PATH, damage_diagnostic

_PNG_3X3 = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAMAAAADCAIAAADZSiLoAAAAF0lEQVR42mM8kWLEwMDAwMDAxAADCBYA"
            "J1YBZLcOOO0AAAAASUVORK5CYII=")
_PNG_4X4 = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mM8kWLEAANMDEgANwcA"
            "RfYBZsiXQosAAAAASUVORK5CYII=")


def _gltf(*members: str) -> str:
    """A glTF document: the asset header plus the given top-level members (JSON text)."""
    body = ",\n  ".join(('"asset": {"version": "2.0"}',) + members)
    return "{\n  " + body + "\n}\n"


def _one_image(uri: str, material: str, *members: str) -> str:
    """A glTF document whose one material (``material``, JSON text) reads texture 0, image ``uri``."""
    return _gltf(f'"images": [{{"uri": "{uri}"}}]', '"textures": [{"source": 0}]', f'"materials": [{material}]', *members)


def _textured(uri: str) -> str:
    return _one_image(uri, '{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}')


_CLEARCOAT = '"materials": [{"name": "M", "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0}}}]'
_PRIMITIVE = ('"accessors": [{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]}, '
              '{"componentType": 5126, "count": 3, "type": "VEC2"}]')


def _mesh(texcoord: int) -> str:
    return _gltf(
        f'"images": [{{"uri": "{_PNG_4X4}"}}]', '"textures": [{"source": 0}]',
        f'"materials": [{{"name": "M", "pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0, "texCoord": {texcoord}}}}}}}]',
        _PRIMITIVE,
        '"meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}]',
    )


UNDECLARED_EXTENSION = Rule(
    "OPBR1201", "gltf-extension-not-declared", Severity.ERROR,
    "An extension is used but not listed in extensionsUsed (or listed in extensionsRequired only), or "
    "KHR_mesh_quantization is not listed in extensionsRequired.",
    "glTF 2.0 (section 3.12) requires every extension used anywhere in the asset to be named in "
    "extensionsUsed, and every name in extensionsRequired to be in extensionsUsed too. Loaders that "
    "trust the declaration skip the undeclared extension, so the material renders without it; the "
    "Khronos glTF-Validator reports it as an error. KHR_mesh_quantization \"is not optional\": its attribute "
    "formats (normalised SHORT texture coordinates, BYTE normals) are invalid without it, so a loader that does not "
    "know it must refuse the file rather than misread the mesh (the validator's NON_REQUIRED_EXTENSION).",
    passing=_gltf('"extensionsUsed": ["KHR_materials_clearcoat"]', _CLEARCOAT),
    failing=_gltf(_CLEARCOAT),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
REQUIRED_UNSUPPORTED = Rule(
    "OPBR1202", "gltf-required-extension-not-interpreted", Severity.WARNING,
    "extensionsRequired names an extension this toolkit cannot interpret.",
    "A required extension changes what the file means; a reader that does not implement it must not "
    "load the asset. The toolkit reads the material anyway, so its findings (and any conversion) may "
    "miss what the extension changes. Interpreted: KHR_texture_transform, EXT_texture_webp, the "
    "KHR_materials_* extensions the gltf_pbr node carries, and extensions that do not affect materials "
    "(mesh compression, lights, instancing, variants).",
    passing=_gltf('"extensionsUsed": ["KHR_materials_clearcoat"]', '"extensionsRequired": ["KHR_materials_clearcoat"]', _CLEARCOAT),
    failing=_gltf('"extensionsUsed": ["VENDOR_materials_magic"]', '"extensionsRequired": ["VENDOR_materials_magic"]',
                  '"materials": [{"name": "M", "extensions": {"VENDOR_materials_magic": {"sparkle": 1}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
EXCLUSIVE_EXTENSIONS = Rule(
    "OPBR1203", "gltf-exclusive-material-extensions", Severity.ERROR,
    "A material combines extensions the glTF specification forbids together.",
    "Every KHR_materials_* extension \"must not be used on a material that also uses\" "
    "KHR_materials_unlit, and all but KHR_materials_emissive_strength not with "
    "KHR_materials_pbrSpecularGlossiness (the Exclusions section of each extension). Viewers pick one "
    "interpretation or the other, so the material looks different everywhere.",
    passing=_gltf('"extensionsUsed": ["KHR_materials_unlit"]', '"materials": [{"name": "M", "extensions": {"KHR_materials_unlit": {}}}]'),
    failing=_gltf('"extensionsUsed": ["KHR_materials_unlit", "KHR_materials_clearcoat"]',
                  '"materials": [{"name": "M", "extensions": {"KHR_materials_unlit": {}, '
                  '"KHR_materials_clearcoat": {"clearcoatFactor": 1.0}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
NOT_CONVERTED = Rule(
    "OPBR1204", "gltf-material-model-not-converted", Severity.WARNING,
    "A material uses KHR_materials_pbrSpecularGlossiness, which Khronos archived.",
    "Superseded by KHR_materials_specular (with KHR_materials_ior): a viewer that no longer reads it shows "
    "the metallic-roughness fallback (glTF's default, a white rough metal, where the file authors none). "
    "Conversions read it as a viewer that supports it renders it: roughness 1 - glossiness, base colour, "
    "metalness and IOR by the spec-gloss -> metal-rough solve (Babylon.js, glTF-Toolkit), approximate for a "
    "coloured specular colour and said so. A malformed one (not an object) is not read. (KHR_materials_unlit "
    "is converted as what it renders, emission of its base colour over a black base: not reported.)",
    passing=_gltf('"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0]}}]'),
    failing=_gltf('"extensionsUsed": ["KHR_materials_pbrSpecularGlossiness"]',
                  '"materials": [{"name": "M", "extensions": {"KHR_materials_pbrSpecularGlossiness": '
                  '{"diffuseFactor": [0.8, 0.8, 0.8, 1.0], "glossinessFactor": 0.5}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
EXTENSION_NOT_CONVERTED = Rule(
    "OPBR1212", "gltf-extension-not-converted", Severity.INFO,
    "A material uses a material extension the toolkit does not convert (KHR_materials_diffuse_transmission "
    "with textures or a volume, or one it does not know, also nested in a KHR_materials_* object).",
    "The file is not wrong (Khronos' own samples use these); the toolkit's reach ends: checks and "
    "conversions see the material without the extension. A top-level one is kept as data and restored "
    "on glTF output; a conversion reports what it keeps and what it loses. The draft extensions that "
    "align glTF with OpenPBR (KHR_materials_coat, _fuzz, _diffuse_roughness, KHR_materials_clearcoat_ior "
    "and Adobe's EXT_materials_*_openpbr family) are read, not reported.",
    passing=_gltf('"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0]}}]'),
    failing=_gltf('"extensionsUsed": ["VENDOR_materials_sparkle"]',
                  '"materials": [{"name": "M", "extensions": {"VENDOR_materials_sparkle": {"amount": 0.5}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
MISSING_TEXCOORD = Rule(
    "OPBR1205", "gltf-texcoord-missing", Severity.ERROR,
    "A texture reads a UV set (texCoord n) that a mesh primitive using the material does not have, or a "
    "primitive's UV sets skip a number (TEXCOORD_0 and TEXCOORD_2 without TEXCOORD_1).",
    "The primitive has no TEXCOORD_n attribute, so the texture is sampled at undefined coordinates "
    "(most viewers read (0, 0) everywhere: one flat colour). Checked only when the file has meshes. "
    "glTF 2.0 (3.7.2.1): indexed attributes \"MUST start with 0 and be consecutive positive integers\"; a set "
    "deleted without renumbering the rest leaves loaders that count the sets (or bind them by position) reading "
    "TEXCOORD_2 as set 1, so the textures on set 2 are sampled at the wrong coordinates or not at all (the Khronos "
    "glTF-Validator's MESH_PRIMITIVE_INDEXED_SEMANTIC_CONTINUITY, an error).",
    passing=_mesh(0), failing=_mesh(1),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
NOT_POWER_OF_TWO = Rule(
    "OPBR1206", "gltf-image-not-power-of-two", Severity.INFO,
    "An image's width or height is not a power of two.",
    "Legal in glTF 2.0, but WebGL 1 viewers cannot mipmap or repeat such textures and resample them, "
    "and GPU block compression (KTX2/Basis) wants multiples of 4. Worth resizing for real-time use.",
    passing=_gltf(f'"images": [{{"uri": "{_PNG_4X4}"}}]', '"textures": [{"source": 0}]',
                  '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]'),
    failing=_gltf(f'"images": [{{"uri": "{_PNG_3X3}"}}]', '"textures": [{"source": 0}]',
                  '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
UNSUPPORTED_IMAGE = Rule(
    "OPBR1207", "gltf-unsupported-image-type", Severity.WARNING,
    "An image is neither PNG nor JPEG (nor WebP/KTX2 through their texture extension).",
    "glTF 2.0 core images are image/png or image/jpeg (section 3.8.2); EXR, TIFF, TGA or HDR files "
    "are not loaded by glTF viewers, so the texture is missing there. Convert it (`openpbr convert` "
    "writes PNG).",
    passing=_textured("albedo.png"), failing=_textured("albedo.exr"),
    example_files=("albedo.png", "albedo.exr"),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
_WEBP = "data:image/webp;base64,UklGRh4AAABXRUJQVlA4TBEAAAAvA8AAAAdQiirUo/+BiOh/AAA="
IMAGE_NEEDS_EXTENSION = Rule(
    "OPBR1220", "gltf-image-needs-texture-extension", Severity.ERROR,
    "A texture's core source is a WebP or KTX2 image: those formats are only allowed through EXT_texture_webp "
    "or KHR_texture_basisu; or such an extension's source is an image of another format (a PNG), or "
    "KHR_texture_basisu's is no KTX2 with a Basis Universal payload (a legacy .basis file, raw KTX2 texels).",
    "glTF 2.0's texture.source names a PNG or JPEG image (3.8.2, and the mimeType enum of image.schema.json); "
    "KHR_texture_basisu allows image/ktx2 only for images \"referenced by the source property of "
    "KHR_texture_basisu texture extension object\", and EXT_texture_webp likewise adds WebP through its own "
    "source, the core source being a PNG or JPEG fallback. A viewer without the extension fails on the image, "
    "one with it never looks for it there: the Khronos glTF-Validator's TEXTURE_INVALID_IMAGE_MIME_TYPE (an "
    "error). Conversely the extension's source \"is the index of\" a WebP (a KTX2) image: a PNG there fails in the "
    "viewers that read the extension (same code; the gltf_structure family). KHR_texture_basisu's source is "
    "moreover a \"KTX v2 image with Basis Universal supercompression\" (its README: ETC1S with BasisLZ, or UASTC): "
    "a pre-ratification .basis file, or a KTX2 of raw texels (a vkFormat such as R8G8B8A8_SRGB, written by toktx "
    "without --encode), cannot be transcoded by the viewers' Basis transcoders, so the texture is missing "
    "everywhere (the validator only calls the image unrecognised, a warning). Other formats (TGA, EXR) that no "
    "extension defines are OPBR1207.",
    passing=_gltf('"extensionsUsed": ["EXT_texture_webp"]', '"extensionsRequired": ["EXT_texture_webp"]',
                  f'"images": [{{"uri": "{_WEBP}"}}]', '"textures": [{"extensions": {"EXT_texture_webp": {"source": 0}}}]',
                  '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]'),
    failing=_gltf(f'"images": [{{"uri": "{_WEBP}"}}]', '"textures": [{"source": 0}]',
                  '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
STRENGTH_WITHOUT_EMISSIVE = Rule(
    "OPBR1208", "gltf-emissive-strength-without-emissive", Severity.WARNING,
    "KHR_materials_emissive_strength is set but the material emits nothing (emissiveFactor is black or absent).",
    "emissiveStrength multiplies emissiveFactor (default (0, 0, 0)) and the emissive texture; with a "
    "black factor the strength has no effect. Usually an exporter that dropped the emissive colour.",
    passing=_gltf('"extensionsUsed": ["KHR_materials_emissive_strength"]',
                  '"materials": [{"name": "M", "emissiveFactor": [1.0, 0.5, 0.2], '
                  '"extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5.0}}}]'),
    failing=_gltf('"extensionsUsed": ["KHR_materials_emissive_strength"]',
                  '"materials": [{"name": "M", "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5.0}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
BROKEN_RESOURCE = Rule(
    "OPBR1209", "gltf-broken-resource", Severity.ERROR,
    "A buffer or embedded image cannot be loaded: invalid base64, above the size limit, missing, shorter than its "
    "byteLength, or outside its buffer; a buffer's data URI declares a media type other than application/octet-stream "
    "or application/gltf-buffer; or a GLB chunk is not 4-byte aligned, or is a second JSON or BIN chunk.",
    "A data URI that is not valid base64, a buffer file that does not exist or holds fewer bytes than its "
    "byteLength (3.6.1; a truncated copy: the validator's BUFFER_BYTE_LENGTH_MISMATCH), a bufferView past the "
    "end of its buffer or a GLB without the binary chunk its buffer needs: loaders fail on the whole "
    "file or show the mesh without the texture. A GLB chunk whose length is no multiple of 4 (4.4.3: chunks "
    "\"MUST be aligned to a 4-byte boundary\", the JSON padded with spaces; GLB_CHUNK_LENGTH_UNALIGNED) leaves "
    "the binary data unaligned for loaders that map it in place; a GLB has one JSON chunk and at most one BIN chunk "
    "(4.4.3; a second of either: GLB_DUPLICATE_CHUNK), and loaders read the first, the last or refuse the file. A "
    "buffer's data URI \"MUST\" declare "
    "application/octet-stream or application/gltf-buffer (3.6.1; BUFFER_DATA_URI_MIME_TYPE_INVALID): a text/plain "
    "one is refused by loaders that check. A data URI whose decoded size is above "
    "OPENPBR_MAX_DATA_URI_MB (default: the file limit OPENPBR_MAX_FILE_MB, 64 MiB) is reported "
    "without being decoded, and a buffer an image needs that lies outside the asset's folder is "
    "never opened.",
    passing=_gltf(f'"images": [{{"uri": "{_PNG_4X4}"}}]', '"textures": [{"source": 0}]',
                  '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]'),
    failing=_gltf('"images": [{"uri": "data:image/png;base64,iVBORw0KGgo!!!not-base64!!!"}]', '"textures": [{"source": 0}]',
                  '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
INVALID_PROPERTY = Rule(
    "OPBR1210", "gltf-invalid-property", Severity.ERROR,
    "A material property has the wrong JSON type (a textureInfo without an integer index or null, an "
    "extension, an extensions property or pbrMetallicRoughness that is not an object (null), a malformed "
    "KHR_texture_transform; a number written 0.0 is the integer it equals, as JSON Schema reads it), a NaN or "
    "Infinity literal anywhere (not JSON: the validator's INVALID_JSON), a KHR_materials_variants mapping whose "
    "material or variant index is no index (-1, 0.5), a material extension on another "
    "object (KHR_materials_emissive_strength inside pbrMetallicRoughness, KHR_texture_transform on a "
    "material), a sampler filter or wrap outside the schema's list, or a value out of range that no "
    "gltf_pbr parameter holds (texCoord, occlusion strength, iridescenceThicknessMinimum); an image with both "
    "a uri and a bufferView, or in a bufferView without a mimeType; a name listed twice in extensionsUsed or "
    "extensionsRequired; a KHR_materials_variants object on a material (it belongs on the root and on mesh "
    "primitives), a variant that is not an object with a string name, or a variants mapping that lists no variant; "
    "an image in a bufferView with a byteStride or a target, or in one a mesh primitive draws with; a "
    "KHR_draco_mesh_compression object without its bufferView or attributes; an empty array at the root "
    "(\"samplers\": []), an extensionsUsed item that is no string, or an image or buffer uri that is no URI "
    "(http://[::1/a.png); a node hierarchy that is not a set of disjoint trees (a loop, a node with two parents, a "
    "scene listing a child node) or a POSITION accessor without min and max (the data the material is drawn with); "
    "JSON text that starts with a byte-order mark (\"glTF exporters MUST NOT add a byte "
    "order mark\"; clients may ignore it, JSON.parse on the raw text does not: the validator's INVALID_JSON).",
    "The glTF schema rejects the file; lenient loaders skip the property, so the texture or extension "
    "silently disappears. A bufferView of image data \"MUST NOT\" define byteStride (glTF 2.0, 3.6.1.1; the "
    "Khronos glTF-Validator's IMAGE_BUFFER_VIEW_WITH_BYTESTRIDE), nor a target (34962 vertices, 34963 indices), and "
    "it is no mesh data: loaders that honour the target, or share the view with a primitive's accessor, upload the "
    "image's bytes to the GPU as vertices (BUFFER_VIEW_TARGET_OVERRIDE). The root's arrays have at least one item "
    "and extensionsUsed names strings (EMPTY_ENTITY, ARRAY_TYPE_MISMATCH); a uri that a URI parser refuses (a "
    "scheme not starting with a letter, an unclosed IPv6 bracket, a port that is no number) names nothing a loader "
    "can fetch (INVALID_URI). KHR_draco_mesh_compression's schema requires "
    "bufferView (the compressed stream) and attributes: without them a required Draco extension leaves the decoder "
    "nothing to decode, and the mesh is not drawn (the validator does not look into the extension). Factors of the "
    "wrong type are OPBR202. A string holding an unpaired "
    "surrogate escape (\\ud800 alone) is valid JSON but no valid text: it cannot be written as UTF-8, "
    "and tools disagree on it; it is read with U+FFFD in its place.",
    passing=_gltf('"materials": [{"name": "M", "normalTexture": {"index": 0}}]', '"textures": [{"source": 0}]',
                  f'"images": [{{"uri": "{_PNG_4X4}"}}]'),
    failing=_gltf('"materials": [{"name": "M", "normalTexture": {"index": "0"}}]', '"textures": [{"source": 0}]',
                  f'"images": [{{"uri": "{_PNG_4X4}"}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

NO_EFFECT = Rule(
    "OPBR1211", "gltf-extension-no-effect", Severity.WARNING,
    "A material extension is set where the glTF extension texts say it has no effect: transmission "
    "or diffuse transmission on a fully metallic material, a volume without a transmission extension, dispersion "
    "without a volume, iridescence with zero thickness, a volume beside an empty transmission "
    "object, an empty extension object that is the material's only empty one (\"KHR_materials_transmission\": {}; "
    "OPBR1251 where the material writes several empty); a texture whose factor is left at its "
    "default 0 (emissiveTexture without emissiveFactor), a normal map at scale 0, or a texture without the "
    "channel its slot reads (an RGB specularTexture, sheenRoughnessTexture or diffuseTransmissionTexture, which read "
    "alpha alone, an anisotropyTexture whose blue strength is 0 everywhere, an "
    "RGB base colour texture under alphaMode MASK that never reaches below the cutoff: the gltf_images family); "
    "or an alphaCutoff without alphaMode MASK.",
    "KHR_materials_transmission applies to the dielectric part only (metallicFactor defaults to 1, so "
    "an exporter that omits it makes glass opaque metal); KHR_materials_volume acts only through "
    "transmission or diffuse transmission, and KHR_materials_dispersion only through a volume "
    "(the Khronos validator's VOLUME_NO_TRANSMISSION / DISPERSION_NO_VOLUME); iridescence needs a film "
    "thicker than 0 nm; a factor multiplies its texture, so an emissive, clearcoat, transmission or sheen "
    "texture without its factor (default 0) shows nothing, and transmissionFactor, clearcoatFactor, "
    "sheenColorFactor (\"If sheenColorFactor is zero, the whole sheen layer is disabled\"), iridescenceFactor, "
    "anisotropyStrength and diffuseTransmissionFactor each default to 0. KHR_materials_diffuse_transmission "
    "replaces part of the dielectric's diffuse BRDF, which a metal (metallicFactor 1) does not have. A normal "
    "texture's scale multiplies the map's X and Y (3.9.3), so 0 leaves the vertex normal. A slot reads the "
    "channel its extension names (KHR_materials_specular: strength \"stored in the alpha (A) channel\"; "
    "KHR_materials_sheen: sheenRoughnessTexture likewise in A; KHR_materials_diffuse_transmission: strength in A; the "
    "draft KHR_materials_fuzz: roughness in A; KHR_materials_anisotropy: strength in B; 3.9.2: alpha in the base "
    "colour texture's A), and an image without that channel reads A = 1 (an RGB JPEG never has one). "
    "Usually half of a set-up lost in export.",
    passing=_gltf('"extensionsUsed": ["KHR_materials_transmission"]',
                  '"materials": [{"name": "M", "pbrMetallicRoughness": {"metallicFactor": 0.0}, '
                  '"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}}]'),
    failing=_gltf('"extensionsUsed": ["KHR_materials_transmission"]',
                  '"materials": [{"name": "M", "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

EMPTY_EXTENSION = Rule(
    "OPBR1251", "gltf-extension-empty", Severity.INFO,
    "A material extension object is empty where the factor that carries its effect defaults to 0 "
    "(\"KHR_materials_sheen\": {}, likewise transmission, clearcoat, iridescence, anisotropy and diffuse "
    "transmission), in a material that writes other extensions empty too: the extension does nothing. (A lone empty "
    "extension is OPBR1211's.)",
    "Valid glTF, and the material renders as it would without the object: every property is optional, and "
    "each extension's README gives its factor the default 0 (\"If sheenColorFactor is zero, the whole sheen "
    "layer is disabled\"). The Khronos glTF-Validator does not report it. Exporters write such objects for a "
    "feature switched off (MaterialX's standard_surface_to_gltf_pbr graph, baked to glTF, writes one for each "
    "lobe at 0, ior, specular and emissive strength empty beside them), so where a material writes several empty "
    "extension objects it is a note, not a warning. A lone empty object is more likely a set-up lost in export (a "
    "glass whose transmissionFactor was never written): OPBR1211, a warning, as an extension that authors a "
    "texture or a setting but no factor.",
    passing=_gltf('"extensionsUsed": ["KHR_materials_sheen"]',
                  '"materials": [{"name": "M", "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1]}}}]'),
    failing=_gltf('"extensionsUsed": ["KHR_materials_sheen", "KHR_materials_ior"]',
                  '"materials": [{"name": "M", "extensions": {"KHR_materials_sheen": {}, "KHR_materials_ior": {}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

UNEXPECTED_PROPERTY = Rule(
    "OPBR1213", "gltf-unexpected-property", Severity.WARNING,
    "A material, pbrMetallicRoughness, textureInfo, KHR_texture_transform, known material extension, texture, "
    "image or sampler object holds a property its JSON schema does not define (often a misspelling: iridescenceIOR "
    "for iridescenceIor; wrapS on a texture, where it belongs on the sampler).",
    "glTF's schemas name every property of these objects; viewers ignore any other, so a misspelt factor "
    "silently renders as its default. The Khronos glTF-Validator reports it (UNEXPECTED_PROPERTY) as a "
    "warning; so does this rule, with the property most likely meant. Extensions the toolkit does not know "
    "are not looked into.",
    passing=_gltf('"extensionsUsed": ["KHR_materials_ior"]',
                  '"materials": [{"name": "M", "extensions": {"KHR_materials_ior": {"ior": 1.4}}}]'),
    failing=_gltf('"extensionsUsed": ["KHR_materials_ior"]',
                  '"materials": [{"name": "M", "extensions": {"KHR_materials_ior": {"IOR": 1.4}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
MIME_MISMATCH = Rule(
    "OPBR1214", "gltf-image-mime-mismatch", Severity.ERROR,
    "An image's declared MIME type (its mimeType, or its data URI's type) is not the format of its bytes.",
    "Loaders that choose the decoder by the declared type, rather than by the bytes, fail on the image and "
    "show the material without its texture; browsers that sniff the bytes show it, so the file seems fine "
    "where it was checked. The Khronos glTF-Validator reports it as an error (IMAGE_MIME_TYPE_INVALID; "
    "INVALID_URI for a data URI).",
    passing=_gltf(f'"images": [{{"uri": "{_PNG_4X4}"}}]', '"textures": [{"source": 0}]',
                  '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]'),
    failing=_gltf(f'"images": [{{"uri": "{_PNG_4X4.replace("image/png", "image/jpeg")}"}}]', '"textures": [{"source": 0}]',
                  '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

_SPEC_GLOSS = ('"extensionsUsed": ["KHR_materials_pbrSpecularGlossiness"]',
               '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], '
               '"metallicFactor": 0.0}, "extensions": {"KHR_materials_pbrSpecularGlossiness": '
               '{"diffuseFactor": [0.8, 0.8, 0.8, 1.0], "glossinessFactor": 0.5}}}]')
ARCHIVED_WITH_FALLBACK = Rule(
    "OPBR1215", "gltf-archived-extension-with-fallback", Severity.INFO,
    "A material uses the archived KHR_materials_pbrSpecularGlossiness and authors a metallic-roughness fallback.",
    "As OPBR1204, but the file does what the extension asks of an exporter: pbrMetallicRoughness holds the "
    "material for viewers that no longer read spec-gloss, and the extension is not required, so every "
    "viewer shows an authored material. Conversions read the spec-gloss values, as a viewer that supports "
    "them renders them.",
    passing=_gltf(_SPEC_GLOSS[1].replace(', "extensions": {"KHR_materials_pbrSpecularGlossiness": '
                                         '{"diffuseFactor": [0.8, 0.8, 0.8, 1.0], "glossinessFactor": 0.5}}', "")),
    failing=_gltf(*_SPEC_GLOSS),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)
MISSPELT_EXTENSION = Rule(
    "OPBR1216", "gltf-extension-name-misspelt", Severity.WARNING,
    "An extension name that no registry defines is one or two letters away from one that it does, or is not "
    "written as one (VENDOR_name: clearcoat without a prefix).",
    "KHR_material_clearcoat (without the s) is an unknown extension to every viewer, which ignore it "
    "silently: the clear coat never renders, though extensionsUsed and the material agree with each "
    "other. The Khronos glTF-Validator reports only that it cannot validate the extension (an info), and a name "
    "without the upper-case vendor prefix and underscore of the registry's convention as a warning "
    "(INVALID_EXTENSION_NAME_FORMAT). "
    "Known names: the Khronos registry's (schemas/gltf_extensions.json) and the drafts the toolkit reads.",
    passing=_gltf('"extensionsUsed": ["KHR_materials_clearcoat"]', _CLEARCOAT),
    failing=_gltf('"extensionsUsed": ["KHR_material_clearcoat"]',
                  _CLEARCOAT.replace("KHR_materials_clearcoat", "KHR_material_clearcoat")),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

RULES = (UNDECLARED_EXTENSION, REQUIRED_UNSUPPORTED, EXCLUSIVE_EXTENSIONS, NOT_CONVERTED, MISSING_TEXCOORD,
         NOT_POWER_OF_TWO, UNSUPPORTED_IMAGE, STRENGTH_WITHOUT_EMISSIVE, BROKEN_RESOURCE, INVALID_PROPERTY, NO_EFFECT,
         EXTENSION_NOT_CONVERTED, UNEXPECTED_PROPERTY, MIME_MISMATCH, ARCHIVED_WITH_FALLBACK, MISSPELT_EXTENSION,
         IMAGE_NEEDS_EXTENSION, EMPTY_EXTENSION)


def check(asset, context):
    """Runs on glTF assets only (rules.FAMILY_FORMATS)."""
    facts = asset.extra.get("gltf", {})
    yield from _declarations(asset, facts, context)
    yield from _observations(asset, context)
    for material in asset.materials:
        yield from _exclusions(material, context)
        yield from _emissive_strength(material, context)
        yield from _no_effect(material, context)
        yield from _texture_factors(material, context)
    yield from _texcoords(asset, facts, context)
    yield from _images(asset, facts, context)


@lru_cache(maxsize=1)
def known_extension_names() -> frozenset[str]:
    """Every extension name the Khronos registry defines (schemas/gltf_extensions.json), the archived
    ones and the drafts the toolkit reads: anything else is unknown to viewers."""
    return frozenset(load_json("gltf_extensions.json")["registry"]) | slots.UNDERSTOOD_EXTENSIONS \
        | {slots.DIFFUSE_TRANSMISSION} | frozenset(drafts.ALL_DRAFTS)


#: Unknown extension names compared with the registry per file, at most (each costs ~2 ms; a file listing
#: thousands is hostile, not misspelt).
MISSPELLING_CHECKS = 64


@lru_cache(maxsize=1024)
def _registry_name_near(name: str) -> str | None:
    """The registry name one or two edits from ``name`` (the nearest, then the first in order), or ``None``."""
    near = [(_edits(name, known, 3), known) for known in sorted(known_extension_names())
            if abs(len(known) - len(name)) <= 2]
    best = min(near, default=(3, None))
    return best[1] if best[0] <= 2 else None


#: An extension's name: an upper-case vendor prefix, an underscore and the rest (the glTF extension registry's
#: naming convention; the Khronos glTF-Validator's pattern for INVALID_EXTENSION_NAME_FORMAT).
EXTENSION_NAME = re.compile(r"[A-Z0-9]+_[A-Za-z0-9_]+")


def _misspelt(asset, facts, context):
    known = known_extension_names()
    unknown = [(index, name) for index, name in enumerate(facts.get("extensions_used", ()))
               if isinstance(name, str) and name not in known]
    for index, name in unknown[:MISSPELLING_CHECKS]:
        meant = _registry_name_near(name)
        if meant is None and not EXTENSION_NAME.fullmatch(name):
            yield context.diagnostic(
                MISSPELT_EXTENSION, f"{name!r} is no extension name: names are a vendor prefix in capitals, an "
                "underscore and the rest (KHR_materials_clearcoat), and viewers ignore an extension they do not know",
                Location(asset.path, None, f"/extensionsUsed/{index}"),
                hint="name the extension by its registered name (KHR_..., EXT_..., or your own vendor prefix)")
        if meant is not None:
            yield context.diagnostic(
                MISSPELT_EXTENSION, f"{name} is no known extension: viewers ignore it (a misspelling of {meant}?)",
                Location(asset.path, None, f"/extensionsUsed/{index}"),
                hint=f"rename it {meant} here and where the file uses it")


def _edits(a: str, b: str, limit: int) -> int:
    """The Levenshtein distance of ``a`` and ``b`` (insertions, deletions, substitutions), or ``limit``
    when it is at least that."""
    if abs(len(a) - len(b)) >= limit:
        return limit
    previous = list(range(len(b) + 1))
    for i, x in enumerate(a, 1):
        current = [i]
        for j, y in enumerate(b, 1):
            current.append(min(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + (x != y)))
        if min(current) >= limit:
            return limit
        previous = current
    return min(previous[-1], limit)


def _declarations(asset, facts, context):
    yield from _misspelt(asset, facts, context)
    used = set(facts.get("extensions_used", ()))
    reported = set()
    for pointer, name in facts.get("extension_uses", ()):
        if name not in used and name not in reported:
            reported.add(name)
            yield context.diagnostic(UNDECLARED_EXTENSION, f"{name} is used but not declared in extensionsUsed",
                                     Location(asset.path, None, pointer), hint=f'add "{name}" to extensionsUsed')
    for index, name in enumerate(facts.get("extensions_used", ())):
        if name in slots.NEVER_OPTIONAL and name not in facts.get("extensions_required", ()):
            yield context.diagnostic(UNDECLARED_EXTENSION, f"{name} is in extensionsUsed but not in extensionsRequired: "
                                     "it cannot be optional (a loader without it misreads the quantised attributes)",
                                     Location(asset.path, None, f"/extensionsUsed/{index}"),
                                     hint=f'add "{name}" to extensionsRequired')
    for index, name in enumerate(facts.get("extensions_required", ())):
        where = Location(asset.path, None, f"/extensionsRequired/{index}")
        if name not in used:
            yield context.diagnostic(UNDECLARED_EXTENSION, f"{name} is in extensionsRequired but not in extensionsUsed",
                                     where, hint=f'add "{name}" to extensionsUsed')
        if name not in slots.UNDERSTOOD_EXTENSIONS:
            yield context.diagnostic(REQUIRED_UNSUPPORTED, f"{name} is required, and the toolkit does not interpret it",
                                     where, hint="findings and conversions ignore what this extension changes")


def _observations(asset, context):
    for observation in asset.observations:
        detail = observation.detail
        if observation.kind == "gltf_resource":
            yield context.diagnostic(BROKEN_RESOURCE, detail["message"], observation.location)
        elif observation.kind == "gltf_buffer_outside":
            yield context.diagnostic(UNSAFE_PATH, f"buffer {detail['message']}: the meshes it holds are not checked",
                                     observation.location,
                                     hint="copy the buffer next to the asset and use a relative path (or a .glb)")
        elif observation.kind == "gltf_invalid":
            yield context.diagnostic(INVALID_PROPERTY, detail["message"], observation.location)
        elif observation.kind == "gltf_unexpected_property":
            guess = difflib.get_close_matches(detail["property"], detail["expected"], n=1, cutoff=0.6)
            yield context.diagnostic(
                UNEXPECTED_PROPERTY, f"{detail['object']} has no property {detail['property']!r}: glTF viewers ignore it",
                observation.location, hint=f"did you mean {guess[0]!r}?" if guess else f"known: {', '.join(detail['expected'])}")
        elif observation.kind == "gltf_archived" and detail.get("fallback"):
            yield context.diagnostic(ARCHIVED_WITH_FALLBACK, f"material {detail['material']!r} uses {detail['extension']}, "
                                     "which Khronos archived, with a metallic-roughness fallback for viewers that no "
                                     "longer read it", observation.location,
                                     hint="conversions read the spec-gloss values (approximate for a coloured specular colour)")
        elif observation.kind == "gltf_archived":
            yield context.diagnostic(NOT_CONVERTED, f"material {detail['material']!r} uses {detail['extension']}, which "
                                     "Khronos archived (superseded by KHR_materials_specular); viewers that no longer "
                                     "read it show the metallic-roughness fallback", observation.location,
                                     hint="conversions read it by the spec-gloss -> metal-rough solve (approximate for a "
                                          "coloured specular colour); re-export as metallic-roughness")
        elif observation.kind == "gltf_not_converted":
            rule = NOT_CONVERTED if detail["extension"] == slots.SPECULAR_GLOSSINESS else EXTENSION_NOT_CONVERTED
            yield context.diagnostic(
                rule, f"material {detail['material']!r} uses {detail['extension']}, which the toolkit does not convert",
                observation.location, hint="findings and conversions describe the material without it (one directly on the "
                                           "material is kept as data and restored on glTF output)",
            )


def _exclusions(material, context):
    present = set(material.extra.get("gltf", {}).get("material_extensions", ()))
    for exclusive, excluded in ((slots.UNLIT, slots.EXCLUDED_WITH_UNLIT),
                                (slots.SPECULAR_GLOSSINESS, slots.EXCLUDED_WITH_SPECULAR_GLOSSINESS)):
        if exclusive not in present:
            continue
        clash = sorted(present.intersection(excluded))
        if clash:
            yield context.diagnostic(
                EXCLUSIVE_EXTENSIONS, f"{material.name}: {', '.join(clash)} must not be used together with {exclusive}",
                Location(material.location.file, None, f"{material.location.path}/extensions/{exclusive}"),
                hint=f"remove {exclusive} or the other extensions",
            )


def _no_effect(material, context):
    present = set((material.extra.get("gltf") or {}).get("material_extensions") or ())
    value = {name: constant_or_default(material, name) for name in
             ("metallic", "transmission", "thickness", "dispersion", "iridescence", "iridescence_thickness")}
    found = []
    if slots.TRANSMISSION in present and value["metallic"] == 1.0 and value["transmission"] != 0.0:
        found.append((slots.TRANSMISSION, "transmission on a fully metallic material (metallicFactor 1, the default) "
                                          "has no effect"))
    # (a transmission extension at factor 0 is a set-up switched off, as in Khronos' IORTestGrid: not half of
    # one lost in export, and not the validator's KHR_MATERIALS_VOLUME_NO_TRANSMISSION)
    if slots.VOLUME in present and slots.DIFFUSE_TRANSMISSION not in present and slots.TRANSMISSION not in present:
        found.append((slots.VOLUME, "a volume without transmission or diffuse transmission has no effect"))
    if slots.DISPERSION in present and value["dispersion"] != 0.0 and (
            slots.VOLUME not in present or value["thickness"] == 0.0):
        found.append((slots.DISPERSION, "dispersion without a volume (thicknessFactor > 0) has no effect"))
    if slots.VOLUME in present and value["thickness"] != 0.0 and (material.extra.get("gltf") or {}).get("doubleSided") is True:
        # KHR_materials_volume: "The doubleSided property has no effect on volume boundaries" (the validator's
        # KHR_MATERIALS_VOLUME_DOUBLE_SIDED)
        found.append((slots.VOLUME, "doubleSided has no effect on a volume boundary (thicknessFactor > 0)"))
    if slots.IRIDESCENCE in present and value["iridescence"] != 0.0 and value["iridescence_thickness"] == 0.0:
        found.append((slots.IRIDESCENCE, "iridescence with a film of 0 nm has no effect"))
    empty = []
    for extension, parameter in EFFECT_FACTORS:
        if extension in present and not _authors_anything(material, extension):
            factor = slots.SLOT_BY_PARAMETER[parameter].factor
            if extension == slots.TRANSMISSION and slots.VOLUME in present and value["thickness"] != 0.0:
                found.append((extension, f"an empty {extension} object ({factor} defaults to 0) leaves the volume "
                                         "nothing to act through: neither has an effect"))
            else:
                empty.append((extension, f"an empty {extension} object does nothing: {factor} defaults to 0"))
    diffuse = ((material.extra.get("gltf") or {}).get("extensions") or {}).get(slots.DIFFUSE_TRANSMISSION)
    if isinstance(diffuse, dict):
        factor = diffuse.get("diffuseTransmissionFactor")
        if not set(diffuse) - {"extensions", "extras"}:
            empty.append((slots.DIFFUSE_TRANSMISSION, f"an empty {slots.DIFFUSE_TRANSMISSION} object does nothing: "
                                                      "diffuseTransmissionFactor defaults to 0"))
        elif value["metallic"] == 1.0 and isinstance(factor, (int, float)) and factor > 0:
            found.append((slots.DIFFUSE_TRANSMISSION, "diffuse transmission on a fully metallic material (metallicFactor "
                                                      "1, the default) has no effect: a metal has no diffuse lobe"))
    blanket = sum(not _authors_anything(material, name) for name in present) >= 2  # (several written empty)
    if not blanket:  # a lone empty object is a set-up lost in export (a glass whose factor was never written)
        found, empty = found + [(e, why.replace("does nothing", "has no effect")) for e, why in empty], []
    for rule, listed in ((NO_EFFECT, found), (EMPTY_EXTENSION, empty)):
        for extension, why in listed:
            yield context.diagnostic(rule, f"{material.name}: {why}",
                                     Location(material.location.file, None, f"{material.location.path}/extensions/{extension}"))
    for name in ("normal", "clearcoat_normal"):
        entry = material.inputs.get(name)
        if entry is not None and entry.texture is not None and entry.texture.normal_map == 0.0:
            slot = slots.SLOT_BY_PARAMETER[name]
            yield context.diagnostic(NO_EFFECT, f"{material.name}: {slot.texture}.scale 0 flattens the normal map to the "
                                                "vertex normal, so the texture has no effect",
                                     Location(material.location.file, None, entry.texture.node, "scale"),
                                     hint="set scale to 1 (the default), or remove the normal texture")
    if "alpha_cutoff" in material.inputs and constant_or_default(material, "alpha_mode") != 1:  # (the validator's warning)
        yield context.diagnostic(NO_EFFECT, f"{material.name}: alphaCutoff has no effect unless alphaMode is MASK",
                                 material.inputs["alpha_cutoff"].location)


#: Material extensions whose effect a factor carries that defaults to 0 (each README's property table): an empty
#: extension object does nothing. (One that authors other properties but not the factor may be a deliberate 0, as
#: in Khronos' DiffuseTransmissionTest: not reported; a texture without its factor is _texture_factors'.)
EFFECT_FACTORS = ((slots.TRANSMISSION, "transmission"), (slots.CLEARCOAT, "clearcoat"), (slots.SHEEN, "sheen_color"),
                  (slots.IRIDESCENCE, "iridescence"), (slots.ANISOTROPY, "anisotropy_strength"))


def _authors_anything(material, extension: str) -> bool:
    """Whether any input of ``material`` was read from a property of its ``extension`` object (a default the
    reader fills in, iridescenceThicknessMaximum's, names no property)."""
    within = f"{material.location.path}/extensions/{extension}"
    return any(entry.location is not None and entry.location.input is not None
               and (entry.location.path == within or (entry.location.path or "").startswith(within + "/"))
               for entry in material.inputs.values())


def _emissive_strength(material, context):
    strength = material.inputs.get("emissive_strength")
    if strength is None or strength.constant is None or strength.constant == 1.0:
        return
    emissive = material.inputs.get("emissive")
    if emissive is None:
        black = True
    elif isinstance(emissive.value, Texture):
        black = emissive.value.scale is not None and not any(emissive.value.scale)
    else:
        black = emissive.constant is not None and not any(emissive.constant)
    if black:
        yield context.diagnostic(
            STRENGTH_WITHOUT_EMISSIVE,
            f"{material.name}: emissiveStrength {strength.constant:g} multiplies a black emissiveFactor",
            strength.location, hint="set emissiveFactor (e.g. [1, 1, 1]) or remove the extension",
        )


def _texture_factors(material, context):
    """The factors that multiply a texture (the ranges family sees only constants): OPBR301 outside the
    parameter's range; OPBR1211 at 0 where 0 is the factor's default (emissiveTexture without emissiveFactor:
    the texture shows nothing; a 0 beside a packed texture, metallicFactor 0 with the roughness in G, is meant)."""
    table = tables.table(material.model, material.version) if material.version is not None else {}
    for name, texture in material.textures():
        slot = slots.SLOT_BY_PARAMETER.get(name)
        if slot is None or slot.factor is None or texture.scale is None:
            continue
        values = texture.scale if isinstance(texture.scale, tuple) else (texture.scale,)
        where = Location(material.location.file, None, material.inputs[name].location.path, slot.factor)
        if not any(values) and not any(slot.default if isinstance(slot.default, tuple) else (slot.default,)):
            yield context.diagnostic(
                NO_EFFECT, f"{material.name}: {slot.texture} is multiplied by {slot.factor} 0 (its default when "
                           "absent), so it has no effect", where, hint=f"set {slot.factor} (1 lets the texture through as it is)")
        parameter = table.get(name)
        if parameter is None or name == "iridescence_thickness":
            continue
        low, high = parameter.hard_min, parameter.hard_max
        lows = low if isinstance(low, tuple) else (low,) * len(values)
        highs = high if isinstance(high, tuple) else (high,) * len(values)
        if any((lo is not None and v < lo) or (hi is not None and v > hi) for v, lo, hi in zip(values, lows, highs)):
            shown = ", ".join(f"{v:g}" for v in values)
            yield context.diagnostic(
                HARD_RANGE, f"{slot.factor} = {shown} (multiplying {name}'s texture) is outside its valid range "
                            f"[{_fmt(low)}, {_fmt(high)}]", where,
            )


def _fmt(bound) -> str:
    if bound is None:
        return "inf"
    if isinstance(bound, tuple):
        return "(" + ", ".join(f"{b:g}" for b in bound) + ")"
    return f"{bound:g}"


def _texcoords(asset, facts, context):
    by_material: dict[int, list[dict]] = {}  # indexed, so the check stays linear in uses + primitives
    for primitive in facts.get("primitives", ()):
        sets = primitive["texcoords"]
        if sets and sets != list(range(len(sets))):
            gap = next(n for n in range(len(sets) + 1) if n not in sets)
            yield context.diagnostic(
                MISSING_TEXCOORD, f"primitive {primitive['pointer']} has {', '.join(f'TEXCOORD_{n}' for n in sets)} but no "
                f"TEXCOORD_{gap}: UV sets must be numbered from 0 without a gap, or loaders read the sets after it as "
                "others", Location(asset.path, None, f"{primitive['pointer']}/attributes", f"TEXCOORD_{sets[-1]}"),
                hint=f"renumber the UV sets 0 to {len(sets) - 1} (and the textures' texCoord with them)")
        material = primitive["material"]
        if isinstance(material, int) and not isinstance(material, bool):
            by_material.setdefault(material, []).append(primitive)
    if not by_material:
        return
    for use in facts.get("texture_uses", ()):
        lacking = [p["pointer"] for p in by_material.get(use["material"], ()) if use["texcoord"] not in p["texcoords"]]
        if lacking:
            more = f" (and {len(lacking) - 1} more)" if len(lacking) > 1 else ""
            yield context.diagnostic(
                MISSING_TEXCOORD, f"texCoord {use['texcoord']} but primitive {lacking[0]}{more} has no TEXCOORD_{use['texcoord']}",
                Location(asset.path, None, use["pointer"], "texCoord"),
                hint="use a UV set the mesh has, or add the attribute",
            )


def _images(asset, facts, context):
    used = {use["image"] for use in facts.get("texture_uses", ())}
    for image in facts.get("images", ()):
        where = Location(asset.path, None, image["pointer"])
        # The reader never opens an image outside the asset. The textures rule reports the ones
        # materials use (URL, absolute, "..", a symbolic link out); this reports the unused ones.
        if image.get("outside") and image["index"] not in used:
            yield context.diagnostic(UNSAFE_PATH, f"image {image['index']}: {image['outside']}",
                                     Location(asset.path, None, image["pointer"], "uri"),
                                     hint="copy the image next to the asset and use a relative path")
        width, height = image.get("width"), image.get("height")
        if width and height and (width & (width - 1) or height & (height - 1)):
            yield context.diagnostic(NOT_POWER_OF_TWO, f"image {image['index']} is {width} x {height}, not a power of two",
                                     where, hint="resize to a power of two for WebGL 1 and mipmapping")
        found = image.get("damage")
        declared = image.get("declared")
        if found is not None:  # every image, used or not, as the Khronos validator judges them
            yield damage_diagnostic(context, found, f"image {image['index']} ({image['file']})", where, EMBEDDED_REMEDY)
            if declared is None:  # (else a data URI declaring an image type whose bytes are none: an error too)
                continue
        if declared is not None:
            yield context.diagnostic(MIME_MISMATCH, f"image {image['index']} ({image['file']}) is declared "
                                     f"{declared['type']} but its bytes are {declared['found']}",
                                     Location(asset.path, None, image["pointer"], declared["property"]),
                                     hint=f"declare {declared['found']}, or re-encode the image as {declared['type']}"
                                     if found is None else f"re-encode the image as {declared['type']}")
            if found is not None:
                continue
        mime = image.get("detected_mime") or image.get("mime")
        if mime is None or image["index"] not in used:
            continue
        extension = slots.EXTENSION_MIME_TYPES.get(mime)
        allowed = mime in slots.core_mime_types() or (extension and extension in image.get("via_extensions", ()))
        if not allowed and extension:
            yield context.diagnostic(IMAGE_NEEDS_EXTENSION, f"image {image['index']} ({image['file']}) is {mime}, which a "
                                     f"texture's core source may not name (only PNG or JPEG)", where,
                                     hint=f"reference it through {extension} (texture.extensions.{extension}.source), with a "
                                          "PNG or JPEG fallback as the core source")
        elif not allowed:
            yield context.diagnostic(UNSUPPORTED_IMAGE, f"image {image['index']} ({image['file']}) is {mime}, not PNG or JPEG",
                                     where, hint="convert it to PNG" if not extension else f"reference it through {extension}")
