"""The ninth red-team round's glTF files (session 22, S: "exported by a real tool") that the toolkit passed: a
normalTexture pointing at the base colour image, anisotropyRotation typed in degrees, an interleaved bufferView whose
byteStride is no multiple of 4, a sheenRoughnessTexture without the alpha channel it reads, and a MASK material whose
base colour texture never reaches alphaCutoff. Each test writes the defect into a small file of its own (not the red
team's files, which are held out) and a legal near miss beside it, and expects the finding on the first and silence
on the second. Where the Khronos glTF-Validator has a verdict (the byteStride) it is the anchor, run when
OPENPBR_GLTF_VALIDATOR is set; elsewhere the glTF specification and the extension READMEs are, and the validator,
which reads no texels and no angles, reports no error on either file."""

from __future__ import annotations

import base64
import json
import struct
from pathlib import Path

from PIL import Image

from redteam_support import findings, khronos_errors, messages


def _image(path: Path, mode: str, texels: list) -> str:
    """A 2 x 2 image of ``texels`` (row by row) at ``path``; its file name, for a glTF uri."""
    image = Image.new(mode, (2, 2))
    image.putdata(texels)
    image.save(path)
    return path.name


def _write(path: Path, document: dict) -> Path:
    path.write_text(json.dumps(document, indent=1), encoding="utf-8")
    return path


def _document(images: list[str], material: dict, used: tuple[str, ...] = (), **members) -> dict:
    """A glTF document whose one material reads texture n = image n."""
    document = {"asset": {"version": "2.0"}, "images": [{"uri": uri} for uri in images],
                "textures": [{"source": n} for n in range(len(images))], "materials": [{"name": "M", **material}],
                **members}
    if used:
        document["extensionsUsed"] = list(used)
    return document


# -- a normalTexture pointing at the base colour image ------------------------------------------------------------

_BROWN = [(150, 100, 50)] * 4  # an oak base colour: blue 50/255, decoded z = -0.61
_FLAT_NORMAL = [(128, 128, 255)] * 4


def test_normal_texture_sharing_the_base_colour_image_is_judged_as_a_normal_map(tmp_path):
    """glTF 2.0, 3.9.3: the normal texture's texels are "the XYZ components of a normal vector in tangent space",
    unpacked as 2 texel - 1 with +Z toward the viewer: a brown image read there gives z = 2 * 50 / 255 - 1 < 0. The
    base colour reads the same file first; the file being seen once must not hide its reading as a normal map."""
    colour = _image(tmp_path / "oak.png", "RGB", _BROWN)
    broken = _write(tmp_path / "broken.gltf", _document(
        [colour], {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "normalTexture": {"index": 0}}))
    assert findings(broken) == [("OPBR724", "error", "/materials/0/normalTexture", "index")]
    (message,) = messages(broken, "OPBR724")
    assert "-0.61" in message  # the mean z, 2 * 50 / 255 - 1
    normal = _image(tmp_path / "oak_normal.png", "RGB", _FLAT_NORMAL)
    fixed = _write(tmp_path / "fixed.gltf", _document(
        [colour, normal], {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "normalTexture": {"index": 1}}))
    assert findings(fixed) == []
    assert khronos_errors(broken, tmp_path) in (None, set())


def test_clearcoat_normal_texture_sharing_an_image_is_judged_too(tmp_path):
    colour = _image(tmp_path / "oak.png", "RGB", _BROWN)
    broken = _write(tmp_path / "coat.gltf", _document(
        [colour], {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}},
                   "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
                                                              "clearcoatNormalTexture": {"index": 0}}}},
        ("KHR_materials_clearcoat",)))
    assert [f[:2] for f in findings(broken)] == [("OPBR724", "error")]


# -- anisotropyRotation in degrees ---------------------------------------------------------------------------------

def _anisotropic(rotation) -> dict:
    return {"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_anisotropy"],
            "materials": [{"name": "Brass", "pbrMetallicRoughness": {"metallicFactor": 1.0, "roughnessFactor": 0.35},
                           "extensions": {"KHR_materials_anisotropy": {"anisotropyStrength": 0.6,
                                                                       "anisotropyRotation": rotation}}}]}


def test_anisotropy_rotation_of_90_is_degrees_where_the_extension_takes_radians(tmp_path):
    """KHR_materials_anisotropy: anisotropyRotation is "measured in radians counter-clockwise from the tangent"; 90
    radians is 14.3 turns, a quarter turn typed in degrees (OPBR719's judgement for KHR_texture_transform)."""
    broken = _write(tmp_path / "broken.gltf", _anisotropic(90))
    assert findings(broken) == [("OPBR719", "warning", "/materials/0/extensions/KHR_materials_anisotropy",
                                 "anisotropyRotation")]
    (message,) = messages(broken, "OPBR719")
    assert "14.3 turns" in message  # 90 / (2 pi)


def test_anisotropy_rotation_in_radians_or_an_odd_whole_number_stays_quiet(tmp_path):
    """A quarter turn in radians (1.5708) is what the extension asks for; 7, a whole number no degree UI offers,
    is some turn in radians (OPBR719 leaves it alone for KHR_texture_transform, and so here)."""
    for rotation in (1.5708, 7, -3.14159, 0):
        assert findings(_write(tmp_path / "fixed.gltf", _anisotropic(rotation))) == [], rotation


def test_coat_anisotropy_rotation_of_the_coat_draft_in_degrees(tmp_path):
    """The draft KHR_materials_coat's coatAnisotropyRotation follows KHR_materials_anisotropy's convention."""
    document = {"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_coat"],
                "materials": [{"name": "M", "extensions": {"KHR_materials_coat": {
                    "coatFactor": 1.0, "coatAnisotropyStrength": 0.5, "coatAnisotropyRotation": 45}}}]}
    assert ("OPBR719", "warning", "/materials/0/extensions/KHR_materials_coat", "coatAnisotropyRotation") in \
        findings(_write(tmp_path / "coat.gltf", document))
    document["materials"][0]["extensions"]["KHR_materials_coat"]["coatAnisotropyRotation"] = 0.7854
    assert findings(_write(tmp_path / "coat_fixed.gltf", document)) == []


# -- byteStride --------------------------------------------------------------------------------------------------

def _interleaved(stride: int, view_length: int | None = None) -> dict:
    """A triangle whose positions (float3) and UVs (float2) share one bufferView, ``stride`` bytes per vertex."""
    data = bytearray(stride * 2 + 20 + (-(stride * 2 + 20) % 4))
    for number, (position, uv) in enumerate((((0, 0, 0), (0, 0)), ((1, 0, 0), (1, 0)), ((0, 1, 0), (0, 1)))):
        struct.pack_into("<3f2f", data, number * stride, *position, *uv)
    return {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode("ascii")}],
        "bufferViews": [{"buffer": 0, "byteLength": view_length or len(data), "byteStride": stride, "target": 34962}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0],
                       "max": [1, 1, 0]},
                      {"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 3, "type": "VEC2"}],
        "materials": [{"name": "M"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}],
    }


def test_byte_stride_not_a_multiple_of_4_is_an_error(tmp_path):
    """bufferView.schema.json: byteStride "multipleOf": 4 (and 3.6.2.4: a vertex attribute's stride MUST be a
    multiple of 4); the validator's VALUE_MULTIPLE_OF, an error."""
    broken = _write(tmp_path / "broken.gltf", _interleaved(30))
    assert ("OPBR1228", "error", "/bufferViews/0", "byteStride") in findings(broken)
    fixed = _write(tmp_path / "fixed.gltf", _interleaved(32))
    assert findings(fixed) == []
    errors, repaired = khronos_errors(broken, tmp_path), khronos_errors(fixed, tmp_path)
    if errors is not None:
        assert "VALUE_MULTIPLE_OF" in errors and repaired == set(), (errors, repaired)


def test_byte_stride_above_252_is_an_error(tmp_path):
    """bufferView.schema.json: byteStride "maximum": 252; the validator's VALUE_NOT_IN_RANGE."""
    broken = _write(tmp_path / "broken.gltf", _interleaved(256))
    assert ("OPBR1228", "error", "/bufferViews/0", "byteStride") in findings(broken)
    errors = khronos_errors(broken, tmp_path)
    if errors is not None:
        assert "VALUE_NOT_IN_RANGE" in errors


def test_byte_stride_longer_than_its_view_is_an_error(tmp_path):
    """The validator's BUFFER_VIEW_TOO_BIG_BYTE_STRIDE: a view of 16 bytes cannot step 20 bytes per vertex."""
    broken = _write(tmp_path / "broken.gltf", _interleaved(20, view_length=16))
    assert ("OPBR1228", "error", "/bufferViews/0", "byteStride") in findings(broken)
    errors = khronos_errors(broken, tmp_path)
    if errors is not None:
        assert "BUFFER_VIEW_TOO_BIG_BYTE_STRIDE" in errors


def test_tightly_packed_vertex_colours_of_6_bytes_are_unaligned(tmp_path):
    """3.6.2.4: a vertex attribute's elements are aligned to 4 bytes; normalised unsigned-short RGB colours packed
    without a byteStride are 6 bytes apart (the validator's MESH_PRIMITIVE_ACCESSOR_UNALIGNED), padded to a stride
    of 8 they are not."""
    def coloured(stride: int | None) -> dict:
        document = _interleaved(20)
        data = bytearray(base64.b64decode(document["buffers"][0]["uri"].split(",", 1)[1]))
        offset = len(data)
        step = stride or 6
        colours = bytearray(step * 3 + (-(step * 3) % 4))
        for number in range(3):
            struct.pack_into("<3H", colours, number * step, 65535, 65535, 65535)
        data += colours
        document["buffers"][0] = {"byteLength": len(data), "uri": "data:application/octet-stream;base64,"
                                  + base64.b64encode(data).decode("ascii")}
        view = {"buffer": 0, "byteOffset": offset, "byteLength": step * 2 + 6, "target": 34962}
        if stride:
            view["byteStride"] = stride
        document["bufferViews"].append(view)
        document["accessors"].append({"bufferView": 1, "componentType": 5123, "normalized": True, "count": 3,
                                      "type": "VEC3"})
        document["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 2
        return document

    broken = _write(tmp_path / "broken.gltf", coloured(None))
    assert findings(broken) == [("OPBR1228", "error", "/accessors/2", "byteOffset")]
    fixed = _write(tmp_path / "fixed.gltf", coloured(8))
    assert findings(fixed) == []
    errors, repaired = khronos_errors(broken, tmp_path), khronos_errors(fixed, tmp_path)
    if errors is not None:
        assert "MESH_PRIMITIVE_ACCESSOR_UNALIGNED" in errors and repaired == set(), (errors, repaired)


# -- textures read from alpha alone --------------------------------------------------------------------------------

_GREY = [(128, 128, 128)] * 4


def _sheen(image: str) -> dict:
    return _document([image], {"extensions": {"KHR_materials_sheen": {
        "sheenColorFactor": [0.9, 0.85, 0.8], "sheenRoughnessFactor": 1.0, "sheenRoughnessTexture": {"index": 0}}}},
        ("KHR_materials_sheen",))


def test_sheen_roughness_texture_without_alpha_has_no_effect(tmp_path):
    """KHR_materials_sheen: sheenRoughnessTexture holds the roughness "stored in the alpha (A) channel"; a JPEG has
    none, so every texel reads A = 1 and the texture changes nothing."""
    jpeg = tmp_path / "fabric.jpg"
    Image.new("RGB", (2, 2), (128, 128, 128)).save(jpeg)
    broken = _write(tmp_path / "broken.gltf", _sheen(jpeg.name))
    assert findings(broken) == [("OPBR1211", "warning", "/materials/0/extensions/KHR_materials_sheen/"
                                 "sheenRoughnessTexture", "index")]
    rgba = _image(tmp_path / "fabric_rough.png", "RGBA", [(128, 128, 128, a) for a in (40, 90, 160, 220)])
    assert findings(_write(tmp_path / "fixed.gltf", _sheen(rgba))) == []
    assert khronos_errors(broken, tmp_path) in (None, set())


def test_diffuse_transmission_texture_without_alpha_has_no_effect(tmp_path):
    """KHR_materials_diffuse_transmission: diffuseTransmissionTexture "defines the strength ..., stored in the alpha
    (A) channel" (the extension is kept as data, not converted: its textures are judged from its JSON)."""
    def leaf(image: str) -> dict:
        return _document([image], {"pbrMetallicRoughness": {"metallicFactor": 0.0}, "extensions": {
            "KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 1.0,
                                                   "diffuseTransmissionTexture": {"index": 0}}}},
            ("KHR_materials_diffuse_transmission",))

    rgb = _image(tmp_path / "leaf.png", "RGB", _GREY)
    assert findings(_write(tmp_path / "broken.gltf", leaf(rgb))) == [
        ("OPBR1211", "warning", "/materials/0/extensions/KHR_materials_diffuse_transmission/diffuseTransmissionTexture",
         "index")]
    rgba = _image(tmp_path / "leaf_a.png", "RGBA", [(128, 128, 128, 128)] * 4)
    assert findings(_write(tmp_path / "fixed.gltf", leaf(rgba))) == []


def test_fuzz_roughness_texture_of_the_fuzz_draft_without_alpha(tmp_path):
    """The draft KHR_materials_fuzz reads fuzz roughness from A of fuzzRoughnessTexture (io/gltf/drafts.py)."""
    rgb = _image(tmp_path / "fuzz.png", "RGB", _GREY)
    document = _document([rgb], {"extensions": {"KHR_materials_fuzz": {"fuzzFactor": 1.0,
                                                                       "fuzzRoughnessTexture": {"index": 0}}}},
                         ("KHR_materials_fuzz",))
    assert ("OPBR1211", "warning", "/materials/0/extensions/KHR_materials_fuzz/fuzzRoughnessTexture", "index") in \
        findings(_write(tmp_path / "fuzz.gltf", document))


def test_sheen_colour_texture_reading_rgb_of_a_jpeg_stays_quiet(tmp_path):
    """sheenColorTexture reads RGB: a JPEG has all it needs."""
    jpeg = tmp_path / "fabric.jpg"
    Image.new("RGB", (2, 2), (128, 128, 128)).save(jpeg)
    document = _document([jpeg.name], {"extensions": {"KHR_materials_sheen": {
        "sheenColorFactor": [1, 1, 1], "sheenColorTexture": {"index": 0}}}}, ("KHR_materials_sheen",))
    assert findings(_write(tmp_path / "fine.gltf", document)) == []


# -- a MASK material whose texture never reaches the cutoff --------------------------------------------------------

def _cut_out(image: str, mode: str = "MASK", alpha_factor: float | None = None, **members) -> dict:
    base = {"baseColorTexture": {"index": 0}}
    if alpha_factor is not None:
        base["baseColorFactor"] = [1, 1, 1, alpha_factor]
    material = {"alphaMode": mode, "pbrMetallicRoughness": base}
    if mode == "MASK":
        material["alphaCutoff"] = 0.5
    return _document([image], material, **members)


def test_mask_texture_with_alpha_0_everywhere_is_invisible(tmp_path):
    """glTF 2.0, 3.9.4 (material.alphaCutoff): under MASK a fragment whose alpha is below alphaCutoff "is rendered as
    fully transparent"; filtering never exceeds the largest texel, here 0."""
    empty = _image(tmp_path / "oak.png", "RGBA", [(150, 100, 50, 0)] * 4)
    broken = _write(tmp_path / "broken.gltf", _cut_out(empty))
    assert findings(broken) == [("OPBR1249", "error", "/materials/0/pbrMetallicRoughness/baseColorTexture", "index")]
    assert khronos_errors(broken, tmp_path) in (None, set())


def test_mask_texture_with_some_texels_above_the_cutoff_stays_quiet(tmp_path):
    """A cut-out: the leaf is opaque (255) where it is, transparent around it."""
    leaf = _image(tmp_path / "leaf.png", "RGBA", [(40, 120, 30, a) for a in (0, 0, 0, 255)])
    assert findings(_write(tmp_path / "fixed.gltf", _cut_out(leaf))) == []
    equal = _image(tmp_path / "equal.png", "RGBA", [(40, 120, 30, 255)] * 4)  # 1 * 0.5 = the cutoff: drawn
    assert findings(_write(tmp_path / "equal.gltf", _cut_out(equal, alpha_factor=0.5))) == []


def test_mask_texture_times_the_factor_alpha_below_the_cutoff(tmp_path):
    """Alpha is the texture's A times baseColorFactor's fourth component (3.9.2): 200 / 255 * 0.6 = 0.47 < 0.5."""
    dim = _image(tmp_path / "dim.png", "RGBA", [(150, 100, 50, a) for a in (10, 80, 150, 200)])
    assert [f[0] for f in findings(_write(tmp_path / "dim.gltf", _cut_out(dim, alpha_factor=0.6)))] == ["OPBR1249"]
    assert findings(_write(tmp_path / "bright.gltf", _cut_out(dim, alpha_factor=0.7))) == []  # 0.55


def test_mask_is_not_claimed_when_vertex_colours_carry_alpha(tmp_path):
    """COLOR_0 multiplies alpha too (3.9.2): with VEC4 vertex colours the product is not the texture's to tell."""
    empty = _image(tmp_path / "oak.png", "RGBA", [(150, 100, 50, 0)] * 4)
    document = _cut_out(empty)
    data = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<12f", *([1.0] * 12)) + \
        struct.pack("<6f", 0, 0, 1, 0, 0, 1)
    document.update({
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode("ascii")}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 84, "byteLength": 24}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0],
                       "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC4"},
                      {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1, "TEXCOORD_0": 2}, "material": 0}]}]})
    assert [f[0] for f in findings(_write(tmp_path / "coloured.gltf", document))] == []


def test_blend_texture_with_alpha_0_everywhere_draws_nothing(tmp_path):
    """Under BLEND alpha is coverage (3.9.4): 0 everywhere draws nothing (OPBR908's untextured case, textured)."""
    empty = _image(tmp_path / "glass.png", "RGBA", [(200, 200, 200, 0)] * 4)
    assert [f[0] for f in findings(_write(tmp_path / "blend.gltf", _cut_out(empty, "BLEND")))] == ["OPBR1249"]
    faint = _image(tmp_path / "faint.png", "RGBA", [(200, 200, 200, a) for a in (0, 0, 0, 3)])
    assert findings(_write(tmp_path / "faint.gltf", _cut_out(faint, "BLEND"))) == []


def test_rgb_texture_under_mask_is_opaque_and_stays_quiet(tmp_path):
    """An image without alpha reads A = 1: a MASK material with it cuts nothing away (not this rule's)."""
    rgb = _image(tmp_path / "oak.png", "RGB", _BROWN)
    assert findings(_write(tmp_path / "rgb.gltf", _cut_out(rgb))) == []
