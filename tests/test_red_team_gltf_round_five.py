"""The fifth red-team round's glTF files (session 19, E: written without reading this code) that the toolkit
passed: declarations, JSON, buffers and vertex data glTF forbids or discourages. Each test writes the red team's
defect pattern into a small file of its own and the repaired file beside it, and expects the finding on the first
and silence on the second. Where the Khronos glTF-Validator has a verdict it is the anchor (its error code on the
broken file, none on the repaired one; run when OPENPBR_GLTF_VALIDATOR is set); where it has none (a texture
extension left optional, a repeated JSON name), the extension's README and the JSON Encoding section of glTF 2.0
are, and the test checks that the validator indeed reports no error on either file."""

from __future__ import annotations

import base64
import json
import math
import struct
from pathlib import Path

import pytest

from openpbr_tools.io.gltf.accessors import UNIT_TOLERANCE
from openpbr_tools.io.gltf.reader import read_gltf
from redteam_support import findings, khronos_errors

_PNG = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mM8kWLEAANMDEgANwcA"
        "RfYBZsiXQosAAAAASUVORK5CYII=")
_WEBP = "data:image/webp;base64,UklGRh4AAABXRUJQVlA4TBEAAAAvA8AAAAdQiirUo/+BiOh/AAA="
_POSITIONS = (0, 0, 0, 1, 0, 0, 0, 1, 0)
_NORMALS = (0, 0, 1) * 3
_UVS = (0, 0, 1, 0, 0, 1)


def _agree(tmp_path, broken: Path, fixed: Path, khronos_code: str | None, expected: list) -> None:
    """``broken`` has exactly the findings ``expected`` (code, severity, pointer, property) and ``fixed`` none; the
    Khronos validator reports ``khronos_code`` as an error on the first and not on the second (with ``None``: no
    error on either, the validator not checking this)."""
    assert findings(broken) == expected, findings(broken)
    assert findings(fixed) == []
    errors = khronos_errors(broken, tmp_path)
    if errors is None:
        return
    repaired = khronos_errors(fixed, tmp_path)
    if khronos_code is None:
        assert errors == set() and repaired == set(), (errors, repaired)
    else:
        assert khronos_code in errors, errors
        assert khronos_code not in repaired, repaired


def _write(path: Path, document: dict) -> Path:
    path.write_text(json.dumps(document, indent=1), encoding="utf-8")
    return path


def _triangle(columns: list[tuple[str, tuple, dict]], attributes: dict, indices: int | None = None,
              media_type: str = "application/octet-stream") -> dict:
    """A textured triangle drawn with material 0. ``columns`` are the accessors, in order, each
    ``(struct format, values, accessor members)`` in a bufferView of its own; ``attributes`` name them by index."""
    data, views, accessors = b"", [], []
    for number, (layout, values, members) in enumerate(columns):
        packed = struct.pack("<" + layout, *values)
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(packed)})
        accessors.append({"bufferView": number, **members})
        data += packed + bytes(-len(packed) % 4)
    primitive = {"attributes": attributes, "material": 0}
    if indices is not None:
        primitive["indices"] = indices
    return {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "buffers": [{"byteLength": len(data), "uri": f"data:{media_type};base64," + base64.b64encode(data).decode("ascii")}],
        "bufferViews": views, "accessors": accessors,
        "images": [{"uri": _PNG}], "textures": [{"source": 0}],
        "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "meshes": [{"primitives": [primitive]}],
    }


_POSITION = ("9f", _POSITIONS, {"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]})


def _uvs(values=_UVS) -> tuple:
    return "6f", values, {"componentType": 5126, "count": 3, "type": "VEC2"}


def _normals(values=_NORMALS) -> tuple:
    return "9f", values, {"componentType": 5126, "count": 3, "type": "VEC3"}


def test_a_webp_only_texture_with_the_extension_optional_is_a_warning(tmp_path):
    """gb02: no core source, and EXT_texture_webp in extensionsUsed only (its README: "Using Without a Fallback")."""
    def webp_only(required: bool) -> dict:
        document = _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1})
        document.update(images=[{"uri": _WEBP}], textures=[{"extensions": {"EXT_texture_webp": {"source": 0}}}],
                        extensionsUsed=["EXT_texture_webp"])
        if required:
            document["extensionsRequired"] = ["EXT_texture_webp"]
        return document

    broken = _write(tmp_path / "broken.gltf", webp_only(False))
    fixed = _write(tmp_path / "fixed.gltf", webp_only(True))
    _agree(tmp_path, broken, fixed, None, [("OPBR1229", "warning", "/textures/0/extensions/EXT_texture_webp", None)])


def test_a_webp_texture_with_a_png_fallback_may_leave_the_extension_optional(tmp_path):
    """The README's own advice for a texture with a fallback: "this extension should not be present in
    extensionsRequired"."""
    document = _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1})
    document.update(images=[{"uri": _PNG}, {"uri": _WEBP}], extensionsUsed=["EXT_texture_webp"],
                    textures=[{"source": 0, "extensions": {"EXT_texture_webp": {"source": 1}}}])
    assert findings(_write(tmp_path / "fallback.gltf", document)) == []


def _quantized(required: bool) -> dict:
    """gb03: texture coordinates as normalised SHORT (gltfpack's quantisation)."""
    uvs = ("6h", (0, 0, 32767, 0, 0, 32767), {"componentType": 5122, "normalized": True, "count": 3, "type": "VEC2"})
    document = _triangle([_POSITION, uvs], {"POSITION": 0, "TEXCOORD_0": 1})
    document["extensionsUsed"] = ["KHR_mesh_quantization"]
    if required:
        document["extensionsRequired"] = ["KHR_mesh_quantization"]
    return document


def test_mesh_quantization_listed_as_optional_is_an_undeclared_requirement(tmp_path):
    broken = _write(tmp_path / "broken.gltf", _quantized(False))
    fixed = _write(tmp_path / "fixed.gltf", _quantized(True))
    _agree(tmp_path, broken, fixed, "NON_REQUIRED_EXTENSION", [("OPBR1201", "error", "/extensionsUsed/0", None)])


def test_a_property_written_twice_in_a_material_is_a_warning_and_the_last_is_read(tmp_path):
    """gb06: a merge script's second pbrMetallicRoughness (glTF 2.0, JSON Encoding: names SHOULD be unique, clients
    SHOULD keep the last)."""
    document = _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1})
    document["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = 0.0
    fixed = _write(tmp_path / "fixed.gltf", document)
    text = fixed.read_text(encoding="utf-8")
    first = '"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1.0], "metallicFactor": 1.0},\n'
    broken = tmp_path / "broken.gltf"
    broken.write_text(text.replace('"pbrMetallicRoughness": {', first + '   "pbrMetallicRoughness": {', 1), encoding="utf-8")
    assert text.count("pbrMetallicRoughness") == 1 and broken.read_text(encoding="utf-8").count("pbrMetallicRoughness") == 2
    _agree(tmp_path, broken, fixed, None, [("OPBR1230", "warning", "/materials/0/pbrMetallicRoughness", None)])
    (material,) = read_gltf(str(broken)).materials
    assert material.inputs["metallic"].constant == 0.0  # the lexically last value, as the specification asks


@pytest.mark.parametrize("value", [math.nan, math.inf])
def test_texture_coordinates_that_are_not_finite_are_flagged_at_the_accessor(tmp_path, value):
    """gb07: a degenerate unwrap wrote NaN (glTF 2.0, 3.6.2.2: NaN and infinities MUST NOT be present)."""
    broken = _write(tmp_path / "broken.gltf", _triangle([_POSITION, _uvs((0, 0, 1, 0, value, 1))],
                                                        {"POSITION": 0, "TEXCOORD_0": 1}))
    fixed = _write(tmp_path / "fixed.gltf", _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1}))
    _agree(tmp_path, broken, fixed, "ACCESSOR_INVALID_FLOAT", [("OPBR1231", "error", "/accessors/1", None)])


def test_normals_of_length_two_and_a_half_are_flagged_at_the_attribute(tmp_path):
    """gb08: an object scale of 2.5 baked into the normals (3.7.2.1: NORMAL is normalised)."""
    attributes = {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}
    broken = _write(tmp_path / "broken.gltf", _triangle([_POSITION, _normals((0, 0, 2.5) * 3), _uvs()], attributes))
    fixed = _write(tmp_path / "fixed.gltf", _triangle([_POSITION, _normals(), _uvs()], attributes))
    _agree(tmp_path, broken, fixed, "ACCESSOR_VECTOR3_NON_UNIT",
           [("OPBR1231", "error", "/meshes/0/primitives/0/attributes", "NORMAL")])


def test_normals_quantised_to_bytes_are_unit_length_within_the_validators_tolerance(tmp_path):
    """KHR_mesh_quantization's normalised BYTE normals: (90, 90, 0) / 127 has length 1.0022, inside the validator's
    threshold, so clean; (91, 91, 0) / 127, 1.0134, is not."""
    assert abs(math.hypot(90, 90) / 127 - 1) < UNIT_TOLERANCE < abs(math.hypot(91, 91) / 127 - 1)

    def quantized(xy: int) -> dict:
        normals = ("12b", (127, 0, 0, 0, xy, xy, 0, 0, 0, 127, 0, 0),  # (each VEC3 of bytes padded to 4: 3.6.2.4)
                   {"componentType": 5120, "normalized": True, "count": 3, "type": "VEC3"})
        document = _triangle([_POSITION, normals, _uvs()], {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2})
        document["bufferViews"][1]["byteStride"] = 4
        document.update(extensionsUsed=["KHR_mesh_quantization"], extensionsRequired=["KHR_mesh_quantization"])
        return document

    clean = _write(tmp_path / "clean.gltf", quantized(90))
    too_long = _write(tmp_path / "too_long.gltf", quantized(91))
    _agree(tmp_path, too_long, clean, "ACCESSOR_VECTOR3_NON_UNIT",
           [("OPBR1231", "error", "/meshes/0/primitives/0/attributes", "NORMAL")])


@pytest.mark.parametrize("media_type", ["text/plain", "image/png", ""])
def test_a_buffer_data_uri_of_another_media_type_is_a_broken_resource(tmp_path, media_type):
    """gb10: glTF 2.0, 3.6.1: the data URI's mediatype MUST be application/octet-stream or application/gltf-buffer."""
    columns, attributes = [_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1}
    broken = _write(tmp_path / "broken.gltf", _triangle(columns, attributes, media_type=media_type))
    fixed = _write(tmp_path / "fixed.gltf", _triangle(columns, attributes, media_type="application/gltf-buffer"))
    _agree(tmp_path, broken, fixed, "BUFFER_DATA_URI_MIME_TYPE_INVALID", [("OPBR1209", "error", "/buffers/0/uri", None)])


def test_an_accessor_longer_than_its_buffer_view_is_flagged_at_its_count(tmp_path):
    """gb12: TEXCOORD_0 counts 3 elements where its view holds 2 (3.6.2.4: each accessor MUST fit its bufferView)."""
    short = ("4f", _UVS[:4], {"componentType": 5126, "count": 3, "type": "VEC2"})
    broken = _write(tmp_path / "broken.gltf", _triangle([_POSITION, short], {"POSITION": 0, "TEXCOORD_0": 1}))
    fixed = _write(tmp_path / "fixed.gltf", _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1}))
    _agree(tmp_path, broken, fixed, "ACCESSOR_TOO_LONG", [("OPBR1228", "error", "/accessors/1", "count")])


def _indexed(last: int) -> dict:
    """gb13: one triangle through an UNSIGNED_SHORT index accessor whose last index is ``last``."""
    indices = ("3H", (0, 1, last), {"componentType": 5123, "count": 3, "type": "SCALAR"})
    return _triangle([_POSITION, _uvs(), indices], {"POSITION": 0, "TEXCOORD_0": 1}, indices=2)


def test_indices_that_reach_the_vertex_count_are_flagged_at_the_primitive(tmp_path):
    """3.7.2.1: "all index values MUST be less than attribute accessors' count" (3 vertices: 0 to 2)."""
    broken = _write(tmp_path / "broken.gltf", _indexed(3))
    fixed = _write(tmp_path / "fixed.gltf", _indexed(2))
    _agree(tmp_path, broken, fixed, "ACCESSOR_INDEX_OOB", [("OPBR1228", "error", "/meshes/0/primitives/0", "indices")])


def test_a_null_texture_info_is_an_invalid_property(tmp_path):
    """gb14: a Python exporter's None written as "normalTexture": null (the schema: an object)."""
    document = _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1})
    broken_document = json.loads(json.dumps(document))
    broken_document["materials"][0]["normalTexture"] = None
    broken = _write(tmp_path / "broken.gltf", broken_document)
    fixed = _write(tmp_path / "fixed.gltf", document)
    _agree(tmp_path, broken, fixed, "TYPE_MISMATCH", [("OPBR1210", "error", "/materials/0/normalTexture", None)])


def test_variants_written_as_plain_strings_are_invalid(tmp_path):
    """gb15: the root's variants as ["Red", "Blue"] instead of objects with a name."""
    def variants(listed: list) -> dict:
        document = _triangle([_POSITION, _uvs()], {"POSITION": 0, "TEXCOORD_0": 1})
        document["extensionsUsed"] = ["KHR_materials_variants"]
        document["extensions"] = {"KHR_materials_variants": {"variants": listed}}
        document["materials"] += [{"name": "red"}, {"name": "blue"}]
        document["meshes"][0]["primitives"][0]["extensions"] = {"KHR_materials_variants": {"mappings": [
            {"material": 1, "variants": [0]}, {"material": 2, "variants": [1]}]}}
        return document

    broken = _write(tmp_path / "broken.gltf", variants(["Red", "Blue"]))
    fixed = _write(tmp_path / "fixed.gltf", variants([{"name": "Red"}, {"name": "Blue"}]))
    pointer = "/extensions/KHR_materials_variants/variants/"
    _agree(tmp_path, broken, fixed, "ARRAY_TYPE_MISMATCH",
           [("OPBR1210", "error", pointer + "0", None), ("OPBR1210", "error", pointer + "1", None)])


def test_an_accessor_two_primitives_share_is_reported_once(tmp_path):
    document = _triangle([_POSITION, _uvs((0, 0, 1, 0, math.nan, 1))], {"POSITION": 0, "TEXCOORD_0": 1})
    document["meshes"][0]["primitives"].append(dict(document["meshes"][0]["primitives"][0]))
    assert findings(_write(tmp_path / "shared.gltf", document)) == [("OPBR1231", "error", "/accessors/1", None)]


def test_the_data_of_a_primitive_without_a_material_is_not_read(tmp_path):
    """The cost stays with the material's geometry: a primitive the file's materials do not shade is not judged."""
    document = _triangle([_POSITION, _uvs((0, 0, 1, 0, math.nan, 1)), ("3H", (0, 1, 7), {"componentType": 5123, "count": 3,
                                                                                        "type": "SCALAR"})],
                         {"POSITION": 0, "TEXCOORD_0": 1}, indices=2)
    del document["meshes"][0]["primitives"][0]["material"]
    assert findings(_write(tmp_path / "unshaded.gltf", document)) == []


def test_the_vertex_values_rules_documented_examples_agree_with_the_khronos_validator(tmp_path):
    from openpbr_tools.rules import all_rules

    rule = all_rules()["OPBR1231"]
    failing, passing = tmp_path / "failing.gltf", tmp_path / "passing.gltf"
    failing.write_text(rule.failing, encoding="utf-8")
    passing.write_text(rule.passing, encoding="utf-8")
    errors = khronos_errors(failing, tmp_path)
    if errors is None:
        pytest.skip("OPENPBR_GLTF_VALIDATOR is not set")
    assert "ACCESSOR_INVALID_FLOAT" in errors
    assert khronos_errors(passing, tmp_path) == set()
