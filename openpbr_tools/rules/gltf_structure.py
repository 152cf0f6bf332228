"""glTF structure: accessors laid out as glTF 2.0 requires, and texture extensions naming images of their format.

A material is only as good as the mesh data it is sampled with: texture coordinates that start mid-float,
overlap their neighbours, are substituted at the wrong vertices or run out before the positions do put the
texture in the wrong place, or make the viewer refuse the mesh. The reader's layout facts
(:mod:`openpbr_tools.io.gltf.layout`, which cites the specification clause of each) are judged here, each
finding located at the accessor (or at the primitive's attribute, for counts):

* an accessor offset that is no multiple of its component size, within its bufferView or within the buffer
  (3.6.2.4; the Khronos glTF-Validator's ACCESSOR_OFFSET_ALIGNMENT, ACCESSOR_TOTAL_OFFSET_ALIGNMENT);
* a bufferView ``byteStride`` smaller than an element of an accessor using it (ACCESSOR_SMALL_BYTESTRIDE);
* sparse indices that do not strictly increase, or reach the accessor's count (3.6.2.3;
  ACCESSOR_SPARSE_INDICES_NON_INCREASING, ACCESSOR_SPARSE_INDEX_OOB);
* attributes (and morph targets) of one primitive with different counts (3.7.2.1;
  MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT).

Also, as OPBR1220 (the core source's counterpart, in the glTF family): a texture extension's ``source`` that
names an image of another format (EXT_texture_webp's a PNG; the validator's TEXTURE_INVALID_IMAGE_MIME_TYPE).
Buffers shorter than their byteLength and unaligned GLB chunks are OPBR1209, a ``scene`` naming no scene OPBR802.
"""

from __future__ import annotations

from ..diagnostics import Severity
from ..model import Location
from . import Rule
from .gltf import IMAGE_NEEDS_EXTENSION, _gltf


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
    "byteStride smaller than its element, sparse indices that do not strictly increase or reach its count; or "
    "the attributes of one primitive have different counts.",
    "glTF 2.0 requires accessor offsets (into the bufferView and into the buffer) to be multiples of the "
    "component size (3.6.2.4), a stride to hold a whole element, sparse indices to \"strictly increase\" and to "
    "stay below the accessor's count (3.6.2.3), and \"all attribute accessors for a given primitive\" to \"have "
    "the same count\" (3.7.2.1). Otherwise GPU APIs refuse the unaligned vertex buffer (WebGL: "
    "INVALID_OPERATION), elements overlap (a UV read from the middle of a position), sparse substitutions land "
    "on the wrong vertices (or past the end), and vertices past the shorter attribute have no UVs: the texture "
    "is misplaced or the mesh is not drawn. The Khronos glTF-Validator reports each as an error "
    "(ACCESSOR_OFFSET_ALIGNMENT, ACCESSOR_TOTAL_OFFSET_ALIGNMENT, ACCESSOR_SMALL_BYTESTRIDE, "
    "ACCESSOR_SPARSE_INDICES_NON_INCREASING, ACCESSOR_SPARSE_INDEX_OOB, MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT). "
    "Up to about four million sparse indices of an accessor are read.",
    passing=_counted(3), failing=_counted(2),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

RULES = (ACCESSOR_STRUCTURE,)


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


def _sparse_not_increasing(p):
    return (f"sparse index {p['position']} is {p['value']}, not greater than the one before it ({p['previous']}): the "
            "indices must strictly increase, or the substituted values land on the wrong vertices",
            "sort the sparse indices together with their values")


def _sparse_out_of_range(p):
    return (f"sparse index {p['position']} is {p['value']}, but the accessor has only {p['count']} elements "
            f"(0 to {p['count'] - 1})", "drop the index or fix the accessor's count")


def _unequal_count(p):
    return (f"{p['property']} has {p['count']} elements but {p['reference']} has {p['expected']}: every attribute of "
            "a primitive needs one element per vertex", f"export {p['property']} with {p['expected']} elements, "
            "from the same mesh as the other attributes")


_MESSAGES = {"offset_alignment": _offset_alignment, "total_offset_alignment": _total_offset_alignment,
             "small_stride": _small_stride, "sparse_not_increasing": _sparse_not_increasing,
             "sparse_out_of_range": _sparse_out_of_range, "unequal_count": _unequal_count}


def check(asset, context):
    """Runs on glTF assets only (rules.FAMILY_FORMATS)."""
    facts = asset.extra.get("gltf", {})
    for problem in facts.get("accessor_problems", ()):
        message, hint = _MESSAGES[problem["kind"]](problem)
        pointer = problem["pointer"]
        where = f"primitive {pointer.rsplit('/', 1)[0]}" if problem["kind"] == "unequal_count" else \
            f"accessor {pointer.split('/')[2]}" + (" (sparse)" if pointer.endswith("/sparse") else "")
        yield context.diagnostic(ACCESSOR_STRUCTURE, f"{where}: {message}",
                                 Location(asset.path, None, problem["pointer"], problem["property"]), hint=hint)
    images = facts.get("images", ())
    for source in facts.get("extension_sources", ()):
        image = images[source["image"]] if source["image"] < len(images) else {}
        found = image.get("detected_mime") or image.get("mime")
        if found is None or found == source["mime"] or image.get("damage") is not None:
            continue
        yield context.diagnostic(
            IMAGE_NEEDS_EXTENSION, f"{source['extension']}'s source is image {source['image']} ({image.get('file')}), "
            f"which is {found}, not {source['mime']}: viewers that support {source['extension']} fail to decode it",
            Location(asset.path, None, source["pointer"], "source"),
            hint=f"convert the image to {source['mime']} (keep the PNG or JPEG as the texture's core source), or remove "
                 f"{source['extension']} from the texture")
