"""The fourth red-team round's glTF files (session 18, D: written without reading this code): layouts and
references the Khronos glTF-Validator reports as errors and the toolkit said nothing about. Each test writes
the red team's defect pattern into a small file of its own and the repaired file beside it; the anchor is the
validator (its error code on the broken file, none on the repaired one), run when OPENPBR_GLTF_VALIDATOR is set."""

from __future__ import annotations

import base64
import json
import os
import struct
from pathlib import Path

import pytest

from redteam_support import findings as _findings
from redteam_support import khronos_errors as _khronos_errors

_PNG = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mM8kWLEAANMDEgANwcA"
        "RfYBZsiXQosAAAAASUVORK5CYII=")
_WEBP = "data:image/webp;base64,UklGRh4AAABXRUJQVlA4TBEAAAAvA8AAAAdQiirUo/+BiOh/AAA="
_POSITIONS = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
_UVS = struct.pack("<6f", 0, 0, 1, 0, 0, 1)


def _agree(tmp_path, broken: Path, fixed: Path, khronos_code: str, expected: tuple) -> None:
    """``broken`` has exactly the finding ``expected`` (code, severity, pointer, property) and ``fixed`` none;
    the Khronos validator reports ``khronos_code`` as an error on the first and not on the second."""
    assert _findings(broken) == [expected], _findings(broken)
    assert _findings(fixed) == []
    errors = _khronos_errors(broken, tmp_path)
    if errors is not None:
        assert khronos_code in errors, errors
        assert khronos_code not in _khronos_errors(fixed, tmp_path)


def _write(path: Path, document: dict) -> Path:
    path.write_text(json.dumps(document, indent=1), encoding="utf-8")
    return path


def _triangle(data: bytes, views: list, accessors: list, attributes: dict, **members) -> dict:
    """A textured triangle whose buffer is ``data`` (a data URI); POSITION is accessor 0."""
    uri = "data:application/octet-stream;base64," + base64.b64encode(data).decode("ascii")
    document = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "buffers": [{"byteLength": len(data), "uri": uri}], "bufferViews": views,
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0],
                       "max": [1, 1, 0]}] + accessors,
        "images": [{"uri": _PNG}], "textures": [{"source": 0}],
        "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, **attributes}, "material": 0}]}],
    }
    document.update(members)
    return document


def _planar(texcoord: dict, uv_data: bytes = _UVS, pad: int = 0) -> dict:
    """Positions in view 0, texture coordinates (``texcoord``: accessor 1) in view 1."""
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 36, "target": 34962},
             {"buffer": 0, "byteOffset": 36, "byteLength": len(uv_data) + pad, "target": 34962}]
    accessor = {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2", **texcoord}
    return _triangle(_POSITIONS + uv_data + bytes(pad), views, [accessor], {"TEXCOORD_0": 1})


def test_a_texcoord_accessor_at_an_offset_no_multiple_of_four_is_flagged_at_the_accessor(tmp_path):
    """gb08: a FLOAT TEXCOORD_0 at byteOffset 2 (glTF 2.0 3.6.2.4)."""
    broken = _write(tmp_path / "broken.gltf", _planar({"byteOffset": 2}, bytes(2) + _UVS, pad=2))
    fixed = _write(tmp_path / "fixed.gltf", _planar({"byteOffset": 4}, bytes(4) + _UVS))
    _agree(tmp_path, broken, fixed, "ACCESSOR_OFFSET_ALIGNMENT", ("OPBR1228", "error", "/accessors/1", "byteOffset"))


def _interleaved(stride: int) -> dict:
    """gb14: POSITION and TEXCOORD_0 interleaved, 20 bytes a vertex, in one view of byteStride ``stride``."""
    data = b"".join(_POSITIONS[12 * i:12 * i + 12] + _UVS[8 * i:8 * i + 8] for i in range(3))
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 60, "byteStride": stride, "target": 34962}]
    document = _triangle(data, views, [{"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 3,
                                        "type": "VEC2"}], {"TEXCOORD_0": 1})
    return document


def test_a_byte_stride_smaller_than_an_element_is_flagged_at_each_accessor_it_overlaps(tmp_path):
    broken = _write(tmp_path / "broken.gltf", _interleaved(8))
    fixed = _write(tmp_path / "fixed.gltf", _interleaved(20))
    # the VEC3 positions (12 bytes) overlap at stride 8; the VEC2 texture coordinates (8 bytes) fit
    _agree(tmp_path, broken, fixed, "ACCESSOR_SMALL_BYTESTRIDE", ("OPBR1228", "error", "/accessors/0", "bufferView"))


def _sparse(indices: tuple[int, int]) -> dict:
    """gb05/gb06: TEXCOORD_0 with two sparse substitutions at ``indices`` (UNSIGNED_SHORT)."""
    values = struct.pack("<4f", 0.5, 0.5, 0.25, 0.25)
    data = _POSITIONS + _UVS + struct.pack("<2H", *indices) + values
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24},
             {"buffer": 0, "byteOffset": 60, "byteLength": 4}, {"buffer": 0, "byteOffset": 64, "byteLength": 16}]
    sparse = {"count": 2, "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 3}}
    return _triangle(data, views, [{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2",
                                    "sparse": sparse}], {"TEXCOORD_0": 1})


@pytest.mark.parametrize("indices, khronos_code", [
    ((2, 1), "ACCESSOR_SPARSE_INDICES_NON_INCREASING"),  # two entries swapped by an optimiser
    ((1, 3), "ACCESSOR_SPARSE_INDEX_OOB"),  # 3 with count 3 (valid 0..2)
])
def test_sparse_indices_must_strictly_increase_and_stay_below_the_count(tmp_path, indices, khronos_code):
    broken = _write(tmp_path / "broken.gltf", _sparse(indices))
    fixed = _write(tmp_path / "fixed.gltf", _sparse((1, 2)))
    _agree(tmp_path, broken, fixed, khronos_code, ("OPBR1228", "error", "/accessors/1/sparse", "indices"))


def test_a_texcoord_with_fewer_elements_than_the_positions_is_flagged_at_the_attribute(tmp_path):
    """gb15: UVs taken from another level of detail (glTF 2.0 3.7.2.1: all attributes the same count)."""
    broken = _write(tmp_path / "broken.gltf", _planar({"count": 2}))
    fixed = _write(tmp_path / "fixed.gltf", _planar({}))
    _agree(tmp_path, broken, fixed, "MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT",
           ("OPBR1228", "error", "/meshes/0/primitives/0/attributes", "TEXCOORD_0"))


def test_an_external_buffer_shorter_than_its_byte_length_is_a_broken_resource(tmp_path):
    """gb07: a truncated upload of the .bin beside the asset."""
    data = _POSITIONS + _UVS
    document = _planar({})
    for name, written in (("broken", data[:-16]), ("fixed", data)):
        (tmp_path / f"{name}.bin").write_bytes(written)
        document["buffers"] = [{"byteLength": len(data), "uri": f"{name}.bin"}]
        _write(tmp_path / f"{name}.gltf", document)
    _agree(tmp_path, tmp_path / "broken.gltf", tmp_path / "fixed.gltf", "BUFFER_BYTE_LENGTH_MISMATCH",
           ("OPBR1209", "error", "/buffers/0", None))


def _glb(path: Path, padded: bool) -> Path:
    """gb03: a GLB whose JSON chunk is, or is not, padded with spaces to a multiple of 4 bytes."""
    data = _POSITIONS + _UVS
    document = _planar({})
    document["buffers"] = [{"byteLength": len(data)}]
    # (no data-URI image inside the GLB: that is a warning of its own, DATA_URI_GLB / OPBR1237)
    del document["images"], document["textures"]
    document["materials"] = [{"name": "M"}]
    text = json.dumps(document, separators=(",", ":")).encode("utf-8")
    text += b" " * ((-len(text)) % 4 if padded else (1 if len(text) % 4 == 0 else 0))
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(data), 0x004E4942) + data
    path.write_bytes(b"glTF" + struct.pack("<II", 2, 12 + len(chunks)) + chunks)
    return path


def test_a_glb_json_chunk_not_padded_to_four_bytes_is_flagged(tmp_path):
    broken, fixed = _glb(tmp_path / "broken.glb", False), _glb(tmp_path / "fixed.glb", True)
    assert (len(broken.read_bytes()) - 28 - 60) % 4  # the JSON chunk's length is no multiple of 4
    _agree(tmp_path, broken, fixed, "GLB_CHUNK_LENGTH_UNALIGNED", ("OPBR1209", "error", "", None))


def _webp(source_uri: str) -> dict:
    """gb09: the texture's EXT_texture_webp source is image 1; its core source, image 0, a PNG fallback."""
    return {"asset": {"version": "2.0"}, "extensionsUsed": ["EXT_texture_webp"],
            "images": [{"uri": _PNG}, {"uri": source_uri}],
            "textures": [{"source": 0, "extensions": {"EXT_texture_webp": {"source": 1}}}],
            "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]}


def test_an_ext_texture_webp_source_that_is_a_png_is_flagged_at_the_source(tmp_path):
    broken = _write(tmp_path / "broken.gltf", _webp(_PNG))
    fixed = _write(tmp_path / "fixed.gltf", _webp(_WEBP))
    _agree(tmp_path, broken, fixed, "TEXTURE_INVALID_IMAGE_MIME_TYPE",
           ("OPBR1220", "error", "/textures/0/extensions/EXT_texture_webp", "source"))


def test_a_default_scene_that_names_no_scene_is_a_dangling_reference(tmp_path):
    """gb10: "scene": 1 with one scene."""
    broken = _write(tmp_path / "broken.gltf", _planar({}) | {"scene": 1})
    fixed = _write(tmp_path / "fixed.gltf", _planar({}))
    _agree(tmp_path, broken, fixed, "UNRESOLVED_REFERENCE", ("OPBR802", "error", "/scene", None))


def _variants(mappings: list, on_material: bool = False) -> dict:
    document = _planar({})
    document["extensionsUsed"] = ["KHR_materials_variants"]
    document["extensions"] = {"KHR_materials_variants": {"variants": [{"name": "Red"}, {"name": "Blue"}]}}
    document["materials"] += [{"name": "red"}, {"name": "blue"}]
    owner = document["materials"][0] if on_material else document["meshes"][0]["primitives"][0]
    owner["extensions"] = {"KHR_materials_variants": {"mappings": mappings}}
    return document


_MAPPINGS = [{"material": 1, "variants": [0]}, {"material": 2, "variants": [1]}]


def test_a_variants_mapping_without_variants_is_invalid(tmp_path):
    """gb02: a mapping left over after its variant was deleted (the schema's minItems 1)."""
    broken = _write(tmp_path / "broken.gltf", _variants(_MAPPINGS + [{"material": 0, "variants": []}]))
    fixed = _write(tmp_path / "fixed.gltf", _variants(_MAPPINGS))
    _agree(tmp_path, broken, fixed, "EMPTY_ENTITY",
           ("OPBR1210", "error", "/meshes/0/primitives/0/extensions/KHR_materials_variants/mappings/2/variants", None))


def test_variants_mappings_on_a_material_are_an_extension_out_of_place(tmp_path):
    """gb13: the mappings written inside the material's extensions never switch any material."""
    broken = _write(tmp_path / "broken.gltf", _variants(_MAPPINGS, on_material=True))
    fixed = _write(tmp_path / "fixed.gltf", _variants(_MAPPINGS))
    _agree(tmp_path, broken, fixed, "UNEXPECTED_EXTENSION_OBJECT",
           ("OPBR1210", "error", "/materials/0/extensions/KHR_materials_variants", None))


def test_a_sparse_accessor_without_a_buffer_view_and_a_morph_target_of_equal_count_stay_clean(tmp_path):
    """The red team's good files gg04 and gg10: sparse values over zeros, a morph target displacing the UVs."""
    document = _sparse((1, 2))
    del document["accessors"][1]["bufferView"]
    document["accessors"].append({"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"})
    document["meshes"][0]["primitives"][0]["targets"] = [{"TEXCOORD_0": 2}]
    document["meshes"][0]["weights"] = [0.5]
    path = _write(tmp_path / "clean.gltf", document)
    assert _findings(path) == []
    errors = _khronos_errors(path, tmp_path)
    assert errors is None or errors == set(), errors


@pytest.mark.parametrize("code, khronos_code", [
    ("OPBR1228", "MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT"),
])
def test_the_rules_documented_examples_agree_with_the_khronos_validator(tmp_path, code, khronos_code):
    """The failing example is an error to the validator too, and the passing one is free of errors."""
    from openpbr_tools.rules import all_rules

    if not os.environ.get("OPENPBR_GLTF_VALIDATOR"):
        pytest.skip("OPENPBR_GLTF_VALIDATOR is not set")
    rule = all_rules()[code]
    failing, passing = tmp_path / "failing.gltf", tmp_path / "passing.gltf"
    failing.write_text(rule.failing, encoding="utf-8")
    passing.write_text(rule.passing, encoding="utf-8")
    assert khronos_code in _khronos_errors(failing, tmp_path)
    assert _khronos_errors(passing, tmp_path) == set()
