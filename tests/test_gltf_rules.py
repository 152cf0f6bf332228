"""The glTF rule family (OPBR12xx) beyond its documented examples, and `openpbr validate` / `info`
on .gltf and .glb files."""

from __future__ import annotations

import base64
import io
import json

import pytest
from click.testing import CliRunner
from PIL import Image

from cli.group import cli
from openpbr_tools.validate import validate_paths

from gltf_support import gltf_pbr_material


def png(size=(4, 4), fmt="PNG") -> bytes:
    out = io.BytesIO()
    Image.new("RGB", size, (10, 20, 30)).save(out, fmt)
    return out.getvalue()


def write(tmp_path, document, name="doc.gltf"):
    path = tmp_path / name
    path.write_text(json.dumps({"asset": {"version": "2.0"}, **document}), encoding="utf-8")
    return path


def findings(path, code):
    return [d for d in validate_paths([str(path)]).diagnostics if d.code == code]


BASE = {"materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], "textures": [{"source": 0}]}


def test_undeclared_texture_transform_points_at_its_use(tmp_path):
    (tmp_path / "a.png").write_bytes(png())
    document = {"images": [{"uri": "a.png"}], "textures": [{"source": 0}],
                "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {
                    "index": 0, "extensions": {"KHR_texture_transform": {"scale": [2, 2]}}}}}]}
    found = findings(write(tmp_path, document), "OPBR1201")
    assert len(found) == 1
    assert found[0].location.path == "/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform"


def test_required_extension_must_also_be_used(tmp_path):
    found = findings(write(tmp_path, {"extensionsRequired": ["KHR_materials_ior"], "materials": [{}]}), "OPBR1201")
    assert found and found[0].location.path == "/extensionsRequired/0"


@pytest.mark.parametrize("name,reported", [("KHR_draco_mesh_compression", False), ("KHR_texture_transform", False),
                                           ("KHR_texture_basisu", True), ("VENDOR_x", True)])
def test_required_extensions_the_toolkit_cannot_interpret(tmp_path, name, reported):
    path = write(tmp_path, {"extensionsUsed": [name], "extensionsRequired": [name], "materials": [{}]})
    assert bool(findings(path, "OPBR1202")) == reported


@pytest.mark.parametrize("extensions,reported", [
    ({"KHR_materials_pbrSpecularGlossiness": {}, "KHR_materials_clearcoat": {}}, True),
    ({"KHR_materials_pbrSpecularGlossiness": {}, "KHR_materials_emissive_strength": {"emissiveStrength": 2}}, False),
    ({"KHR_materials_unlit": {}, "KHR_materials_emissive_strength": {"emissiveStrength": 2}}, True),
    ({"KHR_materials_clearcoat": {}, "KHR_materials_sheen": {}}, False),
])
def test_extension_exclusions(tmp_path, extensions, reported):
    path = write(tmp_path, {"extensionsUsed": sorted(extensions), "materials": [{"extensions": extensions}]})
    assert bool(findings(path, "OPBR1203")) == reported


def test_texcoord_checked_against_every_primitive_using_the_material(tmp_path):
    (tmp_path / "a.png").write_bytes(png())
    document = {
        "images": [{"uri": "a.png"}], "textures": [{"source": 0}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}}],
        "accessors": [{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]},
                      {"componentType": 5126, "count": 3, "type": "VEC2"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 1}, "material": 0},
                                   {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}],
    }
    found = findings(write(tmp_path, document), "OPBR1205")
    assert len(found) == 1 and "/meshes/0/primitives/1" in found[0].message


def test_texcoord_is_not_judged_without_meshes(tmp_path):
    (tmp_path / "a.png").write_bytes(png())
    document = {"images": [{"uri": "a.png"}], "textures": [{"source": 0}],
                "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 3}}}]}
    assert not findings(write(tmp_path, document), "OPBR1205")


def test_non_power_of_two_external_image(tmp_path):
    (tmp_path / "a.png").write_bytes(png((6, 4)))
    found = findings(write(tmp_path, {"images": [{"uri": "a.png"}], **BASE}), "OPBR1206")
    assert found and "6 x 4" in found[0].message


def test_webp_needs_its_texture_extension(tmp_path):
    """A WebP (or KTX2) named by the core source is the validator's TEXTURE_INVALID_IMAGE_MIME_TYPE, an error
    (OPBR1220), not the warning OPBR1207 that a format no extension defines (TGA, EXR) gets."""
    (tmp_path / "a.webp").write_bytes(png(fmt="WEBP"))
    plain = write(tmp_path, {"images": [{"uri": "a.webp"}], **BASE}, "plain.gltf")
    assert findings(plain, "OPBR1220") and not findings(plain, "OPBR1207")
    through_extension = {"images": [{"uri": "a.webp"}], "extensionsUsed": ["EXT_texture_webp"],
                         "textures": [{"extensions": {"EXT_texture_webp": {"source": 0}}}],
                         "materials": BASE["materials"]}
    path = write(tmp_path, through_extension, "ext.gltf")
    assert not findings(path, "OPBR1207") and not findings(path, "OPBR1220")


def test_a_tga_through_the_core_source_stays_a_warning(tmp_path):
    (tmp_path / "a.tga").write_bytes(png(fmt="TGA"))
    path = write(tmp_path, {"images": [{"uri": "a.tga"}], **BASE})
    assert findings(path, "OPBR1207") and not findings(path, "OPBR1220")


def test_image_content_decides_over_a_misleading_suffix(tmp_path):
    (tmp_path / "a.png").write_bytes(png(fmt="TIFF"))
    found = findings(write(tmp_path, {"images": [{"uri": "a.png"}], **BASE}), "OPBR1207")
    assert found and "tiff" in found[0].message


@pytest.mark.parametrize("material,reported", [
    ({"emissiveTexture": {"index": 0}, "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3}}}, True),
    ({"emissiveTexture": {"index": 0}, "emissiveFactor": [1, 1, 1],
      "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3}}}, False),
    ({"emissiveFactor": [0, 0, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3}}}, True),
])
def test_emissive_strength_needs_an_emissive_colour(tmp_path, material, reported):
    (tmp_path / "a.png").write_bytes(png())
    document = {"extensionsUsed": ["KHR_materials_emissive_strength"], "images": [{"uri": "a.png"}],
                "textures": [{"source": 0}], "materials": [material]}
    assert bool(findings(write(tmp_path, document), "OPBR1208")) == reported


@pytest.mark.parametrize("document,fragment", [
    ({"buffers": [{"uri": "geometry.bin", "byteLength": 4}]}, "not found"),
    ({"buffers": [{"uri": "data:application/octet-stream;base64,AAAAAA==", "byteLength": 4}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 16}],
      "images": [{"bufferView": 0, "mimeType": "image/png"}], **BASE}, "outside its buffer"),
    ({"buffers": [{"byteLength": 4}], "bufferViews": [{"buffer": 0, "byteLength": 4}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 1, "type": "SCALAR"}]}, "no GLB binary chunk"),
    ({"buffers": [{"uri": "data:application/octet-stream;base64,AAAA", "byteLength": 8}]}, "fewer than its byteLength"),
])
def test_broken_buffers_and_embedded_images(tmp_path, document, fragment):
    found = findings(write(tmp_path, {"materials": [{}], **document}), "OPBR1209")
    assert any(fragment in d.message for d in found), [d.message for d in found]


def test_malformed_texture_transform_is_an_invalid_property(tmp_path):
    (tmp_path / "a.png").write_bytes(png())
    document = {"images": [{"uri": "a.png"}], "textures": [{"source": 0}], "extensionsUsed": ["KHR_texture_transform"],
                "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {
                    "index": 0, "extensions": {"KHR_texture_transform": {"scale": "big"}}}}}]}
    assert findings(write(tmp_path, document), "OPBR1210")


def test_gltf_rules_do_not_fire_on_materialx(write_mtlx, codes_of):
    path = write_mtlx('<gltf_pbr name="S" type="surfaceshader">\n  <input name="roughness" type="float" value="0.5" />\n</gltf_pbr>')
    assert not [c for c in codes_of(path) if c.startswith("OPBR12")]


# -- the command line ----------------------------------------------------------------------------

def run(*args):
    result = CliRunner().invoke(cli, list(map(str, args)))
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    return result


def test_validate_a_clean_gltf_exits_zero(tmp_path):
    (tmp_path / "a.png").write_bytes(png())
    path = write(tmp_path, {"images": [{"uri": "a.png"}], **BASE})
    result = run("validate", path)
    assert result.exit_code == 0, result.output


def test_validate_reports_gltf_findings_and_exits_one(tmp_path):
    path = write(tmp_path, {"materials": [{"pbrMetallicRoughness": {"roughnessFactor": 1.5}}]})
    result = run("validate", path)
    assert result.exit_code == 1 and "OPBR301" in result.output and "roughnessFactor" in result.output


def test_validate_a_broken_glb_exits_two(tmp_path):
    (tmp_path / "broken.glb").write_bytes(b"glTF\x02\x00\x00\x00")
    result = run("validate", tmp_path / "broken.glb")
    assert result.exit_code == 2 and "GLB" in result.output


def test_validate_a_folder_mixing_materialx_and_gltf(tmp_path, write_mtlx):
    write_mtlx('<open_pbr_surface name="S" type="surfaceshader" version="1.1.1">\n'
               '  <input name="base_weight" type="float" value="1.5" />\n</open_pbr_surface>', name="a.mtlx")
    write(tmp_path, {"materials": [{"pbrMetallicRoughness": {"metallicFactor": -1}}]}, "b.gltf")
    result = run("validate", "--format", "json", tmp_path)
    report = json.loads(result.output)
    assert sorted(f["path"].rsplit("/", 1)[-1] for f in report["files"]) == ["a.mtlx", "b.gltf"]
    found = sorted((d["location"]["file"].rsplit("/", 1)[-1], d["code"]) for d in report["diagnostics"])
    assert found == [("a.mtlx", "OPBR301"), ("b.gltf", "OPBR301")], result.output


def test_info_lists_materials_and_textures_of_a_glb(tmp_path):
    from openpbr_tools.io.gltf.writer import write_gltf
    from openpbr_tools.model import Texture

    (tmp_path / "wood.png").write_bytes(png())
    material = gltf_pbr_material("Wood", base_color=Texture("wood.png", channels=(0, 1, 2), colorspace="srgb_texture"),
                                 roughness=0.6)
    write_gltf([material], tmp_path / "wood.glb", source=str(tmp_path / "wood.mtlx"))
    result = run("info", tmp_path / "wood.glb")
    assert result.exit_code == 0, result.output
    assert "Wood" in result.output and "gltf_pbr 2.0.1" in result.output
    assert "base_color: #/images/0 (srgb_texture)" in result.output, result.output


def test_data_uri_image_is_listed_by_info_as_packaged(tmp_path):
    uri = "data:image/png;base64," + base64.b64encode(png()).decode()
    path = write(tmp_path, {"images": [{"uri": uri}], **BASE})
    result = run("info", "--format", "json", path)
    textures = json.loads(result.output)[0]["materials"][0]["textures"]
    assert textures == [{"input": "base_color", "file": "#/images/0", "colorspace": "srgb_texture", "channels": [0, 1, 2],
                         "normal_map": False, "udim": False}]


# -- session 17: image encodings and channels, variants, tangent signs, plausibility ----------------------------

def _image(tmp_path, name, mode, value, fmt="PNG", **save):
    out = io.BytesIO()
    image = Image.new(mode, (4, 4), value)
    image.save(out, fmt, **save)
    (tmp_path / name).write_bytes(out.getvalue())


def test_a_16_bit_normal_map_is_allowed(tmp_path):
    """Only base colour and emissive textures must be 8-bit (3.9.2, 3.9.3); data textures may use more bits."""
    from openpbr_tools.rules.gltf_images import _PNG_16BIT

    document = {"images": [{"uri": _PNG_16BIT}], "textures": [{"source": 0}],
                "materials": [{"normalTexture": {"index": 0}, "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 0}}]}
    found = findings(write(tmp_path, document), "OPBR1219")
    assert [d.location.path for d in found] == ["/materials/0/emissiveTexture"]


def test_transmission_with_a_textured_alpha_in_blend_is_coverage_not_reported(tmp_path):
    """KHR_materials_transmission: alpha-as-coverage may be used along with transmission."""
    _image(tmp_path, "a.png", "RGBA", (200, 200, 200, 128))
    glass = {"alphaMode": "BLEND", "pbrMetallicRoughness": {"metallicFactor": 0, "baseColorTexture": {"index": 0}},
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}}}
    document = {"extensionsUsed": ["KHR_materials_transmission"], "images": [{"uri": "a.png"}], "textures": [{"source": 0}],
                "materials": [glass]}
    assert not findings(write(tmp_path, document), "OPBR1221")


def test_an_extension_authoring_other_properties_but_not_its_factor_is_a_deliberate_zero(tmp_path):
    """As in Khronos' DiffuseTransmissionTest ("Factor 0.0"): only an empty object is reported."""
    for index, extension in enumerate(({"diffuseTransmissionColorFactor": [1, 0, 0]}, {})):
        document = {"extensionsUsed": ["KHR_materials_diffuse_transmission"],
                    "materials": [{"pbrMetallicRoughness": {"metallicFactor": 0},
                                   "extensions": {"KHR_materials_diffuse_transmission": extension}}]}
        found = findings(write(tmp_path, document, f"{index}.gltf"), "OPBR1211")  # (a lone empty object: a warning)
        assert bool(found) == (extension == {})


def _tangents(tmp_path, values, component_type=5126, name="t.gltf", primitives=1):
    import struct

    fmt = {5126: "f", 5122: "h"}[component_type]
    data = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + b"".join(struct.pack(f"<4{fmt}", 1, 0, 0, w) for w in values)
    accessor = {"bufferView": 1, "componentType": component_type, "count": 3, "type": "VEC4"}
    if component_type != 5126:
        accessor["normalized"] = True
    document = {"buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
                "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": len(data) - 36}],
                "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                              accessor],
                "materials": [{}],
                "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TANGENT": 1}, "material": 0}] * primitives}]}
    if component_type != 5126:
        document["extensionsUsed"] = ["KHR_mesh_quantization"]
    return findings(write(tmp_path, document, name), "OPBR1227")


def test_tangent_signs_minus_one_and_quantised_extremes_are_signs(tmp_path):
    assert not _tangents(tmp_path, [1.0, -1.0, -1.0])
    assert not _tangents(tmp_path, [32767, -32767, -32768], component_type=5122, name="q.gltf")  # max(c / 32767, -1)
    assert _tangents(tmp_path, [16384, 32767, 32767], component_type=5122, name="half.gltf")


def test_a_tangent_accessor_shared_by_primitives_is_reported_once(tmp_path):
    found = _tangents(tmp_path, [0.0, 1.0, float("nan")], primitives=3)
    assert len(found) == 1 and "2 of 3" in found[0].message


def test_a_variant_index_naming_nothing_is_a_dangling_reference(tmp_path):
    document = {"extensionsUsed": ["KHR_materials_variants"],
                "extensions": {"KHR_materials_variants": {"variants": [{"name": "Red"}]}}, "materials": [{}],
                "accessors": [{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]}],
                "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0, "extensions": {
                    "KHR_materials_variants": {"mappings": [{"material": 0, "variants": [0, 3]}]}}}]}]}
    found = findings(write(tmp_path, document), "OPBR802")
    assert [d.location.path for d in found] == ["/meshes/0/primitives/0/extensions/KHR_materials_variants/mappings/0/variants/1"]


def test_a_volume_thickness_is_compared_with_the_meshes_using_the_material_only(tmp_path):
    volume = {"extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume"],
              "materials": [{"pbrMetallicRoughness": {"metallicFactor": 0}, "extensions": {
                  "KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_volume": {"thicknessFactor": 0.5}}}]}
    assert not findings(write(tmp_path, volume), "OPBR1222")  # no mesh: nothing to compare with
    small = {"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0.01, 0.04, 0.02]}
    meshed = {**volume, "accessors": [small], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}]}
    assert findings(write(tmp_path, meshed, "m.gltf"), "OPBR1222")  # 0.5 > 10 x 0.04
    small["max"] = [0.01, 0.06, 0.02]
    assert not findings(write(tmp_path, meshed, "n.gltf"), "OPBR1222")  # 0.5 < 10 x 0.06


def test_an_anisotropy_texture_with_blue_strength_is_not_reported(tmp_path):
    _image(tmp_path, "flow.png", "RGB", (255, 128, 200))
    document = {"extensionsUsed": ["KHR_materials_anisotropy"], "images": [{"uri": "flow.png"}], "textures": [{"source": 0}],
                "materials": [{"extensions": {"KHR_materials_anisotropy": {"anisotropyStrength": 1, "anisotropyTexture": {"index": 0}}}}]}
    assert not [d for d in findings(write(tmp_path, document), "OPBR1211") if "anisotropy" in d.message]
