"""Findings of an independent red-team set (session 15: broken and odd-but-legal MaterialX, USD and glTF files
written without reading this code), each fixed here and proven against its source: the glTF extension texts
(KHR_materials_ior's ior 0, KHR_materials_anisotropy's unbounded rotation) and the Khronos glTF-Validator."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.convert import convert_file
from openpbr_tools.evaluate.fresnel import ior_to_f0
from openpbr_tools.io import read_asset
from openpbr_tools.translate.common import Settings
from openpbr_tools.validate import validate_paths


def _gltf(tmp_path, extensions: dict, name: str = "m.gltf"):
    path = tmp_path / name
    path.write_text(json.dumps({
        "asset": {"version": "2.0"}, "extensionsUsed": sorted(extensions),
        "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0},
                       "extensions": extensions}]}), encoding="utf-8")
    return path


def _findings(path) -> set[tuple[str, str]]:
    return {(d.code, d.severity.name) for d in validate_paths([str(path)]).diagnostics
            if d.severity.name in ("ERROR", "WARNING")}


def test_gltf_ior_zero_is_the_specular_glossiness_mode_not_an_error(tmp_path):
    """KHR_materials_ior: "Valid values for ior are numbers greater than or equal to one. As a special case, a
    value of zero is allowed" (Fresnel 1 at every angle). 0.5 stays an error."""
    assert _findings(_gltf(tmp_path, {"KHR_materials_ior": {"ior": 0}})) == set()
    assert ("OPBR301", "ERROR") in _findings(_gltf(tmp_path, {"KHR_materials_ior": {"ior": 0.5}}, "half.gltf"))


def test_gltf_ior_zero_reads_as_an_infinite_ior_with_a_note_and_verifies(tmp_path):
    source = _gltf(tmp_path, {"KHR_materials_ior": {"ior": 0}})
    result = convert_file(str(source), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings())
    [(_, translated)] = [(s, t) for s, t in result.pairs]
    ior = translated.inputs["specular_ior"].constant
    assert ior_to_f0(ior) > 0.99  # the extension's F = 1, as nearly as a finite IOR gets
    [note] = [d for d in result.diagnostics if d.location.input == "ior"]
    assert note.code == "OPBR1103" and "infinite IOR" in note.message
    outcome = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / "v.mtlx"), "--verify",
                                       "--format", "json"])
    assert outcome.exit_code in (0, 1), outcome.output  # (it raised IndexError in the evaluator before)
    assert "OPBR1108" in outcome.output or "OPBR1109" in outcome.output


@pytest.mark.parametrize("ior", ["0", "-1"])
def test_an_openpbr_ior_outside_its_open_range_is_verified_not_a_crash(tmp_path, ior):
    """specular_ior 0 divided the coat's IOR by zero in the evaluator (NaN table indices): it is evaluated just
    inside its open bound and said to be."""
    path = tmp_path / "m.mtlx"
    path.write_text(f"""<?xml version="1.0"?>
<materialx version="1.39">
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="specular_ior" type="float" value="{ior}" />
    <input name="coat_weight" type="float" value="0.5" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
</materialx>
""", encoding="utf-8")
    for suffix in ("usda", "gltf"):
        outcome = CliRunner().invoke(cli, ["convert", str(path), "-o", str(tmp_path / f"o.{suffix}"), "--verify"])
        assert outcome.exit_code in (0, 1) and "OPBR011" not in outcome.output, outcome.output


def test_a_negative_anisotropy_rotation_is_no_finding(tmp_path):
    """KHR_materials_anisotropy bounds anisotropyStrength to [0, 1] and anisotropyRotation not at all."""
    path = _gltf(tmp_path, {"KHR_materials_anisotropy": {"anisotropyStrength": 1.0, "anisotropyRotation": -2.5}})
    assert {code for code, _ in _findings(path)} & {"OPBR301", "OPBR302"} == set()
    assert read_asset(str(path)).materials[0].inputs["anisotropy_rotation"].constant == -2.5


def _textured_document(tmp_path, material: dict, **more) -> str:
    from PIL import Image

    Image.new("RGB", (4, 4), (200, 120, 40)).save(tmp_path / "t.png")
    document = {"asset": {"version": "2.0"}, "images": [{"uri": "t.png"}], "textures": [{"source": 0}],
                "materials": [dict({"name": "M"}, **material)]}
    document.update(more)
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps(document), encoding="utf-8")
    return str(path)


#: The red team's glTF defects the Khronos glTF-Validator reports and this toolkit did not.
KHRONOS_FOUND = {
    "material extension inside pbrMetallicRoughness": (
        {"emissiveFactor": [1, 1, 1], "pbrMetallicRoughness": {"extensions": {
            "KHR_materials_emissive_strength": {"emissiveStrength": 4}}}}, {"extensionsUsed": ["KHR_materials_emissive_strength"]}),
    "KHR_texture_transform on the material": (
        {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "extensions": {
            "KHR_texture_transform": {"scale": [4, 4]}}}, {"extensionsUsed": ["KHR_texture_transform"]}),
    "a mipmap mode as magFilter": (
        {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
        {"samplers": [{"magFilter": 9987, "minFilter": 9987}], "textures": [{"source": 0, "sampler": 0}]}),
}


@pytest.mark.parametrize("case", sorted(KHRONOS_FOUND))
def test_each_finding_of_the_khronos_validator_is_one_here_at_least_as_severe(tmp_path, case):
    from gltf_support import validate_with_khronos

    material, more = KHRONOS_FOUND[case]
    path = _textured_document(tmp_path, material, **more)
    theirs = {(m["pointer"], m["severity"]) for m in validate_with_khronos(path, tmp_path)["issues"]["messages"]
              if m["severity"] <= 1}
    ours = {(f"{d.location.path}/{d.location.input}" if d.location.input else d.location.path): d.severity.name
            for d in validate_paths([path]).diagnostics if d.severity.name in ("ERROR", "WARNING")}
    assert theirs
    for pointer, severity in theirs:
        assert pointer in ours, (pointer, ours)
        assert severity == 1 or ours[pointer] == "ERROR"


@pytest.mark.parametrize("material, expected", [
    ({"emissiveTexture": {"index": 0}}, {"/materials/0/emissiveFactor"}),
    ({"emissiveTexture": {"index": 0}, "emissiveFactor": [1, 1, 1]}, set()),
    ({"extensions": {"KHR_materials_clearcoat": {"clearcoatTexture": {"index": 0}}}},
     {"/materials/0/extensions/KHR_materials_clearcoat/clearcoatFactor"}),
    # (a zero factor beside a packed texture is common and meant: the roughness still reads G)
    ({"pbrMetallicRoughness": {"metallicFactor": 0, "metallicRoughnessTexture": {"index": 0}}}, set()),
])
def test_a_texture_whose_factor_defaults_to_zero_is_said_to_have_no_effect(tmp_path, material, expected):
    """glTF 2.0: emissiveFactor defaults to [0, 0, 0] and "acts as a linear multiplier" of the texture, as
    clearcoatFactor (default 0) does for clearcoatTexture: an exporter that writes only the texture shows none."""
    used = {"extensionsUsed": sorted(material.get("extensions", {}))} if material.get("extensions") else {}
    path = _textured_document(tmp_path, material, **used)
    found = {f"{d.location.path}/{d.location.input}" for d in validate_paths([path]).diagnostics if d.code == "OPBR1211"}
    assert found == expected
