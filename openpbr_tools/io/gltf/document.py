"""The glTF container: JSON (``.gltf``) or GLB (``.glb``), its buffers and its images.

Only the container is decoded here; what the materials mean is :mod:`.gltf_reader`'s job. The JSON is kept as
parsed (``dict``/``list``), because whether a property was authored matters to the reader (pygltflib's object model
fills in every schema default, and its GLB loader raises ``struct.error`` on a truncated file, so it is used for its
constants only). The GLB layout is the
specification's section 4.4: a 12-byte header (magic ``glTF``, version 2, total length), then
chunks of (length, type, data), the first of type JSON, an optional second of type BIN. Declared
lengths are checked against the bytes actually present before anything is sliced, so a header
claiming gigabytes costs nothing.

Limits, each refusing hostile input before the work it would cause:

* the file itself: ``OPENPBR_MAX_FILE_MB`` (64 MiB), checked on its size before it is read;
* JSON nesting: :data:`MAX_JSON_DEPTH` levels (serde_json's default recursion limit); deeper
  documents are refused as malformed, so no later step can run out of Python's recursion limit;
* integers of more than 4300 digits (Python's conversion limit) are read as floats (infinite), not
  refused: the property holding one is then simply out of range or of the wrong type;
* a property name repeated within one object (``{"a": 1, "a": 2}``: glTF 2.0, JSON Encoding: names "SHOULD be
  unique", clients "SHOULD override lexically preceding values") is read as its last value, as the specification
  asks, and every repetition is kept (:attr:`GltfDocument.duplicates`) for the rules;
* strings holding an unpaired UTF-16 surrogate escape (``"\\ud800"``: valid JSON, not valid
  Unicode, and unwritable as UTF-8) get U+FFFD instead, and the repair is reported
  (:attr:`GltfDocument.repairs`);
* a data URI's decoded bytes: ``OPENPBR_MAX_DATA_URI_MB`` (by default the file limit: an embedded
  resource may be as large as a file beside the asset), computed from the payload's length before
  anything is decoded.

Resources (buffers, images) are fetched lazily, each at most once (failures included, so a thousand images in one
broken buffer cost one attempt), and only ever from inside the asset: a data URI, the GLB binary chunk, or a relative
file beside the asset (after following symbolic links) no larger than the file limit. A resource that cannot be
fetched raises :class:`ResourceError`, which callers turn into a finding; it is a :class:`~openpbr_tools.io.ReadError`,
so a caller that does not expect it still reports unreadable input rather than a traceback.

One module because the limits above are one policy over one file's bytes: the container, the JSON's repairs and
the buffers and images its URIs name (files, data URIs, the BIN chunk) are read along one path, under the same
path guard, size limits and :class:`ResourceError`.
"""

from __future__ import annotations

import base64
import binascii
import json
import os
import re
import struct
from dataclasses import dataclass, field
from urllib.parse import unquote, unquote_to_bytes

from ...model import Location
from .. import ReadError, max_file_bytes, read_bytes
from ..paths import Kind, PathGuard, classify

GLB_JSON = 0x4E4F534A
GLB_BIN = 0x004E4942
MAX_JSON_DEPTH = 128  # serde_json's default recursion limit; glTF documents nest about 8 deep
MAX_INTEGER_DIGITS = 4300  # sys.int_info.default_max_str_digits: int() refuses longer strings
_SURROGATE_ESCAPE = re.compile(rb"\\u[dD][89a-fA-F]")
_SURROGATE = re.compile("[\ud800-\udfff]")


class ResourceError(ReadError):
    """A buffer or image that cannot be fetched; ``pointer`` is the JSON pointer of the culprit."""

    def __init__(self, message: str, pointer: str, file: str = "", outside: bool = False):
        super().__init__("unreadable", message, Location(file, path=pointer))
        self.pointer = pointer
        self.outside = outside  # refused because it lies outside the asset (not because it is broken)


def max_data_uri_bytes() -> int:
    """The largest decoded data URI accepted: ``OPENPBR_MAX_DATA_URI_MB``, else the file limit."""
    value = os.environ.get("OPENPBR_MAX_DATA_URI_MB")
    try:
        return int(float(value) * 1024 * 1024) if value else max_file_bytes()
    except ValueError:
        return max_file_bytes()


def vertex_attributes(pointer: str, primitive: dict) -> list[tuple[str, object]]:
    """(JSON pointer, accessor id as written) of a primitive's attributes and its morph targets' attributes."""
    targets = primitive.get("targets") if isinstance(primitive.get("targets"), list) else ()
    groups = [(primitive.get("attributes"), f"{pointer}/attributes")]
    groups += [(target, f"{pointer}/targets/{n}") for n, target in enumerate(targets)]
    return [(f"{where}/{name}", accessor) for group, where in groups
            for name, accessor in (group.items() if isinstance(group, dict) else ())]


@dataclass(slots=True)
class GltfDocument:
    path: str
    json: dict
    binary: bytes | None = None
    is_glb: bool = False
    repairs: list[tuple[str, str]] = field(default_factory=list)  # (JSON pointer, what was repaired)
    duplicates: list[tuple[str, int]] = field(default_factory=list)  # (JSON pointer of a repeated name, times written)
    chunks: tuple[tuple[int, int], ...] = ()  # a GLB's chunks as (type, declared length), in file order
    trailing: int = 0  # bytes after a GLB's declared length (loaders stop at the header's length)
    bom: bool = False  # the JSON text starts with a UTF-8 byte-order mark (read past, as clients may)
    _buffers: dict[int, bytes | ResourceError] = field(default_factory=dict)
    _files: dict[str, bytes | ResourceError] = field(default_factory=dict)
    allow_outside: tuple[str, ...] = ()  # folders besides the asset's own that URIs may name

    @property
    def folder(self) -> str:
        return os.path.dirname(os.path.abspath(self.path))

    def array(self, name: str) -> list:
        value = self.json.get(name)
        return value if isinstance(value, list) else []

    def item(self, name: str, index) -> dict | None:
        """``json[name][index]`` when it exists and is an object, else ``None``."""
        items = self.array(name)
        if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index < len(items):
            return None
        found = items[index]
        return found if isinstance(found, dict) else None

    def primitives(self):
        """(JSON pointer, primitive) of every mesh primitive that is an object, in document order."""
        for mesh_index, mesh in enumerate(self.array("meshes")):
            primitives = mesh.get("primitives") if isinstance(mesh, dict) else None
            for index, primitive in enumerate(primitives if isinstance(primitives, list) else ()):
                if isinstance(primitive, dict):
                    yield f"/meshes/{mesh_index}/primitives/{index}", primitive

    def error(self, message: str, pointer: str, outside: bool = False) -> ResourceError:
        return ResourceError(message, pointer, self.path, outside)

    def missing(self, uri: str, pointer: str) -> ResourceError:
        return self.error(f"file {unquote(uri)!r} not found", pointer)

    # -- resources -------------------------------------------------------------------------
    def resolve(self, uri: str, pointer: str) -> str:
        """The real path of a relative URI inside the asset's folder; :class:`ResourceError` for a
        URL, an absolute path, a path that climbs out of the folder (``..`` or a symbolic link) or
        a name no file system accepts (NUL)."""
        relative = unquote(uri)
        # Both the URI and the file name it decodes to must be relative: "%2Fetc%2Fpasswd" is absolute.
        kind = classify(uri)
        if kind is Kind.RELATIVE:
            kind = classify(relative)
        if kind is Kind.NUL:  # unpaired surrogates are repaired at load
            raise self.error(f"{uri!r} is not a usable file name (embedded null byte)", pointer)
        if kind is Kind.EMPTY:  # names the folder itself, no file
            raise self.missing(uri, pointer)
        if kind is not Kind.RELATIVE:
            raise self.error(f"{uri!r} is not a relative path inside the asset; it is not opened", pointer, outside=True)
        resolved = PathGuard(self.folder, self.allow_outside).resolve(relative)
        if not resolved.inside:
            raise self.error(f"{uri!r} resolves outside the asset's folder; it is not opened", pointer, outside=True)
        return resolved.real

    def buffer(self, index: int) -> bytes:
        if index not in self._buffers:
            try:
                self._buffers[index] = self._load_buffer(index)
            except ResourceError as error:
                self._buffers[index] = error
        found = self._buffers[index]
        if isinstance(found, ResourceError):
            raise found
        return found

    def _load_buffer(self, index: int) -> bytes:
        pointer = f"/buffers/{index}"
        buffer = self.item("buffers", index)
        if buffer is None:
            raise self.error(f"buffer {index} does not exist", pointer)
        uri = buffer.get("uri")
        if uri is None:
            if not self.is_glb or index != 0 or self.binary is None:
                raise self.error("buffer has no uri and there is no GLB binary chunk", pointer)
            data = self.binary
        elif not isinstance(uri, str):
            raise self.error("buffer uri is not a string", pointer + "/uri")
        else:
            data = self.fetch(uri, pointer + "/uri")
        length = buffer.get("byteLength")
        if isinstance(length, int) and len(data) < length:
            raise self.error(f"buffer holds {len(data)} bytes, fewer than its byteLength {length}", pointer)
        return data

    def buffer_view(self, index) -> memoryview:
        """The bytes of a bufferView, as a view into its buffer (never copied)."""
        pointer = f"/bufferViews/{index}"
        view = self.item("bufferViews", index)
        if view is None:
            raise self.error(f"bufferView {index!r} does not exist", pointer)
        buffer = view.get("buffer")
        if isinstance(buffer, bool) or not isinstance(buffer, int):
            raise self.error(f"bufferView {index} names no valid buffer", pointer)
        data = self.buffer(buffer)
        offset, length = view.get("byteOffset", 0), view.get("byteLength")
        if not all(isinstance(n, int) and not isinstance(n, bool) and n >= 0 for n in (offset, length)) \
                or offset + length > len(data):
            raise self.error(f"bufferView {index} lies outside its buffer", pointer)
        return memoryview(data)[offset:offset + length]

    def image_view(self, index: int) -> tuple[bytes | memoryview, str | None]:
        """The encoded bytes of image ``index`` (a view when they sit in a buffer) and its declared
        (or data URI) MIME type."""
        pointer = f"/images/{index}"
        image = self.item("images", index)
        if image is None:
            raise self.error(f"image {index} does not exist", pointer)
        if "bufferView" in image:
            return self.buffer_view(image["bufferView"]), image.get("mimeType")
        uri = image.get("uri")
        if not isinstance(uri, str):
            raise self.error("image has neither uri nor bufferView", pointer)
        mime = image.get("mimeType") or data_uri_mime(uri)
        return self.fetch(uri, pointer + "/uri"), mime

    def image_bytes(self, index: int) -> tuple[bytes, str | None]:
        """The encoded bytes of image ``index`` and its declared (or data URI) MIME type."""
        data, mime = self.image_view(index)
        return bytes(data), mime

    def fetch(self, uri: str, pointer: str) -> bytes:
        """The bytes a URI names: a data URI, or a relative file inside the asset's folder."""
        if uri.startswith("data:"):
            try:
                return decode_data_uri(uri, pointer)
            except ResourceError as error:
                raise self.error(error.message, pointer) from None
        path = self.resolve(uri, pointer)
        if not os.path.isfile(path):
            raise self.missing(uri, pointer)
        if path not in self._files:  # several buffers naming one file read it once
            try:
                self._files[path] = read_bytes(path)
            except ReadError as error:
                self._files[path] = self.error(f"{uri!r}: {error.message}", pointer)
        found = self._files[path]
        if isinstance(found, ResourceError):
            raise self.error(found.message, pointer)
        return found


_MEDIA_TYPE = re.compile(r"(|[A-Za-z0-9!#$&^_.+-]+/[A-Za-z0-9!#$&^_.+-]+)")


def data_uri_mime(uri: str) -> str | None:
    if not uri.startswith("data:"):
        return None
    header = uri[5:uri.find(",")] if "," in uri else ""
    mime = header.split(";", 1)[0]
    return mime or None


def decode_data_uri(uri: str, pointer: str) -> bytes:
    """Decode ``data:[<mime>][;base64],<payload>`` strictly, refusing payloads above
    :func:`max_data_uri_bytes` before decoding them."""
    comma = uri.find(",")
    if comma < 0:
        raise ResourceError("data URI has no ',' before its payload", pointer)
    header, payload = uri[5:comma], uri[comma + 1:]
    if any(not part for part in header.split(";")[1:]) or not _MEDIA_TYPE.fullmatch(header.split(";", 1)[0]):
        # RFC 2397: data:[<mediatype>][;base64],<data>, a media type type/subtype with ;attribute=value parameters
        raise ResourceError(f"data URI header {header!r} is malformed (RFC 2397: data:[type/subtype][;name=value]"
                            "[;base64],...): loaders that parse it strictly refuse it", pointer)
    limit = max_data_uri_bytes()
    base64_encoded = header.endswith(";base64")
    decoded_size = len(payload) * 3 // 4 if base64_encoded else len(payload)  # an upper bound either way
    if decoded_size > limit:
        raise ResourceError(f"data URI payload ({decoded_size / 2**20:.1f} MiB decoded) is above the "
                            f"{limit / 2**20:g} MiB limit (OPENPBR_MAX_DATA_URI_MB); it is not decoded", pointer)
    if base64_encoded:
        try:
            return base64.b64decode(payload, validate=True)
        except (binascii.Error, ValueError) as error:
            raise ResourceError(f"data URI is not valid base64 ({error})", pointer) from None
    return unquote_to_bytes(payload)


def load_document(path: str) -> GltfDocument:
    """Read and decode the container; :class:`ReadError` when it is not glTF at all."""
    data = read_bytes(path)
    trailing = 0
    json_text = data[:64].lstrip(b" \t\r\n").removeprefix(b"\xef\xbb\xbf").lstrip(b" \t\r\n")[:1] == b"{"
    if data[:4] == b"glTF" or path.lower().endswith(".glb") and not json_text:  # (JSON named .glb is read as the
        # JSON it is, as a GLB named .gltf is read as a GLB, and as the Khronos glTF-Validator reads both)
        if len(data) >= 12 and data[:4] == b"glTF" and 12 <= struct.unpack_from("<I", data, 8)[0] < len(data):
            trailing = len(data) - struct.unpack_from("<I", data, 8)[0]  # the Khronos validator's GLB_EXTRA_DATA
            data = data[:len(data) - trailing]
        text, binary, chunks = _split_glb(data, path)
        is_glb = True
    else:
        text, binary, is_glb, chunks = data, None, False, ()
    if text[:2] in (b"\xff\xfe", b"\xfe\xff"):
        raise ReadError("not_gltf", "glTF JSON is UTF-16 (it starts with a UTF-16 byte-order mark); glTF requires UTF-8",
                        Location(path))
    try:
        decoded = text.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        raise ReadError("not_gltf", f"glTF JSON is not UTF-8: {error.reason} at byte {error.start}", Location(path)) from None
    too_deep = ReadError("not_gltf", f"JSON nested more than {MAX_JSON_DEPTH} levels deep", Location(path))
    repeated: dict[int, tuple[dict, dict[str, int]]] = {}
    try:
        document = json.loads(decoded, parse_int=_integer, parse_constant=_NotJson,
                              object_pairs_hook=_object_keeping_repeats(repeated))
    except json.JSONDecodeError as error:
        raise ReadError("not_gltf", f"not JSON: {error.msg} (line {error.lineno}, column {error.colno})",
                        Location(path, line=error.lineno)) from None
    except RecursionError:
        raise too_deep from None
    if not isinstance(document, dict):
        raise ReadError("not_gltf", f"the JSON root is a {type(document).__name__}, not an object", Location(path, line=1))
    repairs: list[tuple[str, str]] = []
    duplicates: list[tuple[str, int]] = []
    if not _settle(document, repair=_SURROGATE_ESCAPE.search(text) is not None, repairs=repairs,
                   repeated=repeated, duplicates=duplicates, literals=re.search(rb"NaN|Infinity", text) is not None):
        raise too_deep
    asset = document.get("asset")
    if not isinstance(asset, dict) or not isinstance(asset.get("version"), str):
        raise ReadError("not_gltf", "not a glTF document: no asset.version", Location(path, path="/asset"))
    major = asset["version"].split(".", 1)[0]
    if major != "2":
        raise ReadError("not_gltf", f"glTF version {asset['version']!r} is not 2.x", Location(path, path="/asset", input="version"))
    return GltfDocument(path=path, json=document, binary=binary, is_glb=is_glb, repairs=repairs, chunks=chunks,
                        duplicates=duplicates, trailing=trailing, bom=text.startswith(b"\xef\xbb\xbf"))


def _object_keeping_repeats(repeated: dict[int, tuple[dict, dict[str, int]]]):
    """A ``json`` object hook that builds each object as ``json`` does (the last value of a repeated name wins)
    and notes, by the object's identity, how often each repeated name was written. The object itself is kept in
    ``repeated`` so that its identity stays unique until :func:`_settle` has found its pointer."""

    def build(pairs: list) -> dict:
        found = dict(pairs)
        if len(found) != len(pairs):
            counts: dict[str, int] = {}
            for key, _ in pairs:
                counts[key] = counts.get(key, 0) + 1
            repeated[id(found)] = (found, {key: n for key, n in counts.items() if n > 1})
        return found

    return build


def _integer(digits: str):
    """JSON integers as Python ints, except those too long for ``int()`` (read as float: ±inf)."""
    return int(digits) if len(digits) <= MAX_INTEGER_DIGITS else float(digits)


#: The glTF schema's integer properties (glTFid references, counts, enums) and arrays of them. JSON has one number type
#: and JSON Schema's "integer" is any number without a fraction (0.0 is the integer 0: the Khronos glTF-Validator accepts
#: it), so such a number written with a fraction of 0 is read as the integer (the red team's F#6: "index": 0.0 was two
#: errors and a dropped texture).
_INTEGER_PROPERTIES = frozenset((
    "index", "texCoord", "source", "sampler", "material", "mesh", "node", "scene", "bufferView", "buffer", "camera",
    "skin", "indices", "input", "output", "count", "byteOffset", "byteLength", "byteStride", "componentType", "mode",
    "target", "skeleton", "inverseBindMatrices", "magFilter", "minFilter", "wrapS", "wrapT", "variant"))
_INTEGER_ARRAYS = frozenset(("nodes", "children", "joints", "variants", "attributes"))


class _NotJson(float):
    """A ``NaN``, ``Infinity`` or ``-Infinity`` literal, which Python's ``json`` reads and JSON (RFC 8259) has not:
    :func:`_settle` notes where each stands and leaves the float."""

    def __new__(cls, literal: str):
        value = super().__new__(cls, literal)
        value.literal = literal
        return value


def _settle(document: dict, repair: bool, repairs: list[tuple[str, str]],
            repeated: dict[int, tuple[dict, dict[str, int]]], duplicates: list[tuple[str, int]],
            literals: bool = False) -> bool:
    """Check the nesting depth (``False`` when above :data:`MAX_JSON_DEPTH`) and, when ``repair``,
    replace unpaired surrogates in keys and strings by U+FFFD, noting each repair; note the pointer of every
    name the parse found ``repeated`` in an object of the document, and (``literals``) of every NaN or Infinity
    literal (:class:`_NotJson`). Iterative: the document may be nested as deeply as ``json`` allowed."""
    stack: list[tuple[dict | list, int, str]] = [(document, 1, "")]
    while stack:
        container, depth, pointer = stack.pop()
        integers = pointer.rsplit("/", 1)[-1] in _INTEGER_ARRAYS
        if depth > MAX_JSON_DEPTH:
            return False
        if isinstance(container, dict):
            known = repeated.get(id(container)) if repeated else None
            if known is not None and known[0] is container:
                duplicates.extend((f"{pointer}/{_escape(key)}", times) for key, times in known[1].items())
            if repair and any(_SURROGATE.search(key) for key in container):
                fixed = {}
                for key, value in container.items():
                    clean = _SURROGATE.sub("\ufffd", key)
                    if clean != key:
                        repairs.append((f"{pointer}/{_escape(clean)}", "property name holds an unpaired surrogate escape"))
                    fixed[clean] = value
                container.clear()
                container.update(fixed)
            items = container.items()
        else:
            items = enumerate(container)
        for key, value in list(items):
            if isinstance(value, (dict, list)):
                stack.append((value, depth + 1, f"{pointer}/{_escape(key)}"))
            elif isinstance(value, float) and (integers or key in _INTEGER_PROPERTIES) and value.is_integer() \
                    and abs(value) <= 2 ** 53 and not isinstance(value, _NotJson):
                container[key] = int(value)  # (within what a float holds exactly)
            elif literals and isinstance(value, _NotJson):
                container[key] = float(value)
                repairs.append((f"{pointer}/{_escape(key)}", f"{value.literal} is not JSON (RFC 8259 has no such number; "
                                "the Khronos glTF-Validator's INVALID_JSON): JSON.parse, and with it every web viewer, "
                                "refuses the whole file"))
            elif repair and isinstance(value, str) and _SURROGATE.search(value):
                container[key] = _SURROGATE.sub("\ufffd", value)
                repairs.append((f"{pointer}/{_escape(key)}",
                                "string holds an unpaired surrogate escape (\\ud800-\\udfff), which is not Unicode; read as U+FFFD"))
    return True


def _escape(token) -> str:
    return str(token).replace("~", "~0").replace("/", "~1")


def _split_glb(data: bytes, path: str) -> tuple[bytes, bytes | None, tuple[tuple[int, int], ...]]:
    """The JSON and BIN chunks of a GLB file (specification 4.4), and every chunk's (type, length). A chunk
    length that is no multiple of 4 is not refused here (the layout rules report it; the bytes still read)."""

    def refuse(message: str):
        raise ReadError("not_gltf", f"bad GLB: {message}", Location(path))

    if len(data) < 12:
        refuse(f"{len(data)} bytes, shorter than the 12-byte header")
    magic, version, length = data[:4], *struct.unpack_from("<II", data, 4)
    if magic != b"glTF":
        refuse(f"magic is {magic!r}, not b'glTF'")
    if version != 2:
        refuse(f"container version {version}, not 2")
    if length != len(data):
        refuse(f"header length {length} differs from the file size {len(data)}")
    chunks: list[tuple[int, bytes]] = []
    offset = 12
    while offset < len(data):
        if offset + 8 > len(data):
            refuse(f"truncated chunk header at byte {offset}")
        chunk_length, chunk_type = struct.unpack_from("<II", data, offset)
        start = offset + 8
        if chunk_length > len(data) - start:
            refuse(f"chunk at byte {offset} declares {chunk_length} bytes, past the end of the file")
        chunks.append((chunk_type, data[start:start + chunk_length]))
        offset = start + chunk_length
    if not chunks or chunks[0][0] != GLB_JSON:
        refuse("the first chunk is not JSON")
    binary = next((chunk for kind, chunk in chunks[1:2] if kind == GLB_BIN), None)
    return chunks[0][1], binary, tuple((kind, len(chunk)) for kind, chunk in chunks)
