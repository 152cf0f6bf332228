"""glTF structure: accessors laid out as glTF 2.0 requires, and texture extensions naming images of their format.

A material is only as good as the mesh data it is sampled with: texture coordinates that start mid-float,
overlap their neighbours, are substituted at the wrong vertices or run out before the positions do put the
texture in the wrong place, or make the viewer refuse the mesh. The reader's layout facts
(:mod:`openpbr_tools.io.gltf.layout`, which cites the specification clause of each) are judged here, each
finding located at the accessor (or at the primitive's attribute, for counts):

* an accessor offset that is no multiple of its component size, within its bufferView or within the buffer
  (3.6.2.4; the Khronos glTF-Validator's ACCESSOR_OFFSET_ALIGNMENT, ACCESSOR_TOTAL_OFFSET_ALIGNMENT);
* a bufferView ``byteStride`` smaller than an element of an accessor using it (ACCESSOR_SMALL_BYTESTRIDE), not a
  multiple of 4 or outside 4 to 252 (bufferView.schema.json; VALUE_MULTIPLE_OF, VALUE_NOT_IN_RANGE), or larger than
  the view (BUFFER_VIEW_TOO_BIG_BYTE_STRIDE); a vertex attribute whose offset or packed element size is no multiple
  of 4 (3.6.2.4; MESH_PRIMITIVE_ACCESSOR_UNALIGNED);
* sparse indices that do not strictly increase, or reach the accessor's count (3.6.2.3;
  ACCESSOR_SPARSE_INDICES_NON_INCREASING, ACCESSOR_SPARSE_INDEX_OOB);
* an accessor that does not fit its bufferView (3.6.2.4; ACCESSOR_TOO_LONG);
* attributes (and morph targets) of one primitive with different counts (3.7.2.1;
  MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT), and indices that reach the vertex count (3.7.2.1; ACCESSOR_INDEX_OOB).

The values the primitives of the file's materials are drawn with (OPBR1231): no NaN or infinity in a float
(3.6.2.2; ACCESSOR_INVALID_FLOAT), NORMAL and TANGENT xyz of unit length (3.7.2.1; ACCESSOR_VECTOR3_NON_UNIT).
Only the accessors of such primitives are read, each once and at most :data:`~..io.gltf.accessors.MAX_ELEMENTS`
elements of it (:mod:`openpbr_tools.io.gltf.accessors`).

And the document as a whole: a texture whose only image comes through EXT_texture_webp or KHR_texture_basisu
while the extension is not required (OPBR1229), and a property name written twice in one JSON object (OPBR1230).

Also, as OPBR1220 (the core source's counterpart, in the glTF family): a texture extension's ``source`` that
names an image of another format (EXT_texture_webp's a PNG; the validator's TEXTURE_INVALID_IMAGE_MIME_TYPE), or
KHR_texture_basisu's a file declared KTX2 that holds no Basis Universal payload (a legacy ``.basis`` file, a KTX2 of
raw texels: the reader's ``not_basis_universal``, from the file's header).
A GLB chunk that is neither JSON nor BIN, a BIN chunk longer than buffer 0 and its padding, and a data URI inside a
GLB are OPBR1237 (waste, a warning; from the reader's layout facts). Buffers shorter than their byteLength, data URIs
of another media type, unaligned GLB chunks and a second JSON or BIN chunk are OPBR1209, a
``scene`` naming no scene OPBR802.
"""

from __future__ import annotations

import base64
import json
import struct

from ..diagnostics import Severity
from ..io.gltf.accessors import UNIT_TOLERANCE
from ..io.gltf.layout import STRIDE_RANGE
from ..model import Location
from . import Rule
from .gltf import _PNG_4X4, _WEBP, IMAGE_NEEDS_EXTENSION, _gltf


def _counted(texcoords: int) -> str:
    return _gltf(
        '"materials": [{"name": "M"}]',
        '"accessors": [{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}, '
        f'{{"componentType": 5126, "count": {texcoords}, "type": "VEC2"}}]',
        '"meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}]',
    )


ACCESSOR_STRUCTURE = Rule(
    "OPBR1228", "gltf-accessor-structure", Severity.ERROR,
    "An accessor is laid out as glTF forbids: an offset that is no multiple of its component size, a bufferView "
    "byteStride smaller than its element, not a multiple of 4, outside 4-252 or longer than the view, a vertex "
    "attribute not aligned to 4 bytes, more elements than its bufferView holds, sparse indices that do not "
    "strictly increase or reach its count; or the attributes of one primitive have different counts, or its "
    "indices reach its vertex count.",
    "glTF 2.0 requires accessor offsets (into the bufferView and into the buffer) to be multiples of the "
    "component size (3.6.2.4), a stride to hold a whole element, a vertex attribute's offset and stride to be "
    "multiples of 4 (3.6.2.4: \"accessor.byteOffset and bufferView.byteStride MUST be multiples of 4\"; "
    "bufferView.schema.json: byteStride minimum 4, maximum 252, multipleOf 4), sparse indices to \"strictly increase\" and to "
    "stay below the accessor's count (3.6.2.3), and \"all attribute accessors for a given primitive\" to \"have "
    "the same count\" (3.7.2.1). Otherwise GPU APIs refuse the unaligned vertex buffer (WebGL: "
    "INVALID_OPERATION), elements overlap (a UV read from the middle of a position), sparse substitutions land "
    "on the wrong vertices (or past the end), and vertices past the shorter attribute have no UVs: the texture "
    "is misplaced or the mesh is not drawn. The Khronos glTF-Validator reports each as an error "
    "(ACCESSOR_OFFSET_ALIGNMENT, ACCESSOR_TOTAL_OFFSET_ALIGNMENT, ACCESSOR_SMALL_BYTESTRIDE, VALUE_MULTIPLE_OF "
    "and VALUE_NOT_IN_RANGE at byteStride, BUFFER_VIEW_TOO_BIG_BYTE_STRIDE, MESH_PRIMITIVE_ACCESSOR_UNALIGNED, "
    "ACCESSOR_SPARSE_INDICES_NON_INCREASING, ACCESSOR_SPARSE_INDEX_OOB, MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT). "
    "Likewise an accessor that does not fit its bufferView (\"each accessor MUST fit its bufferView\", 3.6.2.4: "
    "the last elements are read from the next view or past the buffer; ACCESSOR_TOO_LONG), and a primitive's "
    "indices that reach its vertex count (\"all index values MUST be less than attribute accessors' count\", "
    "3.7.2.1: WebGL refuses the draw, other APIs read undefined vertices; ACCESSOR_INDEX_OOB). "
    "Up to about four million sparse indices or indices of an accessor are read, the indices only of primitives "
    "with a material.",
    passing=_counted(3), failing=_counted(2),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)


def _webp_only(required: bool) -> str:
    return _gltf('"extensionsUsed": ["EXT_texture_webp"]', *(('"extensionsRequired": ["EXT_texture_webp"]',) if required else ()),
                 f'"images": [{{"uri": "{_WEBP}"}}]', '"textures": [{"extensions": {"EXT_texture_webp": {"source": 0}}}]',
                 '"materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]')


EXTENSION_WITHOUT_FALLBACK = Rule(
    "OPBR1229", "gltf-texture-extension-not-required", Severity.WARNING,
    "A texture's only image comes through EXT_texture_webp or KHR_texture_basisu (no core source to fall back on), "
    "but the extension is not in extensionsRequired.",
    "Both extensions' READMEs, \"Using Without a Fallback\": to use their images without a PNG or JPEG fallback, the "
    "extension \"must be present in both extensionsUsed and extensionsRequired\". Listed as optional, a viewer "
    "without WebP (or KTX2) support loads the asset anyway and renders the material without the texture (a plain "
    "base colour) instead of refusing it. The Khronos glTF-Validator does not check this. Require the extension, or "
    "give the texture a PNG or JPEG core source.",
    passing=_webp_only(True), failing=_webp_only(False),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

_MATERIAL = '{"name": "M", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1.0]}'
NAME_REPEATED = Rule(
    "OPBR1230", "gltf-json-name-repeated", Severity.WARNING,
    "A JSON object names one property twice (two pbrMetallicRoughness in one material).",
    "glTF 2.0, JSON Encoding: property names \"SHOULD be unique\" and clients \"SHOULD override lexically preceding "
    "values for the same key\"; RFC 8259 says of such objects that \"the behavior of software that receives [them] is "
    "unpredictable\". JavaScript and Python parsers keep the last value (as the toolkit and the Khronos "
    "glTF-Validator, which says nothing), streaming and first-match parsers the first: the same material renders "
    "differently from one viewer to the next. Usually a merge or hand edit; keep the one meant.",
    passing=_gltf(f'"materials": [{_MATERIAL}}}]'),
    failing=_gltf(f'"materials": [{_MATERIAL}, "pbrMetallicRoughness": {{"metallicFactor": 0.0}}}}]'),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)


def _triangle_uvs(v: float) -> str:
    """A triangle (positions, then texture coordinates with one ``u`` of ``v``) in one data-URI buffer."""
    data = struct.pack("<9f6f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, v)
    uri = "data:application/octet-stream;base64," + base64.b64encode(data).decode("ascii")
    return _gltf(
        f'"buffers": [{{"byteLength": 60, "uri": "{uri}"}}]',
        '"bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24}]',
        '"accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], '
        '"max": [1, 1, 0]}, {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}]',
        '"materials": [{"name": "M"}]',
        '"meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}]',
    )


VERTEX_VALUES = Rule(
    "OPBR1231", "gltf-vertex-values-invalid", Severity.ERROR,
    "A vertex attribute of a primitive with a material holds values glTF forbids: a NaN or infinite float, a "
    "NORMAL (a TANGENT's xyz) that is not of unit length, or a float COLOR_n outside [0, 1].",
    "glTF 2.0: float accessor values \"of NaN, +Infinity, and -Infinity MUST NOT be present\" (3.6.2.2), and NORMAL "
    "is a \"normalized\" vector, TANGENT's xyz \"normalized\" (3.7.2.1). A NaN texture coordinate samples garbage or "
    "black (a degenerate unwrap), a NaN normal or position drops or blackens the triangles; a normal of length 2.5 "
    "(an object scale baked into the normals) brightens or darkens the lighting by that factor in viewers that do "
    "not renormalise, and tilts a normal map's basis. The Khronos glTF-Validator reports both as errors "
    f"(ACCESSOR_INVALID_FLOAT, ACCESSOR_VECTOR3_NON_UNIT, with its tolerance: |length - 1| > {UNIT_TOLERANCE:g}). "
    "COLOR_n multiplies the base colour (3.7.2.1), and the validator calls a float colour outside [0, 1] an error "
    "(ACCESSOR_NON_CLAMPED): the albedo exceeds 1 there. "
    "Only POSITION, NORMAL, TANGENT, TEXCOORD_n and COLOR_n accessors of primitives with a material are read, each "
    "once and its first four million or so elements; a TANGENT's w is OPBR1227.",
    passing=_triangle_uvs(1.0), failing=_triangle_uvs(float("nan")),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)


def _glb_with_data_uri(data_uri: bool) -> bytes:
    """A GLB whose PNG is a data URI, or in the BIN chunk through a bufferView."""
    png = base64.b64decode(_PNG_4X4.split(",", 1)[1])
    png += bytes(-len(png) % 4)
    document = {"asset": {"version": "2.0"}, "textures": [{"source": 0}],
                "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]}
    if data_uri:
        document["images"] = [{"uri": _PNG_4X4}]
    else:
        document.update({"buffers": [{"byteLength": len(png)}], "bufferViews": [{"buffer": 0, "byteLength": len(png)}],
                         "images": [{"bufferView": 0, "mimeType": "image/png"}]})
    text = json.dumps(document).encode("utf-8")
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
    if not data_uri:
        chunks += struct.pack("<II", len(png), 0x004E4942) + png
    return b"glTF" + struct.pack("<II", 2, 12 + len(chunks)) + chunks


GLB_CONTAINER = Rule(
    "OPBR1237", "gltf-glb-container-waste", Severity.WARNING,
    "A GLB holds what its container does not need: a chunk that is neither JSON nor BIN, a BIN chunk longer than "
    "buffer 0 and its padding, bytes after the length the GLB's header declares, or a buffer or image as a data URI.",
    "glTF 2.0, 4.4.3: a GLB has one JSON chunk and an optional BIN chunk, whose length may exceed buffer 0's byteLength "
    "only by the padding to 4 bytes; clients \"MUST ignore chunks with unknown types\" (4.4.3.1), and a GLB exists to "
    "carry resources as bytes, not as base64 text a third larger that the loader must decode. Nothing renders wrong, "
    "but the bytes are dead weight or the file was assembled by a tool that lost track of its buffer (a byteLength "
    "shrunk without the chunk). Loaders read a GLB up to the length in its header, so bytes after it are never read "
    "(the file is read as they read it). The Khronos glTF-Validator warns (GLB_UNKNOWN_CHUNK_TYPE, "
    "BUFFER_GLB_CHUNK_TOO_BIG, DATA_URI_GLB, GLB_EXTRA_DATA). A second JSON or BIN chunk is OPBR1209.",
    passing=_glb_with_data_uri(False), failing=_glb_with_data_uri(True),
    passing_name="example.glb", failing_name="example.glb", formats=("gltf",),
)

RULES = (ACCESSOR_STRUCTURE, EXTENSION_WITHOUT_FALLBACK, NAME_REPEATED, VERTEX_VALUES, GLB_CONTAINER)


def _offset_alignment(p):
    return (f"byteOffset {p['offset']} is not a multiple of the component size ({p['size']} bytes)",
            f"move the data to an offset that is a multiple of {p['size']}")


def _total_offset_alignment(p):
    return (f"byteOffset {p['offset']} plus bufferView {p['view']}'s byteOffset {p['view_offset']} is not a multiple "
            f"of the component size ({p['size']} bytes): the data starts unaligned in the buffer",
            f"align bufferView {p['view']} (or the accessor) to a multiple of {p['size']} bytes")


def _small_stride(p):
    return (f"bufferView {p['view']} has byteStride {p['stride']}, smaller than one {p['type']} element "
            f"({p['element']} bytes): consecutive elements overlap",
            f"set byteStride to at least {p['element']} (the size of one interleaved vertex)")


def _stride_not_multiple(p):
    return (f"byteStride {p['stride']} is not a multiple of 4: every other vertex's values start off a 4-byte "
            "boundary, which WebGL and GPU vertex fetch refuse (or read as garbage floats)",
            f"pad each interleaved vertex to {p['stride'] + (-p['stride'] % 4)} bytes")


def _stride_out_of_range(p):
    return (f"byteStride {p['stride']} is outside the {STRIDE_RANGE[0]} to {STRIDE_RANGE[1]} bytes glTF allows" +
            (" (WebGL accepts no stride above 255)" if p["stride"] > STRIDE_RANGE[1] else "") +
            ": loaders that check the schema refuse the file, others read the view as tightly packed",
            "split the interleaved attributes over more bufferViews" if p["stride"] > STRIDE_RANGE[1]
            else "set byteStride to the size of one interleaved vertex (a multiple of 4), or remove it")


def _stride_too_big(p):
    return (f"byteStride {p['stride']} is larger than the bufferView's byteLength {p['length']}: not even two "
            "elements fit in it", "set byteStride to the size of one interleaved vertex, or byteLength to the data's")


def _vertex_unaligned(p):
    attribute, primitive = p["attribute"].rsplit("/", 1)[-1], p["attribute"].rsplit("/", 2)[0]
    why = (f"its byteOffset is {p['offset']}" if p["offset"] % 4 else
           f"its {p['type']} elements are packed {p['packed']} bytes apart (bufferView {p['view']} has no byteStride)")
    return (f"{primitive} reads it as {attribute}, a vertex attribute, whose offset and stride must be multiples of 4, "
            f"but {why}: GPU APIs refuse the unaligned vertex buffer",
            "pad each element to a multiple of 4 bytes (a byteStride on the bufferView) and start the accessor at a "
            "multiple of 4")


def _sparse_not_increasing(p):
    return (f"sparse index {p['position']} is {p['value']}, not greater than the one before it ({p['previous']}): the "
            "indices must strictly increase, or the substituted values land on the wrong vertices",
            "sort the sparse indices together with their values")


def _sparse_out_of_range(p):
    return (f"sparse index {p['position']} is {p['value']}, but the accessor has only {p['count']} elements "
            f"(0 to {p['count'] - 1})", "drop the index or fix the accessor's count")


def _sparse_count_zero(p):
    return ("a sparse accessor substitutes 0 values: its count must be at least 1 (the schema's minimum; the Khronos "
            "glTF-Validator's VALUE_NOT_IN_RANGE)", "remove the sparse object, or give it the values it substitutes")


def _sparse_index_type(p):
    return (f"the sparse indices' componentType is {p['value']}: indices are unsigned integers, 5121 (UNSIGNED_BYTE), "
            "5123 (UNSIGNED_SHORT) or 5125 (UNSIGNED_INT), so no reader knows which elements are substituted",
            "write the indices as unsigned integers, with the componentType that names their size")


def _unequal_count(p):
    return (f"{p['property']} has {p['count']} elements but {p['reference']} has {p['expected']}: every attribute of "
            "a primitive needs one element per vertex", f"export {p['property']} with {p['expected']} elements, "
            "from the same mesh as the other attributes")


def _too_long(p):
    return (f"byteOffset {p['offset']} plus {p['count']} elements ({p['length']} bytes) does not fit bufferView "
            f"{p['view']}, {p['view_length']} bytes long: the last elements are read past the view's end",
            f"give the accessor the count its data has, or bufferView {p['view']} the byteLength its accessors need")


def _index_out_of_range(p):
    return (f"indices (accessor {p['accessor']}) hold {p['count']} of {p['checked']} values not below the vertex count "
            f"{p['vertices']} (first: {p['value']} at index {p['first']}): those triangles name vertices that do not "
            "exist", "re-export the mesh (indices from another level of detail, or vertices lost in a merge?)")


def _non_finite(p):
    return (f"{p['count']} of {p['checked']} elements hold a value that is not a finite number (first: element "
            f"{p['first']}, {p['value']:g}; read as {p['attribute']}): glTF forbids NaN and infinity in an accessor",
            "re-export the mesh; a NaN texture coordinate is usually a degenerate UV unwrap")


def _non_unit(p):
    return (f"{p['count']} of {p['checked']} vectors of accessor {p['accessor']} are not of unit length (first: "
            f"element {p['first']}, length {p['length']:.4g}): lighting and normal maps are scaled or tilted there",
            "normalise the vectors (an object scale baked into them?)")


def _non_clamped(p):
    effect = ("COLOR_0 multiplies the base colour, which then exceeds 1 (or goes negative)" if p["attribute"] == "COLOR_0"
              else f"glTF requires {p['attribute']} in [0, 1]")
    return (f"{p['count']} of {p['checked']} colours of accessor {p['accessor']} lie outside [0, 1] (first: element "
            f"{p['first']}, {', '.join(f'{v:g}' for v in p['value'])}): {effect}",
            "clamp the vertex colours to [0, 1] (HDR colours baked into them?)")


_MESSAGES = {"stride_not_multiple": _stride_not_multiple, "stride_out_of_range": _stride_out_of_range,
             "stride_too_big": _stride_too_big, "vertex_unaligned": _vertex_unaligned,
             "offset_alignment": _offset_alignment, "total_offset_alignment": _total_offset_alignment,
             "small_stride": _small_stride, "too_long": _too_long, "sparse_not_increasing": _sparse_not_increasing,
             "sparse_out_of_range": _sparse_out_of_range, "sparse_count_zero": _sparse_count_zero,
             "sparse_index_type": _sparse_index_type, "unequal_count": _unequal_count,
             "index_out_of_range": _index_out_of_range, "non_finite": _non_finite, "non_unit": _non_unit,
             "non_clamped": _non_clamped}
_VALUE_KINDS = ("non_finite", "non_unit", "non_clamped")


def check(asset, context):
    """Runs on glTF assets only (rules.FAMILY_FORMATS)."""
    facts = asset.extra.get("gltf", {})
    for problem in facts.get("accessor_problems", ()):
        message, hint = _MESSAGES[problem["kind"]](problem)
        pointer = problem["pointer"]
        if pointer.startswith("/meshes/"):
            where = f"primitive {pointer.removesuffix('/attributes')}"
        elif pointer.startswith("/bufferViews/"):
            where = f"bufferView {pointer.split('/')[2]}"
        else:
            where = f"accessor {pointer.split('/')[2]}" + (" (sparse)" if pointer.endswith("/sparse") else "")
        rule = VERTEX_VALUES if problem["kind"] in _VALUE_KINDS else ACCESSOR_STRUCTURE
        yield context.diagnostic(rule, f"{where}: {message}",
                                 Location(asset.path, None, problem["pointer"], problem["property"]), hint=hint)
    yield from _fallbacks(asset, facts, context)
    for observation in asset.observations:
        if observation.kind == "gltf_container":
            yield context.diagnostic(GLB_CONTAINER, observation.detail["message"], observation.location)
    for pointer, times in facts.get("repeated_names", ()):
        name = pointer.rsplit("/", 1)[-1].replace("~1", "/").replace("~0", "~")
        yield context.diagnostic(
            NAME_REPEATED, f"{name!r} is written {times} times in {pointer.rsplit('/', 1)[0] or 'the root'}: parsers that "
            "keep the last value (this toolkit, browsers) and those that keep the first read the file differently",
            Location(asset.path, None, pointer), hint=f"keep one {name!r} (the toolkit read the last one)")
    yield from _extension_sources(asset, facts, context)


def _fallbacks(asset, facts, context):
    """One finding per texture extension that some texture needs (no core source) and that is declared used but not
    required (one not declared at all is OPBR1201's)."""
    used, required = set(facts.get("extensions_used", ())), set(facts.get("extensions_required", ()))
    alone: dict[str, list[str]] = {}
    for source in facts.get("extension_sources", ()):
        if not source["fallback"] and source["extension"] in used and source["extension"] not in required:
            alone.setdefault(source["extension"], []).append(source["pointer"])
    for extension, pointers in alone.items():
        more = f" (and {len(pointers) - 1} more texture{'s' if len(pointers) > 2 else ''})" if len(pointers) > 1 else ""
        yield context.diagnostic(
            EXTENSION_WITHOUT_FALLBACK, f"texture {pointers[0].split('/')[2]}{more} has no core source, only "
            f"{extension}'s, but {extension} is not in extensionsRequired: a viewer without it loads the asset and "
            "renders the material untextured", Location(asset.path, None, pointers[0]),
            hint=f'add "{extension}" to extensionsRequired, or give the texture a PNG or JPEG source as a fallback')


def _extension_sources(asset, facts, context):
    images = facts.get("images", ())
    for source in facts.get("extension_sources", ()):
        image = images[source["image"]] if source["image"] < len(images) else {}
        found = image.get("detected_mime") or image.get("mime")
        if found == source["mime"] and image.get("not_basis_universal") and image.get("damage") is None:
            yield context.diagnostic(
                IMAGE_NEEDS_EXTENSION, f"{source['extension']}'s source is image {source['image']} ({image.get('file')}), "
                f"but {image['not_basis_universal']}: the extension requires a KTX v2 file with Basis Universal "
                "supercompression (ETC1S/BasisLZ or UASTC), and viewers that support it fail to transcode this one",
                Location(asset.path, None, source["pointer"], "source"),
                hint="encode the texture as Basis Universal KTX2 (toktx --encode etc1s or uastc; basisu -ktx2)")
            continue
        if found is None or found == source["mime"] or image.get("damage") is not None:
            continue
        yield context.diagnostic(
            IMAGE_NEEDS_EXTENSION, f"{source['extension']}'s source is image {source['image']} ({image.get('file')}), "
            f"which is {found}, not {source['mime']}: viewers that support {source['extension']} fail to decode it",
            Location(asset.path, None, source["pointer"], "source"),
            hint=f"convert the image to {source['mime']} (keep the PNG or JPEG as the texture's core source), or remove "
                 f"{source['extension']} from the texture")
