"""What the glTF writer produces passes the Khronos glTF-Validator with zero errors: .gltf and .glb,
with and without the preview sphere, external, data-URI and GLB-embedded images, baked and
passed-through textures, KHR_texture_transform and every KHR_materials_* extension gltf_pbr carries.

The validator (npm ``gltf-validator``) runs through node; without either, these tests are skipped
and say why. Warnings and infos are listed in the assertion message.
"""

from __future__ import annotations

import base64
import io

import numpy as np
import pytest
from PIL import Image

from openpbr_tools.io import read_asset
from openpbr_tools.io.gltf.writer import write_gltf
from openpbr_tools.model import Texture, UVTransform

from gltf_support import describe_issues, gltf_pbr_material, require_validator, validate_with_khronos


@pytest.fixture(scope="module")
def source(tmp_path_factory):
    folder = tmp_path_factory.mktemp("khronos_source")
    rng = np.random.default_rng(3)
    for name, channels in (("base.png", 4), ("orm.png", 3), ("grey.png", 1), ("normal.png", 3)):
        array = rng.integers(0, 256, size=(8, 8, channels), dtype=np.uint8)
        Image.fromarray(array[:, :, 0] if channels == 1 else array).save(folder / name)
    return folder


def materials():
    transform = UVTransform(scale=(2.0, 2.0), rotate=15.0, offset=(0.1, 0.0), pivot=(0.0, 1.0))
    everything = gltf_pbr_material(
        "Everything", base_color=(0.8, 0.2, 0.1), alpha=0.9, alpha_mode=2, metallic=0.0, roughness=0.4,
        emissive=(0.5, 0.5, 0.5), emissive_strength=2.0, clearcoat=0.6, clearcoat_roughness=0.2,
        sheen_color=(0.3, 0.3, 0.3), sheen_roughness=0.5, specular=0.9, specular_color=(1.0, 0.9, 0.9),
        transmission=0.5, thickness=0.01, attenuation_distance=0.2, attenuation_color=(0.9, 0.9, 0.8), ior=1.5,
        iridescence=1.0, iridescence_ior=1.3, iridescence_thickness=400.0, anisotropy_strength=0.4,
        anisotropy_rotation=0.5, dispersion=0.2,
    )
    textured = gltf_pbr_material(
        "Textured",
        base_color=Texture("base.png", channels=(0, 1, 2), colorspace="srgb_texture", uv=transform, wrap=("clamp", "mirror")),
        alpha=Texture("base.png", channels=(3,), colorspace="none", uv=transform, wrap=("clamp", "mirror")),
        alpha_mode=1, alpha_cutoff=0.3,
        metallic=Texture("grey.png", channels=None, colorspace="none"),  # baked into metallicRoughness B
        roughness=Texture("orm.png", channels=(1,), colorspace="none", texcoord=1),
        normal=Texture("normal.png", image_type="vector3", colorspace="none", normal_map=1.0),
        occlusion=Texture("orm.png", channels=(0,), colorspace="none"),
        clearcoat=Texture("grey.png", channels=None, colorspace="none", scale=0.8),
        sheen_roughness=Texture("grey.png", channels=None, colorspace="none", scale=0.5),  # baked into A
        iridescence_thickness=Texture("orm.png", channels=(1,), colorspace="none", scale=300.0, bias=100.0),
        anisotropy_strength=Texture("grey.png", channels=None, colorspace="none", scale=0.7),
    )
    return [everything, textured]


CASES = [(".gltf", "sphere", None), (".glb", "sphere", None), (".gltf", None, None), (".glb", None, None),
         (".gltf", "sphere", True)]


@pytest.mark.parametrize("suffix,mesh,embed", CASES, ids=["gltf-sphere", "glb-sphere", "gltf", "glb", "gltf-data-uris"])
def test_written_files_have_no_validator_errors(source, tmp_path, suffix, mesh, embed):
    require_validator()
    out = tmp_path / f"materials{suffix}"
    write_gltf(materials(), out, mesh=mesh, embed=embed, source=str(source / "doc.mtlx"))
    report = validate_with_khronos(out, tmp_path)
    assert report["issues"]["numErrors"] == 0, describe_issues(report)
    if mesh:
        assert report["info"]["drawCallCount"] == 2, describe_issues(report)
    used = set(report["info"].get("extensionsUsed", []))
    assert {"KHR_texture_transform", "KHR_materials_anisotropy", "KHR_materials_iridescence"} <= used


def test_a_read_and_rewritten_gltf_has_no_validator_errors(source, tmp_path):
    require_validator()
    first = tmp_path / "first.glb"
    write_gltf(materials(), first, mesh="sphere", source=str(source / "doc.mtlx"))
    asset = read_asset(first)
    again = tmp_path / "again" / "again.gltf"
    again.parent.mkdir()
    write_gltf(asset.materials, again, mesh="sphere", source=asset)
    report = validate_with_khronos(again, tmp_path)
    assert report["issues"]["numErrors"] == 0, describe_issues(report)


# Where the Khronos validator has the same check, it must agree with the rule's documented examples.
SAME_CHECK = {"OPBR1201": "UNDECLARED_EXTENSION", "OPBR1203": "MULTIPLE_EXTENSIONS",
              "OPBR1205": "MESH_PRIMITIVE_TOO_FEW_TEXCOORDS", "OPBR1208": "KHR_MATERIALS_EMISSIVE_STRENGTH_ZERO_FACTOR",
              "OPBR1209": "INVALID_URI", "OPBR1210": "TYPE_MISMATCH"}


@pytest.mark.parametrize("code", sorted(SAME_CHECK))
def test_the_khronos_validator_agrees_with_the_rule_examples(tmp_path, code):
    from openpbr_tools.rules import all_rules

    require_validator()
    rule = all_rules()[code]
    for kind, expected in (("failing", True), ("passing", False)):
        path = tmp_path / f"{kind}.gltf"
        path.write_text(getattr(rule, kind), encoding="utf-8")
        report = validate_with_khronos(path, tmp_path)
        found = {message["code"] for message in report["issues"]["messages"]}
        assert (SAME_CHECK[code] in found) == expected, f"{code} {kind}: " + describe_issues(report)


def test_a_missing_validator_skips_with_the_reason(monkeypatch, tmp_path):
    monkeypatch.setenv("OPENPBR_GLTF_VALIDATOR", str(tmp_path / "nowhere"))
    with pytest.raises(pytest.skip.Exception) as skipped:
        require_validator()
    assert "not installed" in str(skipped.value) or "node is not on PATH" in str(skipped.value)


#: A material property of each family out of its schema range (every component of a colour too); the
#: families the validator (2.0.0-dev.3.10) checks.
OUT_OF_RANGE = {
    "pbrMetallicRoughness": {"baseColorFactor": [1.5, 0, 0, 1], "metallicFactor": -0.1, "roughnessFactor": 1.2},
    "KHR_materials_clearcoat": {"clearcoatFactor": 1.5, "clearcoatRoughnessFactor": -1},
    "KHR_materials_sheen": {"sheenColorFactor": [2, 0, 0], "sheenRoughnessFactor": 1.5},
    "KHR_materials_transmission": {"transmissionFactor": 1.5},
    "KHR_materials_volume": {"thicknessFactor": -1, "attenuationDistance": -2, "attenuationColor": [2, 0, 0]},
    "KHR_materials_ior": {"ior": 0.5},
    "KHR_materials_specular": {"specularFactor": 1.5, "specularColorFactor": [-1, 0, 0]},
    "KHR_materials_iridescence": {"iridescenceFactor": 1.5, "iridescenceIor": 0.5, "iridescenceThicknessMinimum": -5,
                                  "iridescenceThicknessMaximum": -1},
    "KHR_materials_anisotropy": {"anisotropyStrength": 1.5},
    "KHR_materials_emissive_strength": {"emissiveStrength": -1},
    "KHR_materials_dispersion": {"dispersion": -1},
    "KHR_materials_pbrSpecularGlossiness": {"diffuseFactor": [2, 0, 0, 1], "specularFactor": [1.5, 0, 0],
                                            "glossinessFactor": 1.5},
}


@pytest.mark.parametrize("family", sorted(OUT_OF_RANGE))
def test_every_property_the_khronos_validator_finds_out_of_range_is_an_error_here(tmp_path, family):
    """Never weaker than the anchor: each material property the Khronos glTF-Validator reports as an error
    (VALUE_NOT_IN_RANGE, at the property or one of its components) is an error of the toolkit's at that
    property, and the toolkit reports no error the validator does not. A base colour over 1 is an error in
    glTF, whose colours are linear Rec.709 (not the wide-gamut info of a .mtlx document, OPBR304); a
    negative iridescenceThicknessMinimum, which no gltf_pbr parameter holds, too."""
    from openpbr_tools.validate import validate_paths
    import json

    material = {"name": "M"}
    used = []
    if family == "pbrMetallicRoughness":
        material[family] = OUT_OF_RANGE[family]
    else:
        material["extensions"] = {family: OUT_OF_RANGE[family]}
        used.append(family)
    if family == "KHR_materials_volume":
        material["extensions"]["KHR_materials_transmission"] = {"transmissionFactor": 1}
        used.append("KHR_materials_transmission")
    path = tmp_path / "m.gltf"
    document = {"asset": {"version": "2.0"}, "materials": [material]}
    if used:  # (an empty extensionsUsed is an error of its own)
        document["extensionsUsed"] = used
    path.write_text(json.dumps(document))
    theirs = {m["pointer"].rsplit("/", 1)[0] if m["pointer"].rsplit("/", 1)[-1].isdigit() else m["pointer"]
              for m in validate_with_khronos(path, tmp_path)["issues"]["messages"] if m["severity"] == 0}
    ours = {f"{d.location.path}/{d.location.input}" for d in validate_paths([str(path)]).diagnostics
            if d.severity.name == "ERROR"}
    assert theirs and ours == theirs


#: Material properties the validator reports as errors or warnings outside the range rules (JSON types, the
#: occlusion strength's range, an alpha cutoff the mode ignores).
OTHER_FINDINGS = {
    "occlusion strength": {"occlusionTexture": {"index": 0, "strength": 2}},
    "doubleSided of another type": {"doubleSided": "yes"},
    "name of another type": {"name": 5},
    "alphaCutoff without MASK": {"alphaCutoff": 0.3},
    "negative texCoord": {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": -1}}},
    "texture index that points nowhere": {"pbrMetallicRoughness": {"baseColorTexture": {"index": 5}}},
    "normal scale of another type": {"normalTexture": {"index": 0, "scale": "x"}},
    "factor of another length": {"emissiveFactor": [1, 1]},
    "misspelt property": {"pbrMetallicRoughness": {"baseColourFactor": [1, 0, 0, 1]}},
    "misspelt textureInfo property": {"normalTexture": {"index": 0, "sacle": 2}},
}


@pytest.mark.parametrize("case", sorted(OTHER_FINDINGS))
def test_every_material_finding_of_the_khronos_validator_is_one_here(tmp_path, case):
    """Each property the Khronos glTF-Validator reports (error or warning) on a material is reported here at
    that property (a textureInfo's index at the textureInfo) with the same severity."""
    import json

    from openpbr_tools.validate import validate_paths

    # (a flat normal's colour: the cases put it in normalTexture too, where a black image is a normal map pointing
    # into the surface, OPBR724, a finding of the pixels the validator does not read)
    Image.new("RGBA", (4, 4), (128, 128, 255, 255)).save(tmp_path / "t.png")
    material = dict({"name": "M"}, **OTHER_FINDINGS[case])
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "images": [{"uri": "t.png"}], "textures": [{"source": 0}],
                                "materials": [material]}))
    theirs = {(m["pointer"].removesuffix("/index"), ("ERROR", "WARNING")[m["severity"]])
              for m in validate_with_khronos(path, tmp_path)["issues"]["messages"] if m["severity"] <= 1}
    ours = {(f"{d.location.path}/{d.location.input}" if d.location.input else d.location.path, d.severity.name)
            for d in validate_paths([str(path)]).diagnostics if d.severity.name in ("ERROR", "WARNING")}
    assert theirs and ours == theirs


def test_a_misspelt_property_of_a_material_extension_is_a_warning_as_the_validators(tmp_path):
    """The older IridescenceSuzanne sample (tests/data/published/gltf_samples) spells iridescenceIOR: the
    validator's UNEXPECTED_PROPERTY, a warning here too (OPBR1213), with the property most likely meant."""
    import json

    from openpbr_tools.validate import validate_paths

    require_validator()
    Image.new("RGBA", (4, 4)).save(tmp_path / "t.png")
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps({
        "asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_iridescence", "KHR_texture_transform"],
        "images": [{"uri": "t.png"}], "textures": [{"source": 0}],
        "materials": [{"name": "M", "extensions": {"KHR_materials_iridescence": {
            "iridescenceFactor": 1, "iridescenceIOR": 1.8, "iridescenceTexture": {
                "index": 0, "extensions": {"KHR_texture_transform": {"rotate": 1.0}}}}}}]}))
    theirs = {(m["code"], m["pointer"]) for m in validate_with_khronos(path, tmp_path)["issues"]["messages"]
              if m["severity"] <= 1}
    ours = {(d.code, f"{d.location.path}/{d.location.input}"): d for d in validate_paths([str(path)]).diagnostics
            if d.severity.name in ("ERROR", "WARNING")}
    iridescence = "/materials/0/extensions/KHR_materials_iridescence"
    expected = {f"{iridescence}/iridescenceIOR", f"{iridescence}/iridescenceTexture/extensions/KHR_texture_transform/rotate"}
    assert theirs == {("UNEXPECTED_PROPERTY", pointer) for pointer in expected}
    assert set(ours) == {("OPBR1213", pointer) for pointer in expected}
    assert {d.severity.name for d in ours.values()} == {"WARNING"}
    assert ours[("OPBR1213", f"{iridescence}/iridescenceIOR")].hint == "did you mean 'iridescenceIor'?"


def _buffer(data: bytes) -> dict:
    padded = data + b"\0" * (-len(data) % 4)
    return {"uri": "data:application/octet-stream;base64," + base64.b64encode(padded).decode(), "byteLength": len(padded)}


def _image_bytes(fmt: str) -> bytes:
    buffer = io.BytesIO()
    Image.new("RGB", (4, 4), (9, 99, 200)).save(buffer, fmt)
    return buffer.getvalue()


#: Images and declarations the validator reports (error or warning) outside the material objects.
IMAGE_FINDINGS = {
    "data URI declaring another format": lambda png, jpeg: {"images": [{"uri": "data:image/png;base64," + base64.b64encode(jpeg).decode()}]},
    "file declared as another format": lambda png, jpeg: {"images": [{"uri": "t.png", "mimeType": "image/jpeg"}]},
    "bufferView declared as another format": lambda png, jpeg: {
        "buffers": [_buffer(jpeg)], "bufferViews": [{"buffer": 0, "byteLength": len(jpeg)}],
        "images": [{"bufferView": 0, "mimeType": "image/png"}]},
    "uri and bufferView": lambda png, jpeg: {
        "buffers": [_buffer(png)], "bufferViews": [{"buffer": 0, "byteLength": len(png)}],
        "images": [{"uri": "t.png", "bufferView": 0, "mimeType": "image/png"}]},
    "bufferView without mimeType": lambda png, jpeg: {
        "buffers": [_buffer(png)], "bufferViews": [{"buffer": 0, "byteLength": len(png)}], "images": [{"bufferView": 0}]},
    "extension declared twice": lambda png, jpeg: {"images": [{"uri": "t.png"}],
                                                   "extensionsUsed": ["KHR_materials_ior", "KHR_materials_ior"]},
    "file named for another format": lambda png, jpeg: {"images": [{"uri": "t.jpg"}]},  # no finding: no type declared
}


@pytest.mark.parametrize("case", sorted(IMAGE_FINDINGS))
def test_every_image_finding_of_the_khronos_validator_is_one_here(tmp_path, case):
    """Each error or warning the validator reports at an image or an extension list is reported here at the same
    pointer with the same severity, and nothing else is."""
    import json

    from openpbr_tools.validate import validate_paths

    png, jpeg = _image_bytes("PNG"), _image_bytes("JPEG")
    (tmp_path / "t.png").write_bytes(png)
    (tmp_path / "t.jpg").write_bytes(png)
    document = {"asset": {"version": "2.0"}, "textures": [{"source": 0}],
                "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}},
                               "extensions": {"KHR_materials_ior": {"ior": 1.4}}}],
                "extensionsUsed": ["KHR_materials_ior"], **IMAGE_FINDINGS[case](png, jpeg)}
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps(document))
    theirs = {(m["pointer"], ("ERROR", "WARNING")[m["severity"]])
              for m in validate_with_khronos(path, tmp_path)["issues"]["messages"] if m["severity"] <= 1}
    ours = {(f"{d.location.path}/{d.location.input}" if d.location.input else d.location.path, d.severity.name)
            for d in validate_paths([str(path)]).diagnostics if d.severity.name in ("ERROR", "WARNING")}
    assert ours == theirs
    assert bool(theirs) == (case != "file named for another format")
