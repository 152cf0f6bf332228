"""The sixth red-team round's glTF files (session 19, G: written without reading this code) that the toolkit
passed: vertex attributes of a format or set glTF forbids, a texture rotation in degrees, KHR_texture_basisu sources
that hold no Basis Universal payload, a strided image bufferView and a Draco object without its stream. Each test
writes the red team's defect pattern into a small file of its own and the repaired file beside it, and expects the
finding on the first and silence on the second. Where the Khronos glTF-Validator has a verdict it is the anchor (its
code on the broken file, not on the repaired one; run when OPENPBR_GLTF_VALIDATOR is set); where it has none (a
rotation in degrees, a Draco object, whose schema it does not check; a KTX2 without Basis Universal, which this
validator version does not decode), the glTF specification and the extension's README are, and the test checks that
the validator indeed reports no error on either file."""

from __future__ import annotations

import base64
import json
import math
import struct
from pathlib import Path

import pytest

from redteam_support import findings, khronos_errors, khronos_warnings, messages

_PNG_BYTES = base64.b64decode("iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mM8kWLEAANMDEgANwcARfYBZsiXQosAAAAASUVO"
                              "RK5CYII=")
_PNG = "data:image/png;base64," + base64.b64encode(_PNG_BYTES).decode("ascii")
_POSITIONS = (0, 0, 0, 1, 0, 0, 0, 1, 0)
_NORMALS = (0, 0, 1) * 3
_TANGENTS = (1, 0, 0, 1) * 3
_UVS = (0, 0, 1, 0, 0, 1)
_PRIMITIVE = "/meshes/0/primitives/0/attributes"


def _agree(tmp_path, broken: Path, fixed: Path, khronos_code: str | None, expected: list, warning: bool = False) -> None:
    """``broken`` has exactly the findings ``expected`` (code, severity, pointer, property) and ``fixed`` none; the
    Khronos validator reports ``khronos_code`` on the first (an error, or with ``warning`` a warning) and not on the
    second (with ``None``: no error on either, the validator not checking this)."""
    assert findings(broken) == expected, findings(broken)
    assert findings(fixed) == []
    errors = khronos_errors(broken, tmp_path)
    if errors is None:
        return
    repaired = khronos_errors(fixed, tmp_path)
    if khronos_code is None:
        assert errors == set() and repaired == set(), (errors, repaired)
        return
    if warning:
        assert errors == set() and repaired == set(), (errors, repaired)
        errors, repaired = khronos_warnings(broken, tmp_path), khronos_warnings(fixed, tmp_path)
    assert khronos_code in errors, errors
    assert khronos_code not in repaired, repaired


def _write(path: Path, document: dict) -> Path:
    path.write_text(json.dumps(document, indent=1), encoding="utf-8")
    return path


def _triangle(columns: list[tuple[str, tuple, dict]], attributes: dict) -> dict:
    """A triangle drawn with material 0 (a base colour texture on TEXCOORD_0). ``columns`` are the accessors, in order,
    each ``(struct format, values, accessor members)`` in a bufferView of its own; ``attributes`` name them by index."""
    data, views, accessors = b"", [], []
    for number, (layout, values, members) in enumerate(columns):
        packed = struct.pack("<" + layout, *values)
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(packed)})
        accessors.append({"bufferView": number, **members})
        data += packed + bytes(-len(packed) % 4)
    return {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode("ascii")}],
        "bufferViews": views, "accessors": accessors,
        "images": [{"uri": _PNG}], "textures": [{"source": 0}],
        "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "meshes": [{"primitives": [{"attributes": attributes, "material": 0}]}],
    }


_POSITION = ("9f", _POSITIONS, {"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]})
_NORMAL = ("9f", _NORMALS, {"componentType": 5126, "count": 3, "type": "VEC3"})


def _uvs(**members) -> tuple:
    return "6f", _UVS, {"componentType": 5126, "count": 3, "type": "VEC2", **members}


def _tangents(width: int) -> tuple:
    values = _TANGENTS if width == 4 else (1, 0, 0) * 3
    return f"{3 * width}f", values, {"componentType": 5126, "count": 3, "type": f"VEC{width}"}


@pytest.mark.parametrize("degrees", [90, -45, 360])
def test_a_texture_rotation_in_whole_degrees_is_a_warning(tmp_path, degrees):
    """gb01: KHR_texture_transform "rotation: Rotate the UVs by this many radians"; 90 is a quarter turn typed in a
    DCC's degrees, 90 radians 14.3 turns."""
    def rotated(rotation: float) -> dict:
        document = _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1})
        document["extensionsUsed"] = ["KHR_texture_transform"]
        document["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
            "KHR_texture_transform": {"rotation": rotation, "scale": [2, 2]}}
        return document

    broken = _write(tmp_path / "broken.gltf", rotated(degrees))
    fixed = _write(tmp_path / "fixed.gltf", rotated(math.radians(degrees)))
    _agree(tmp_path, broken, fixed, None, [("OPBR719", "warning", "/materials/0/pbrMetallicRoughness/baseColorTexture/"
                                                                   "extensions/KHR_texture_transform", "rotation")])
    assert findings(_write(tmp_path / "seven.gltf", rotated(7.0))) == []  # (session 15's good file: some radians)


def test_a_vec3_tangent_is_an_invalid_attribute_format(tmp_path):
    """gb02: glTF 2.0, 3.7.2.1: TANGENT is VEC4 (w the handedness)."""
    attributes = {"POSITION": 0, "NORMAL": 1, "TANGENT": 2, "TEXCOORD_0": 3}
    broken = _write(tmp_path / "broken.gltf", _triangle([_POSITION, _NORMAL, _tangents(3), _uvs()], attributes))
    fixed = _write(tmp_path / "fixed.gltf", _triangle([_POSITION, _NORMAL, _tangents(4), _uvs()], attributes))
    _agree(tmp_path, broken, fixed, "MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT",
           [("OPBR1217", "error", _PRIMITIVE, "TANGENT")])


def test_a_float_accessor_marked_normalized_is_an_invalid_attribute_format(tmp_path):
    """gb03: accessor.normalized "MUST NOT be set to true for accessors with FLOAT ... component type"."""
    broken = _write(tmp_path / "broken.gltf", _triangle([_POSITION, _uvs(normalized=True)], {"POSITION": 0, "TEXCOORD_0": 1}))
    fixed = _write(tmp_path / "fixed.gltf", _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1}))
    _agree(tmp_path, broken, fixed, "ACCESSOR_NORMALIZED_INVALID", [("OPBR1217", "error", _PRIMITIVE, "TEXCOORD_0")])


def test_tangents_without_normals_are_an_error(tmp_path):
    """gb04: 3.7.2.1, "When normals are not specified, client implementations MUST calculate flat normals and the
    provided tangents (if present) MUST be ignored" (the validator: a warning)."""
    broken = _write(tmp_path / "broken.gltf", _triangle([_POSITION, _tangents(4), _uvs()],
                                                        {"POSITION": 0, "TANGENT": 1, "TEXCOORD_0": 2}))
    fixed = _write(tmp_path / "fixed.gltf", _triangle([_POSITION, _NORMAL, _tangents(4), _uvs()],
                                                      {"POSITION": 0, "NORMAL": 1, "TANGENT": 2, "TEXCOORD_0": 3}))
    _agree(tmp_path, broken, fixed, "MESH_PRIMITIVE_TANGENT_WITHOUT_NORMAL", [("OPBR1218", "error", _PRIMITIVE, "TANGENT")],
           warning=True)


def _ktx2_uastc(vk_format: int = 0, color_model: int = 166) -> bytes:
    """A 4 x 4 KTX v2 file of one level: by default UASTC (DFD colour model 166, vkFormat 0, no supercompression),
    one 16-byte block; the header, level index and data format descriptor as the KTX 2.0 specification lays them out."""
    dfd_offset, dfd_length, data_offset = 104, 44, 160
    header = b"\xabKTX 20\xbb\r\n\x1a\n" + struct.pack("<9I", vk_format, 1, 4, 4, 0, 0, 1, 1, 0)
    index = struct.pack("<4I2Q", dfd_offset, dfd_length, 0, 0, 0, 0) + struct.pack("<3Q", data_offset, 16, 16)
    basic = struct.pack("<2I4B4B8B", 0, (40 << 16) | 2, color_model, 1, 2, 0, 3, 3, 0, 0, 16, 0, 0, 0, 0, 0, 0, 0)
    sample = struct.pack("<I4BII", 127 << 16 | 3 << 24, 0, 0, 0, 0, 0, 0xFFFFFFFF)
    dfd = struct.pack("<I", dfd_length) + basic + sample
    body = header + index + dfd
    return body + bytes(data_offset - len(body)) + bytes(16)


@pytest.mark.parametrize("payload, expected", [
    (b"sB\x13\x00" + bytes(60), "no KTX v2 file (a pre-ratification .basis file)"),  # gb05: a legacy .basis file
    (_ktx2_uastc(vk_format=43, color_model=1), "raw texels (vkFormat 43"),  # gb06: toktx without --encode
    (_ktx2_uastc(color_model=1), "colour model is 1"),
])
def test_a_basisu_source_without_a_basis_universal_payload_is_an_error(tmp_path, payload, expected):
    """KHR_texture_basisu: "a reference to the KTX v2 image with Basis Universal supercompression" (ETC1S with
    BasisLZ, or UASTC). The Khronos validator (2.0.0-dev.3.10) does not decode KTX2, so reports neither."""
    def basisu(image: bytes) -> dict:
        document = _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1})
        (tmp_path / "albedo.ktx2").write_bytes(image)
        document.update(extensionsUsed=["KHR_texture_basisu"], extensionsRequired=["KHR_texture_basisu"],
                        images=[{"uri": "albedo.ktx2", "mimeType": "image/ktx2"}],
                        textures=[{"extensions": {"KHR_texture_basisu": {"source": 0}}}])
        return document

    required = ("OPBR1202", "warning", "/extensionsRequired/0", None)  # (the toolkit does not decode KTX2)
    fixed = _write(tmp_path / "fixed.gltf", basisu(_ktx2_uastc()))
    assert findings(fixed) == [required]
    repaired = khronos_errors(fixed, tmp_path)
    broken = _write(tmp_path / "broken.gltf", basisu(payload))
    assert findings(broken) == [required, ("OPBR1220", "error", "/textures/0/extensions/KHR_texture_basisu", "source")]
    assert expected in messages(broken, "OPBR1220")[0]
    errors = khronos_errors(broken, tmp_path)
    if errors is not None:
        assert errors == set() and repaired == set(), (errors, repaired)


def _glb(document: dict, binary: bytes) -> bytes:
    text = json.dumps(document).encode("utf-8")
    text += b" " * (-len(text) % 4)
    binary += bytes(-len(binary) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def test_an_image_buffer_view_with_a_byte_stride_is_invalid(tmp_path):
    """gb10: glTF 2.0, 3.6.1.1: "Buffer views with other types of data MUST NOT not define byteStride"."""
    def embedded(stride: bool) -> bytes:
        document = _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1})
        data = base64.b64decode(document["buffers"][0]["uri"].split(",", 1)[1])
        view = {"buffer": 0, "byteOffset": len(data), "byteLength": len(_PNG_BYTES)}
        if stride:
            view["byteStride"] = 4
        document["bufferViews"].append(view)
        document["buffers"] = [{"byteLength": len(data) + len(_PNG_BYTES)}]
        document["images"] = [{"bufferView": len(document["bufferViews"]) - 1, "mimeType": "image/png"}]
        return _glb(document, data + _PNG_BYTES)

    broken, fixed = tmp_path / "broken.glb", tmp_path / "fixed.glb"
    broken.write_bytes(embedded(True))
    fixed.write_bytes(embedded(False))
    _agree(tmp_path, broken, fixed, "IMAGE_BUFFER_VIEW_WITH_BYTESTRIDE", [("OPBR1210", "error", "/images/0", "bufferView")])


def test_a_draco_object_without_its_buffer_view_is_invalid(tmp_path):
    """gb11: KHR_draco_mesh_compression's schema requires bufferView and attributes (the validator does not check)."""
    def draco(view: bool) -> dict:
        document = _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1})
        extension = {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}}
        if view:
            extension["bufferView"] = 1
        document["meshes"][0]["primitives"][0]["extensions"] = {"KHR_draco_mesh_compression": extension}
        document["extensionsUsed"] = ["KHR_draco_mesh_compression"]
        return document

    broken = _write(tmp_path / "broken.gltf", draco(False))
    fixed = _write(tmp_path / "fixed.gltf", draco(True))
    assert findings(broken) == [("OPBR1210", "error", "/meshes/0/primitives/0/extensions/KHR_draco_mesh_compression", None)]
    assert findings(fixed) == []
    errors = khronos_errors(broken, tmp_path)
    if errors is not None:
        assert not any(code.startswith("KHR_DRACO") for code in errors | khronos_warnings(broken, tmp_path))


def test_vertex_colours_of_unnormalised_unsigned_bytes_are_an_invalid_attribute_format(tmp_path):
    """gb12: 3.7.2.1: COLOR_n is float, or unsigned byte or short *normalized*."""
    def coloured(normalized: bool) -> dict:
        colours = ("12B", (255, 128, 0, 255) * 3, {"componentType": 5121, "count": 3, "type": "VEC4", "normalized": normalized})
        return _triangle([_POSITION, _uvs(), colours], {"POSITION": 0, "TEXCOORD_0": 1, "COLOR_0": 2})

    broken = _write(tmp_path / "broken.gltf", coloured(False))
    fixed = _write(tmp_path / "fixed.gltf", coloured(True))
    _agree(tmp_path, broken, fixed, "MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT",
           [("OPBR1217", "error", _PRIMITIVE, "COLOR_0")])


def test_texture_coordinate_sets_with_a_gap_are_an_error(tmp_path):
    """gb14: 3.7.2.1: "All indices for indexed attribute semantics MUST start with 0 and be consecutive positive
    integers"; the repaired file renumbers TEXCOORD_2 to TEXCOORD_1 and the emissive texture's texCoord with it."""
    def sets(last: int) -> dict:
        document = _triangle([_POSITION, _uvs(), _uvs()], {"POSITION": 0, "TEXCOORD_0": 1, f"TEXCOORD_{last}": 2})
        document["materials"][0].update(emissiveTexture={"index": 0, "texCoord": last}, emissiveFactor=[1, 1, 1])
        return document

    broken = _write(tmp_path / "broken.gltf", sets(2))
    fixed = _write(tmp_path / "fixed.gltf", sets(1))
    _agree(tmp_path, broken, fixed, "MESH_PRIMITIVE_INDEXED_SEMANTIC_CONTINUITY",
           [("OPBR1205", "error", _PRIMITIVE, "TEXCOORD_2")])


def test_quantized_normals_and_tangents_are_allowed_with_mesh_quantization(tmp_path):
    """KHR_mesh_quantization adds normalised BYTE NORMAL and TANGENT (each element padded to 4 bytes): no finding."""
    normals = ("12b", (0, 0, 127, 0) * 3, {"componentType": 5120, "normalized": True, "count": 3, "type": "VEC3"})
    tangents = ("12b", (127, 0, 0, 127) * 3, {"componentType": 5120, "normalized": True, "count": 3, "type": "VEC4"})
    document = _triangle([_POSITION, normals, tangents, _uvs()], {"POSITION": 0, "NORMAL": 1, "TANGENT": 2, "TEXCOORD_0": 3})
    document["bufferViews"][1]["byteStride"] = 4
    document.update(extensionsUsed=["KHR_mesh_quantization"], extensionsRequired=["KHR_mesh_quantization"])
    path = _write(tmp_path / "quantized.gltf", document)
    assert findings(path) == []
    errors = khronos_errors(path, tmp_path)
    assert errors is None or errors == set(), errors
    del document["extensionsUsed"], document["extensionsRequired"]
    assert [f[0] for f in findings(_write(tmp_path / "plain.gltf", document))] == ["OPBR1217", "OPBR1217"]
