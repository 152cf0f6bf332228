"""The glTF container: JSON (``.gltf``) or GLB (``.glb``), its buffers and its images.

Only the container is decoded here; what the materials mean is :mod:`.gltf_reader`'s job. The JSON
is kept as parsed (``dict``/``list``), because whether a property was authored matters to the
reader (pygltflib's object model fills in every schema default, and its GLB loader raises
``struct.error`` on a truncated file, so it is used for its constants only). The GLB layout is the
specification's section 4.4: a 12-byte header (magic ``glTF``, version 2, total length), then
chunks of (length, type, data), the first of type JSON, an optional second of type BIN.

Resources (buffers, images) are fetched lazily and only ever from inside the asset: a data URI, the
GLB binary chunk, or a relative file beside the asset no larger than the reader's size limit. A
resource that cannot be fetched raises :class:`ResourceError`, which callers turn into a finding.
"""

from __future__ import annotations

import base64
import binascii
import json
import os
import struct
from dataclasses import dataclass, field
from urllib.parse import unquote, unquote_to_bytes

from ..model import Location
from . import ReadError, max_file_bytes, read_bytes

GLB_JSON = 0x4E4F534A
GLB_BIN = 0x004E4942


class ResourceError(Exception):
    """A buffer or image that cannot be fetched; ``pointer`` is the JSON pointer of the culprit."""

    def __init__(self, message: str, pointer: str):
        super().__init__(message)
        self.message = message
        self.pointer = pointer


@dataclass(slots=True)
class GltfDocument:
    path: str
    json: dict
    binary: bytes | None = None
    is_glb: bool = False
    _buffers: dict[int, bytes] = field(default_factory=dict)

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

    # -- resources -------------------------------------------------------------------------
    def buffer(self, index: int) -> bytes:
        if index in self._buffers:
            return self._buffers[index]
        pointer = f"/buffers/{index}"
        buffer = self.item("buffers", index)
        if buffer is None:
            raise ResourceError(f"buffer {index} does not exist", pointer)
        uri = buffer.get("uri")
        if uri is None:
            if not self.is_glb or index != 0 or self.binary is None:
                raise ResourceError("buffer has no uri and there is no GLB binary chunk", pointer)
            data = self.binary
        else:
            data = self.fetch(uri, pointer + "/uri")
        length = buffer.get("byteLength")
        if isinstance(length, int) and len(data) < length:
            raise ResourceError(f"buffer holds {len(data)} bytes, fewer than its byteLength {length}", pointer)
        self._buffers[index] = data
        return data

    def buffer_view(self, index) -> bytes:
        pointer = f"/bufferViews/{index}"
        view = self.item("bufferViews", index)
        if view is None:
            raise ResourceError(f"bufferView {index!r} does not exist", pointer)
        data = self.buffer(view.get("buffer")) if isinstance(view.get("buffer"), int) else None
        if data is None:
            raise ResourceError(f"bufferView {index} names no valid buffer", pointer)
        offset, length = view.get("byteOffset", 0), view.get("byteLength")
        if not isinstance(offset, int) or not isinstance(length, int) or offset < 0 or length < 0 \
                or offset + length > len(data):
            raise ResourceError(f"bufferView {index} lies outside its buffer", pointer)
        return data[offset:offset + length]

    def image_bytes(self, index: int) -> tuple[bytes, str | None]:
        """The encoded bytes of image ``index`` and its declared (or data URI) MIME type."""
        pointer = f"/images/{index}"
        image = self.item("images", index)
        if image is None:
            raise ResourceError(f"image {index} does not exist", pointer)
        if "bufferView" in image:
            return self.buffer_view(image["bufferView"]), image.get("mimeType")
        uri = image.get("uri")
        if not isinstance(uri, str):
            raise ResourceError("image has neither uri nor bufferView", pointer)
        mime = image.get("mimeType") or data_uri_mime(uri)
        return self.fetch(uri, pointer + "/uri"), mime

    def fetch(self, uri: str, pointer: str) -> bytes:
        """The bytes a URI names: a data URI, or a relative file inside the asset's folder."""
        if uri.startswith("data:"):
            return decode_data_uri(uri, pointer)
        if "://" in uri or uri.startswith("/") or os.path.isabs(unquote(uri)):
            raise ResourceError(f"{uri!r} is not a relative path inside the asset; it is not opened", pointer)
        path = os.path.realpath(os.path.join(self.folder, unquote(uri)))
        if os.path.commonpath([path, os.path.realpath(self.folder)]) != os.path.realpath(self.folder):
            raise ResourceError(f"{uri!r} points outside the asset's folder; it is not opened", pointer)
        try:
            return read_bytes(path)
        except ReadError as error:
            raise ResourceError(f"{uri!r}: {error.message}", pointer) from None


def data_uri_mime(uri: str) -> str | None:
    if not uri.startswith("data:"):
        return None
    header = uri[5:uri.find(",")] if "," in uri else ""
    mime = header.split(";", 1)[0]
    return mime or None


def decode_data_uri(uri: str, pointer: str) -> bytes:
    """Decode ``data:[<mime>][;base64],<payload>`` strictly, refusing payloads above the size limit."""
    comma = uri.find(",")
    if comma < 0:
        raise ResourceError("data URI has no ',' before its payload", pointer)
    header, payload = uri[5:comma], uri[comma + 1:]
    limit = max_file_bytes()
    if len(payload) * 3 // 4 > limit:
        raise ResourceError(f"data URI payload is above the {limit / 2**20:.0f} MiB limit (OPENPBR_MAX_FILE_MB)", pointer)
    if header.endswith(";base64"):
        try:
            return base64.b64decode(payload, validate=True)
        except (binascii.Error, ValueError) as error:
            raise ResourceError(f"data URI is not valid base64 ({error})", pointer) from None
    return unquote_to_bytes(payload)


def load_document(path: str) -> GltfDocument:
    """Read and decode the container; :class:`ReadError` when it is not glTF at all."""
    data = read_bytes(path)
    if data[:4] == b"glTF" or path.lower().endswith(".glb"):
        text, binary = _split_glb(data, path)
        is_glb = True
    else:
        text, binary, is_glb = data, None, False
    try:
        decoded = text.decode("utf-8-sig") if isinstance(text, bytes) else text
    except UnicodeDecodeError as error:
        raise ReadError("not_gltf", f"glTF JSON is not UTF-8: {error.reason} at byte {error.start}", Location(path)) from None
    try:
        document = json.loads(decoded)
    except json.JSONDecodeError as error:
        raise ReadError("not_gltf", f"not JSON: {error.msg} (line {error.lineno}, column {error.colno})",
                        Location(path, line=error.lineno)) from None
    except RecursionError:
        raise ReadError("not_gltf", "JSON nested too deeply", Location(path)) from None
    if not isinstance(document, dict):
        raise ReadError("not_gltf", f"the JSON root is a {type(document).__name__}, not an object", Location(path, line=1))
    asset = document.get("asset")
    if not isinstance(asset, dict) or not isinstance(asset.get("version"), str):
        raise ReadError("not_gltf", "not a glTF document: no asset.version", Location(path, path="/asset"))
    major = asset["version"].split(".", 1)[0]
    if major != "2":
        raise ReadError("not_gltf", f"glTF version {asset['version']!r} is not 2.x", Location(path, path="/asset", input="version"))
    return GltfDocument(path=path, json=document, binary=binary, is_glb=is_glb)


def _split_glb(data: bytes, path: str) -> tuple[bytes, bytes | None]:
    """The JSON and BIN chunks of a GLB file (specification 4.4)."""

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
        if start + chunk_length > len(data):
            refuse(f"chunk at byte {offset} declares {chunk_length} bytes, past the end of the file")
        chunks.append((chunk_type, data[start:start + chunk_length]))
        offset = start + chunk_length
    if not chunks or chunks[0][0] != GLB_JSON:
        refuse("the first chunk is not JSON")
    binary = next((chunk for kind, chunk in chunks[1:2] if kind == GLB_BIN), None)
    return chunks[0][1], binary
