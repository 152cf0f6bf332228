"""The glTF binary layout: whether buffers provide their bytes, a GLB's chunks are aligned, accessors lie in
their buffer views as the specification requires, and the document's top-level references name something.

Each check is one the Khronos glTF-Validator makes (its code in brackets), read from glTF 2.0:

* 3.6.1 Buffers: ``byteLength`` is the buffer's length, so the resource must hold that many bytes; a data URI
  that does not decode, a file that is missing or shorter, or a GLB binary chunk shorter than buffer 0
  leaves the data at its end (vertices, UVs, indices) undefined [BUFFER_BYTE_LENGTH_MISMATCH, IO_ERROR]; a buffer's
  data URI "MUST" declare ``application/octet-stream`` or ``application/gltf-buffer`` [BUFFER_DATA_URI_MIME_TYPE_INVALID];
* 4.4.3 GLB chunks: "The start and the end of each chunk MUST be aligned to a 4-byte boundary", so every
  chunk length is a multiple of 4 (the JSON chunk padded with spaces) [GLB_CHUNK_LENGTH_UNALIGNED];
* 3.6.2.4 Data Alignment: "The offset of an accessor into a bufferView (i.e., accessor.byteOffset) and the
  offset of an accessor into a buffer (i.e., accessor.byteOffset + bufferView.byteOffset) MUST be a multiple
  of the size of the accessor's component type" [ACCESSOR_OFFSET_ALIGNMENT, ACCESSOR_TOTAL_OFFSET_ALIGNMENT],
  and a view's ``byteStride`` is at least an element's size, or elements overlap [ACCESSOR_SMALL_BYTESTRIDE];
  for vertex attributes "accessor.byteOffset and bufferView.byteStride MUST be multiples of 4" (the same clause),
  which bufferView.schema.json states for every stride (``multipleOf`` 4, ``minimum`` 4, ``maximum`` 252)
  [VALUE_MULTIPLE_OF, VALUE_NOT_IN_RANGE, MESH_PRIMITIVE_ACCESSOR_UNALIGNED]; a stride is at most the view's
  ``byteLength`` [BUFFER_VIEW_TOO_BIG_BYTE_STRIDE];
* 3.6.2.4 too: "Each accessor MUST fit its bufferView", ``byteOffset + stride * (count - 1) + element size`` at most
  the view's ``byteLength`` [ACCESSOR_TOO_LONG];
* 3.6.2.3 Sparse Accessors: the indices "MUST strictly increase" and each is less than the accessor's
  ``count`` [ACCESSOR_SPARSE_INDICES_NON_INCREASING, ACCESSOR_SPARSE_INDEX_OOB];
* 3.7.2.1: "All attribute accessors for a given primitive MUST have the same count", morph targets' too
  [MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT, MESH_PRIMITIVE_MORPH_TARGET_INVALID_ATTRIBUTE_COUNT];
* the document's ``scene`` names one of its ``scenes`` [UNRESOLVED_REFERENCE];
* a mesh primitive's KHR_draco_mesh_compression object has the ``bufferView`` and ``attributes`` its schema
  requires (the validator does not look into it).

Only the JSON and file sizes are read, except a sparse accessor's indices (at most
:data:`~.accessors.MAX_ELEMENTS` of them, one NumPy view of the buffer). Malformed values (a string for an
offset, an accessor that does not exist) are left to the schema checks: nothing here guesses.
"""

from __future__ import annotations

import os
from typing import Iterator

from . import slots
from .accessors import MAX_ELEMENTS
from .document import GLB_BIN, GLB_JSON, GltfDocument, ResourceError, data_uri_mime, vertex_attributes
from .schema import uri_syntax_error
from .textures import json_index, json_text

COMPONENT_SIZES = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
VECTOR_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}  # (matrices pad their columns: not judged here)
_INDEX_DTYPES = {5121: "u1", 5123: "<u2", 5125: "<u4"}  # sparse indices (3.6.2.3)
_CHUNK_NAMES = {GLB_JSON: "JSON", GLB_BIN: "BIN"}
BUFFER_MEDIA_TYPES = ("application/octet-stream", "application/gltf-buffer")  # a buffer's data URI (3.6.1)
MESHOPT = "EXT_meshopt_compression"


def buffer_problems(document: GltfDocument) -> Iterator[tuple[str, str, str, str | None]]:
    """``(observation kind, JSON pointer, message, property)`` for every buffer that cannot provide its
    ``byteLength`` bytes and every GLB chunk that is not 4-byte aligned; kind ``gltf_resource`` (a broken
    resource) or ``gltf_invalid`` (a uri that is no string). Files are measured, not read."""
    yield from _glb_chunks(document)
    for index, buffer in enumerate(document.array("buffers")):
        uri = buffer.get("uri") if isinstance(buffer, dict) else None
        length = buffer.get("byteLength") if isinstance(buffer, dict) else None
        pointer = f"/buffers/{index}"
        if isinstance(uri, str) and uri.startswith("data:"):
            try:
                document.buffer(index)
            except ResourceError as error:
                yield "gltf_resource", error.pointer, error.message, None
            media_type = data_uri_mime(uri)
            if media_type not in BUFFER_MEDIA_TYPES:
                yield ("gltf_resource", pointer + "/uri", f"the buffer's data URI declares {json_text(media_type or '')}, "
                       f"not {' or '.join(BUFFER_MEDIA_TYPES)}: loaders that check the media type refuse the buffer", None)
        elif isinstance(uri, str):
            syntax = uri_syntax_error(uri)
            if syntax is not None:
                yield "gltf_invalid", pointer, f"uri {json_text(uri)} is no valid URI: {syntax}", "uri"
            try:
                local = document.resolve(uri, pointer + "/uri")
            except ResourceError as error:
                # one outside the asset is never opened: not broken, but its meshes (and images) go unchecked
                yield ("gltf_buffer_outside" if error.outside else "gltf_resource"), error.pointer, error.message, None
                continue
            if not os.path.isfile(local):
                missing = document.missing(uri, pointer + "/uri")
                yield "gltf_resource", missing.pointer, missing.message, None
            elif json_index(length) and os.path.getsize(local) < length:
                yield ("gltf_resource", pointer, f"file {json_text(uri)} holds {os.path.getsize(local)} bytes, fewer than "
                       f"the buffer's byteLength {length}: the data at its end is missing (a truncated copy?)", None)
        elif uri is not None:
            yield "gltf_invalid", pointer, f"uri must be a string, not {json_text(uri)}", "uri"
        elif _meshopt_fallback(document, buffer):
            continue  # a placeholder: loaders that support the required extension read the compressed views instead
        elif not (document.is_glb and index == 0 and document.binary is not None):
            if index in _read_buffers(document):  # (an unread placeholder, as in Khronos' valid_placeholder.glb, is fine)
                yield "gltf_resource", pointer, "buffer has no uri and there is no GLB binary chunk", None
        elif json_index(length) and len(document.binary) < length:
            yield ("gltf_resource", pointer, f"the GLB binary chunk holds {len(document.binary)} bytes, fewer than the "
                   f"buffer's byteLength {length}: the data at its end is missing", None)
    for index, view in enumerate(document.array("bufferViews")):  # (3.6.1.1; the validator's BUFFER_VIEW_TOO_LONG)
        buffer = document.item("buffers", view.get("buffer")) if isinstance(view, dict) else None
        offset, size = (view.get("byteOffset", 0), view.get("byteLength")) if isinstance(view, dict) else (None, None)
        total = buffer.get("byteLength") if isinstance(buffer, dict) else None
        if json_index(offset) and json_index(size) and json_index(total) and offset + size > total:
            yield "gltf_resource", f"/bufferViews/{index}", f"bufferView {index} lies outside its buffer", None
            # (the words document.buffer_view says when a reader loads it: the finding is made once)


def _read_buffers(document: GltfDocument) -> set[int]:
    """The buffers something reads: those of the bufferViews an accessor, an image or an extension (any
    ``bufferView`` property in the JSON) names."""
    views: set[int] = set()
    stack = [document.json]
    while stack:
        item = stack.pop()
        if isinstance(item, dict):
            view = item.get("bufferView")
            if json_index(view):
                views.add(int(view))
            stack.extend(item.values())
        elif isinstance(item, list):
            stack.extend(item)
    found = set()
    for index, view in enumerate(document.array("bufferViews")):
        if index in views and isinstance(view, dict) and json_index(view.get("buffer")):
            found.add(int(view["buffer"]))
    return found


def _meshopt_fallback(document: GltfDocument, buffer) -> bool:
    """A buffer EXT_meshopt_compression marks as a fallback (``fallback: true``) in a file that requires the
    extension: its README lets it have no uri ("the referenced buffer can contain no URI"), as a loader that
    supports the extension never reads it and one that does not refuses the file."""
    extensions = buffer.get("extensions") if isinstance(buffer, dict) else None  # (hostile files: anything goes)
    extension = extensions.get(MESHOPT) if isinstance(extensions, dict) else None
    required = document.json.get("extensionsRequired") if isinstance(document.json, dict) else None
    return isinstance(extension, dict) and extension.get("fallback") is True and isinstance(required, list) \
        and MESHOPT in required


def _glb_chunks(document: GltfDocument) -> Iterator[tuple[str, str, str, str | None]]:
    """A GLB's chunks as 4.4.3 lays them out: 4-byte aligned, one JSON chunk and at most one BIN chunk (a second of either
    is the validator's GLB_DUPLICATE_CHUNK, a broken resource); and, kind ``gltf_container`` (what the container does
    not need), a chunk of another type (4.4.3.1: clients "MUST ignore" it; GLB_UNKNOWN_CHUNK_TYPE), a BIN chunk longer
    than buffer 0 plus its padding to 4 bytes (BUFFER_GLB_CHUNK_TOO_BIG) and a buffer or image that is a data URI
    (DATA_URI_GLB: base64 text where the BIN chunk holds bytes)."""
    seen: set[int] = set()
    for number, (kind, length) in enumerate(document.chunks):
        tag = kind.to_bytes(4, "little").decode("latin-1")
        name = _CHUNK_NAMES.get(kind, f"0x{kind:08x}" + (f" ({tag!r})" if tag.isprintable() else ""))
        if length % 4:
            yield ("gltf_resource", "", f"GLB chunk {number} ({name}) is {length} bytes long, not a multiple of 4: "
                   "every chunk must start and end on a 4-byte boundary (pad the JSON chunk with spaces, the BIN "
                   "chunk with zeros), and loaders that map the binary data in place read it misaligned", None)
        if kind in seen:
            yield ("gltf_resource", "", f"GLB chunk {number} is a second {name} chunk: a GLB holds one JSON chunk and at "
                   "most one BIN chunk, and loaders read the first, the last or refuse the file", None)
        elif kind not in _CHUNK_NAMES:
            yield ("gltf_container", "", f"GLB chunk {number} has type {name}, neither JSON nor BIN: loaders must ignore "
                   "it (no ratified extension defines another chunk), so whatever it holds is dead weight", None)
        seen.add(kind)
    if document.bom:  # glTF 2.0, JSON encoding: "glTF exporters MUST NOT add a byte order mark" (clients MAY ignore it)
        yield ("gltf_invalid", "", "the JSON starts with a UTF-8 byte-order mark, which glTF exporters must not write: "
               "a loader that hands the text to JSON.parse as it is refuses the file (the Khronos validator's INVALID_JSON)",
               None)
    if not document.is_glb:
        return
    if document.trailing:
        yield ("gltf_container", "", f"{document.trailing} byte{'s follow' if document.trailing > 1 else ' follows'} the GLB's "
               "declared length: loaders stop at the length in its header, so they are never read", None)
    buffer = document.item("buffers", 0)
    length = buffer.get("byteLength") if buffer is not None and "uri" not in buffer else None
    if document.binary is not None and json_index(length) and len(document.binary) > length + (-length % 4):
        yield ("gltf_container", "/buffers/0", f"the GLB's BIN chunk holds {len(document.binary)} bytes, "
               f"{len(document.binary) - length - (-length % 4)} more than buffer 0's byteLength {length} and its padding to "
               "4 bytes: the rest is data no view can reach (a buffer shrunk without its chunk?)", "byteLength")
    for array in ("buffers", "images"):
        for index, item in enumerate(document.array(array)):
            uri = item.get("uri") if isinstance(item, dict) else None
            if isinstance(uri, str) and uri.startswith("data:"):
                yield ("gltf_container", f"/{array}/{index}", f"a GLB's {array[:-1]} {index} is a data URI: base64 text "
                       "a third larger than the bytes, where the BIN chunk (a bufferView) holds them as they are",
                       "uri")


def compression_problems(document: GltfDocument) -> Iterator[tuple[str, str, str, str | None]]:
    """``("gltf_invalid", JSON pointer, message, property)`` for every KHR_draco_mesh_compression object of a mesh
    primitive that lacks what its schema requires: ``bufferView`` (the compressed stream, a glTF id) and
    ``attributes`` (an object naming at least one attribute's id in the stream)."""
    for primitive_pointer, primitive in document.primitives():
        extensions = primitive.get("extensions")
        draco = extensions.get(slots.DRACO) if isinstance(extensions, dict) else None
        if not isinstance(draco, dict):
            continue  # (an extension that is no object is the reader's)
        pointer = f"{primitive_pointer}/extensions/{slots.DRACO}"
        if "bufferView" not in draco:
            yield ("gltf_invalid", pointer, f"{slots.DRACO} has no bufferView: there is no compressed stream for a "
                   "Draco decoder to decode, so viewers draw nothing", None)
        elif not json_index(draco["bufferView"]):
            yield ("gltf_invalid", pointer, f"bufferView must be a bufferView index, not "
                   f"{json_text(draco['bufferView'])}", "bufferView")
        attributes = draco.get("attributes")
        if not isinstance(attributes, dict) or not attributes:
            yield ("gltf_invalid", pointer, f"{slots.DRACO} needs attributes, an object naming each attribute's id "
                   "in the compressed stream", "attributes" if "attributes" in draco else None)


def missing_scene(document: GltfDocument):
    """The document's ``scene`` when it is an index that names no scene, else ``None``."""
    scene = document.json.get("scene")
    if json_index(scene) and scene >= len(document.array("scenes")):
        return scene
    return None


def extension_sources(document: GltfDocument) -> list[dict]:
    """``{"pointer", "extension", "mime", "image", "fallback"}`` for every texture extension's ``source``
    (EXT_texture_webp, KHR_texture_basisu) that names an existing image: the image must be of the extension's MIME
    type; ``fallback`` says whether the texture has a core ``source`` too (without one, the extension's README
    asks for it in extensionsRequired: "Using Without a Fallback")."""
    found = []
    for index, texture in enumerate(document.array("textures")):
        extensions = texture.get("extensions") if isinstance(texture, dict) else None
        for mime, name in slots.EXTENSION_MIME_TYPES.items():
            alternative = extensions.get(name) if isinstance(extensions, dict) else None
            source = alternative.get("source") if isinstance(alternative, dict) else None
            if json_index(source) and document.item("images", source) is not None:
                found.append({"pointer": f"/textures/{index}/extensions/{name}", "extension": name, "mime": mime,
                              "image": source, "fallback": "source" in texture})
    return found


def accessor_problems(document: GltfDocument) -> list[dict]:
    """The accessor layout facts glTF forbids, each ``{"kind", "pointer", "property", ...}`` with the numbers a
    message needs; kinds: ``stride_not_multiple``, ``stride_out_of_range``, ``stride_too_big`` (a bufferView's),
    ``offset_alignment``, ``total_offset_alignment``, ``vertex_unaligned``, ``small_stride``, ``too_long``,
    ``sparse_not_increasing``, ``sparse_out_of_range``, ``sparse_count_zero``, ``unequal_count``. Every bufferView and accessor is judged
    once, every primitive's attribute counts once."""
    found: list[dict] = []
    for index, view in enumerate(document.array("bufferViews")):
        if isinstance(view, dict):
            found.extend(_stride(index, view))
    attributes = _vertex_attribute_accessors(document)
    for index, accessor in enumerate(document.array("accessors")):
        if isinstance(accessor, dict):
            found.extend(_accessor(document, index, accessor, attributes.get(index)))
    for pointer, primitive in document.primitives():
        found.extend(_counts(document, pointer, primitive))
    return found


#: bufferView.schema.json's byteStride: ``minimum`` 4, ``maximum`` 252, ``multipleOf`` 4.
STRIDE_RANGE = (4, 252)
VERTEX_ALIGNMENT = 4  # 3.6.2.4: vertex attribute offsets and strides are multiples of 4


def _stride(index: int, view: dict) -> Iterator[dict]:
    """A bufferView's byteStride against its schema (one finding, the range first as the validator's) and its
    byteLength. A stride that is no integer is the schema's type error, not judged here."""
    stride, length = view.get("byteStride"), view.get("byteLength")
    if not json_index(stride):
        return
    pointer = f"/bufferViews/{index}"
    if not STRIDE_RANGE[0] <= stride <= STRIDE_RANGE[1]:
        yield {"kind": "stride_out_of_range", "pointer": pointer, "property": "byteStride", "stride": stride}
    elif stride % VERTEX_ALIGNMENT:
        yield {"kind": "stride_not_multiple", "pointer": pointer, "property": "byteStride", "stride": stride}
    if json_index(length) and stride > length:
        yield {"kind": "stride_too_big", "pointer": pointer, "property": "byteStride", "stride": stride,
               "length": length}


def _vertex_attribute_accessors(document: GltfDocument) -> dict[int, str]:
    """Accessor index -> the first primitive attribute (or morph target attribute) that reads it."""
    found: dict[int, str] = {}
    for pointer, primitive in document.primitives():
        for where, accessor in vertex_attributes(pointer, primitive):
            if json_index(accessor):
                found.setdefault(accessor, where)
    return found


def _accessor(document: GltfDocument, index: int, accessor: dict, attribute: str | None) -> Iterator[dict]:
    pointer = f"/accessors/{index}"
    component_type = accessor.get("componentType")
    size = COMPONENT_SIZES.get(component_type) if json_index(component_type) else None
    view = document.item("bufferViews", accessor.get("bufferView"))
    offset = accessor.get("byteOffset", 0)
    if size is not None and view is not None and json_index(offset):
        view_offset = view.get("byteOffset", 0)
        if offset % size:
            yield {"kind": "offset_alignment", "pointer": pointer, "property": "byteOffset", "offset": offset, "size": size}
        elif json_index(view_offset) and (offset + view_offset) % size:
            yield {"kind": "total_offset_alignment", "pointer": pointer, "property": "byteOffset", "offset": offset,
                   "view_offset": view_offset, "view": accessor["bufferView"], "size": size}
        kind = accessor.get("type")  # (a list or object there is the schema's to report: no width)
        stride, width = view.get("byteStride"), VECTOR_WIDTHS.get(kind) if isinstance(kind, str) else None
        if attribute is not None and not offset % size:
            # 3.6.2.4 names the accessor's own offset and the stride (a tightly packed view's is the element's size;
            # the validator judges no more: a bufferView.byteOffset of 2 under a 2-byte component passes there)
            packed = None if "byteStride" in view or width is None else width * size
            if offset % VERTEX_ALIGNMENT or (packed is not None and packed % VERTEX_ALIGNMENT):
                yield {"kind": "vertex_unaligned", "pointer": pointer, "property": "byteOffset", "offset": offset,
                       "packed": packed, "view": accessor["bufferView"], "attribute": attribute,
                       "type": accessor.get("type")}
        if json_index(stride) and width is not None and stride < width * size:
            yield {"kind": "small_stride", "pointer": pointer, "property": "bufferView", "view": accessor["bufferView"],
                   "stride": stride, "element": width * size, "type": accessor.get("type")}
        count, view_length = accessor.get("count"), view.get("byteLength")
        if width is not None and json_index(count) and count > 0 and json_index(view_length):
            length = (stride if json_index(stride) else width * size) * (count - 1) + width * size
            if offset + length > view_length:
                yield {"kind": "too_long", "pointer": pointer, "property": "count", "view": accessor["bufferView"],
                       "offset": offset, "length": length, "view_length": view_length, "count": count}
    sparse = accessor.get("sparse")
    if isinstance(sparse, dict) and json_index(accessor.get("count")):
        yield from _sparse(document, pointer, sparse, accessor["count"])


def _sparse(document: GltfDocument, pointer: str, sparse: dict, count: int) -> Iterator[dict]:
    indices, number = sparse.get("indices"), sparse.get("count")
    if json_index(number) and number == 0:  # (the schema's minimum 1: the validator's VALUE_NOT_IN_RANGE)
        yield {"kind": "sparse_count_zero", "pointer": f"{pointer}/sparse", "property": "count"}
    if not isinstance(indices, dict) or not json_index(number) or number == 0:
        return
    dtype = _INDEX_DTYPES.get(indices["componentType"]) if json_index(indices.get("componentType")) else None
    offset = indices.get("byteOffset", 0)
    if dtype is None and json_index(indices.get("componentType")):  # (the validator's VALUE_NOT_IN_LIST)
        yield {"kind": "sparse_index_type", "pointer": f"{pointer}/sparse/indices", "property": "componentType",
               "value": indices["componentType"]}
    if dtype is None or not json_index(offset):
        return
    try:
        data = document.buffer_view(indices.get("bufferView"))
    except ResourceError:
        return  # (a view that cannot be loaded is the broken-resource rule's)
    import numpy  # lazy: NumPy (~60 ms) only for a file with a sparse accessor

    number = min(number, MAX_ELEMENTS)
    if offset + number * numpy.dtype(dtype).itemsize > len(data):
        return
    values = numpy.frombuffer(data, dtype=dtype, count=number, offset=offset).astype(numpy.int64)
    where = f"{pointer}/sparse"
    falling = numpy.flatnonzero(values[1:] <= values[:-1])
    if falling.size:
        at = int(falling[0]) + 1
        yield {"kind": "sparse_not_increasing", "pointer": where, "property": "indices", "position": at,
               "value": int(values[at]), "previous": int(values[at - 1])}
    beyond = numpy.flatnonzero(values >= count)
    if beyond.size:
        at = int(beyond[0])
        yield {"kind": "sparse_out_of_range", "pointer": where, "property": "indices", "position": at,
               "value": int(values[at]), "count": count}


def _counts(document: GltfDocument, pointer: str, primitive: dict) -> Iterator[dict]:
    attributes = primitive.get("attributes")
    counts = _attribute_counts(document, attributes)
    if not counts:
        return
    reference = "POSITION" if "POSITION" in counts else next(iter(counts))
    expected = counts[reference]
    for name, count in counts.items():
        if count != expected:
            yield {"kind": "unequal_count", "pointer": f"{pointer}/attributes", "property": name, "count": count,
                   "reference": reference, "expected": expected}
    targets = primitive.get("targets")
    for number, target in enumerate(targets if isinstance(targets, list) else ()):
        for name, count in _attribute_counts(document, target).items():
            if count != expected:
                yield {"kind": "unequal_count", "pointer": f"{pointer}/targets/{number}", "property": name,
                       "count": count, "reference": reference, "expected": expected}


def _attribute_counts(document: GltfDocument, attributes) -> dict[str, int]:
    if not isinstance(attributes, dict):
        return {}
    counts = {}
    for name, index in attributes.items():
        accessor = document.item("accessors", index)
        if accessor is not None and json_index(accessor.get("count")):
            counts[name] = accessor["count"]
    return counts
