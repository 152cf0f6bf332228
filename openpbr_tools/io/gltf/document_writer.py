"""Assembling a glTF document: images, samplers, textures, materials, an optional preview mesh, and
the bytes of the ``.gltf`` (plus its ``.bin`` and image files) or the ``.glb``.

Every array is filled in the order things are added and de-duplicated (an image by its source or
content, a sampler by its wrap modes, a texture by image and sampler), so the same materials always
give the same bytes. Binary data is laid out 4-byte aligned, as accessors need (specification 3.6.2.4);
a GLB pads its JSON chunk with spaces and its BIN chunk with zeros (section 4.4.3).
"""

from __future__ import annotations

import base64
import json
import os
import struct
from urllib.parse import quote

from ... import __version__


def dumps(document: dict) -> str:
    """The glTF JSON text: insertion order, two-space indent, UTF-8, shortest round-trip floats."""
    return json.dumps(document, indent=2, ensure_ascii=False, allow_nan=False) + "\n"


def data_uri(data: bytes, mime: str) -> str:
    """``data`` as an RFC 2397 base64 data URI."""
    return f"data:{mime};base64,{base64.b64encode(data).decode('ascii')}"


class DocumentBuilder:
    def __init__(self, path: str, *, glb: bool, embed: bool):
        self.path, self.glb, self.embed = path, glb, embed
        self.folder = os.path.dirname(os.path.abspath(path))
        self.stem = os.path.splitext(os.path.basename(path))[0]
        self.materials: list[dict] = []
        self.images: list[dict] = []
        self.textures: list[dict] = []
        self.samplers: list[dict] = []
        self.meshes: list[dict] = []
        self.nodes: list[dict] = []
        self.accessors: list[dict] = []
        self.buffer_views: list[dict] = []
        self.binary = bytearray()
        self.files: list[tuple[str, bytes]] = []
        self._image_keys: dict = {}
        self._file_names: dict[str, object] = {}

    # -- materials and textures ---------------------------------------------------------------
    def add_material(self, material: dict) -> int:
        self.materials.append(material)
        return len(self.materials) - 1

    def add_sampler(self, wrap_s: int, wrap_t: int, filters: dict | None = None) -> int:
        sampler = {**(filters or {}), "wrapS": wrap_s, "wrapT": wrap_t}
        if sampler not in self.samplers:
            self.samplers.append(sampler)
        return self.samplers.index(sampler)

    def add_texture(self, image: int, sampler: int | None) -> int:
        texture = {"sampler": sampler, "source": image} if sampler is not None else {"source": image}
        if texture not in self.textures:
            self.textures.append(texture)
        return self.textures.index(texture)

    def add_image(self, key, data, mime: str | None, name: str) -> int:
        """Image for ``key`` (added once); ``data`` is bytes or a callable returning them."""
        if key in self._image_keys:
            return self._image_keys[key]
        payload = data() if callable(data) else data
        mime = mime or "image/png"
        if self.glb and self.embed:
            image = {"bufferView": self.add_view(payload), "mimeType": mime}
        elif self.embed:
            image = {"uri": data_uri(payload, mime)}
        else:
            image = {"uri": self.place_file(name, payload)}
        self.images.append(image)
        self._image_keys[key] = len(self.images) - 1
        return len(self.images) - 1

    def image_name(self, index: int) -> str:
        """How a note names image ``index``: the file it is written to, or where it is embedded."""
        uri = self.images[index].get("uri", "")
        return uri if uri and not uri.startswith("data:") else f"image {index} (embedded)"

    def place_file(self, name: str, payload: bytes) -> str:
        """The URI of a file holding ``payload`` beside the output (unique name, written at the end)."""
        base, suffix = os.path.splitext(name)
        candidate, counter = name, 1
        # Never overwrite a different file already beside the output: take the next free name.
        while (candidate in self._file_names and self._file_names[candidate] != payload) or (
                candidate not in self._file_names and self._occupied(candidate, payload)):
            counter += 1
            candidate = f"{base}_{counter}{suffix}"
        if candidate not in self._file_names:
            self._file_names[candidate] = payload
            target = os.path.join(self.folder, *candidate.split("/"))
            if not os.path.isfile(target):
                self.files.append((target, payload))
        return quote(candidate, safe="/")

    def _occupied(self, name: str, payload: bytes) -> bool:
        target = os.path.join(self.folder, *name.split("/"))
        return os.path.lexists(target) and not (os.path.isfile(target) and _same_bytes(target, payload))

    # -- binary data -------------------------------------------------------------------------
    def add_view(self, payload: bytes, target: int | None = None) -> int:
        while len(self.binary) % 4:
            self.binary.append(0)
        view = {"buffer": 0, "byteOffset": len(self.binary), "byteLength": len(payload)}
        if target is not None:
            view["target"] = target
        self.binary += payload
        self.buffer_views.append(view)
        return len(self.buffer_views) - 1

    def add_accessor(self, array, kind: str, target: int, bounds: bool = False) -> int:
        import pygltflib  # lazy: pygltflib costs ~70 ms; only the preview mesh has accessors

        component = pygltflib.UNSIGNED_SHORT if array.dtype.kind == "u" else pygltflib.FLOAT
        accessor = {"bufferView": self.add_view(array.tobytes(), target), "componentType": component,
                    "count": int(array.shape[0]), "type": kind}
        if bounds:
            accessor["min"] = [float(v) for v in array.min(axis=0)]
            accessor["max"] = [float(v) for v in array.max(axis=0)]
        self.accessors.append(accessor)
        return len(self.accessors) - 1

    def add_spheres(self, materials: list[int], texcoords: list[set[int]]) -> None:
        """One sphere mesh per material (shared geometry), nodes 2.5 radii apart along +X, centred."""
        # lazy: only --mesh needs them (pygltflib ~70 ms; .mesh imports numpy, ~60 ms)
        import pygltflib
        from .mesh import uv_sphere

        sphere = uv_sphere()
        array, elements = pygltflib.ARRAY_BUFFER, pygltflib.ELEMENT_ARRAY_BUFFER
        attributes = {
            "POSITION": self.add_accessor(sphere["POSITION"], "VEC3", array, bounds=True),
            "NORMAL": self.add_accessor(sphere["NORMAL"], "VEC3", array),
            "TANGENT": self.add_accessor(sphere["TANGENT"], "VEC4", array),
            "TEXCOORD_0": self.add_accessor(sphere["TEXCOORD_0"], "VEC2", array),
        }
        indices = self.add_accessor(sphere["indices"], "SCALAR", elements)
        spacing = 2.5
        start = -spacing * (len(materials) - 1) / 2.0
        for position, (material, sets) in enumerate(zip(materials, texcoords)):
            primitive_attributes = dict(attributes)
            for extra_set in sorted(s for s in sets if s > 0):
                # The preview has one UV layout; a texture reading another set gets the same coordinates.
                primitive_attributes[f"TEXCOORD_{extra_set}"] = attributes["TEXCOORD_0"]
            name = self.materials[material].get("name") or f"material_{material}"
            self.meshes.append({"name": name, "primitives": [{"attributes": primitive_attributes, "indices": indices,
                                                              "material": material}]})
            node = {"name": name, "mesh": len(self.meshes) - 1}
            offset = start + spacing * position
            if offset:
                node["translation"] = [offset, 0.0, 0.0]
            self.nodes.append(node)

    # -- output ------------------------------------------------------------------------------
    def document(self) -> dict:
        document: dict = {"asset": {"generator": f"openpbr-tools {__version__}", "version": "2.0"}}
        used = set()
        for material in self.materials:
            used.update(name for name in material.get("extensions", {}))
            used.update(_nested_extensions(material))
        if used:
            document["extensionsUsed"] = sorted(used)
        if self.nodes:
            document["scene"] = 0
            document["scenes"] = [{"nodes": list(range(len(self.nodes)))}]
            document["nodes"] = self.nodes
            document["meshes"] = self.meshes
        for key, items in (("materials", self.materials), ("textures", self.textures), ("images", self.images),
                           ("samplers", self.samplers), ("accessors", self.accessors), ("bufferViews", self.buffer_views)):
            if items:
                document[key] = items
        if self.binary:
            while len(self.binary) % 4:
                self.binary.append(0)
            buffer: dict = {"byteLength": len(self.binary)}
            if not self.glb:
                if self.embed:
                    buffer["uri"] = data_uri(bytes(self.binary), "application/octet-stream")
                else:
                    buffer["uri"] = self.place_file(f"{self.stem}.bin", bytes(self.binary))
            document["buffers"] = [buffer]
        return document

    def finish(self) -> list[tuple[str, bytes]]:
        """[(output path, bytes), (other file, bytes), ...]: the document first, then files beside it."""
        text = dumps(self.document())
        if not self.glb:
            return [(self.path, text.encode("utf-8"))] + self.files
        chunk = text.rstrip("\n").encode("utf-8")
        chunk += b" " * (-len(chunk) % 4)
        body = struct.pack("<II", len(chunk), 0x4E4F534A) + chunk
        if self.binary:
            body += struct.pack("<II", len(self.binary), 0x004E4942) + bytes(self.binary)
        header = b"glTF" + struct.pack("<II", 2, 12 + len(body))
        return [(self.path, header + body)] + self.files


def _nested_extensions(value) -> set[str]:
    """Extension names used inside a material below its own ``extensions`` (KHR_texture_transform)."""
    found = set()
    if isinstance(value, dict):
        for key, child in value.items():
            if key == "extensions" and isinstance(child, dict):
                found.update(child)
                for inner in child.values():
                    found |= _nested_extensions(inner)
            else:
                found |= _nested_extensions(child)
    elif isinstance(value, list):
        for child in value:
            found |= _nested_extensions(child)
    return found


def _same_bytes(path: str, payload: bytes) -> bool:
    try:
        if os.path.getsize(path) != len(payload):
            return False
        with open(path, "rb") as handle:
            return handle.read() == payload
    except OSError:
        return False

