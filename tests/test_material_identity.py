"""Material identities survive every writer and reader: materials sharing a name stay distinct (and
the rename is reported), a USD Material holding OpenPBR plus its UsdPreviewSurface fallback is one
material, and USD material names are prim names, not paths."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.io import read_asset

GLTF = {"asset": {"version": "2.0"}, "materials": [
    {"name": "Mat", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}},
    {"name": "Mat", "pbrMetallicRoughness": {"baseColorFactor": [0, 1, 0, 1]}},
    {"name": "Other", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 1, 1]}},
]}


def _convert(source, target, *extra):
    result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(target), "--format", "json", *extra])
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)["diagnostics"]


@pytest.mark.parametrize("middle", ["usda", "mtlx"])
def test_gltf_materials_sharing_a_name_come_back_distinct(tmp_path, middle):
    source = tmp_path / "in.gltf"
    source.write_text(json.dumps(GLTF))
    notes = _convert(source, tmp_path / f"mid.{middle}")
    renamed = [n for n in notes if "same name" in n["message"]]
    assert len(renamed) == 1 and renamed[0]["location"]["material"] == "Mat"
    _convert(tmp_path / f"mid.{middle}", tmp_path / "back.gltf")
    back = json.loads((tmp_path / "back.gltf").read_text())["materials"]
    # distinct in the middle (Mat_2), and glTF's own names again at the end (glTF allows repeats)
    assert [m["name"] for m in back] == ["Mat", "Mat", "Other"]
    assert [m["pbrMetallicRoughness"]["baseColorFactor"][:3] for m in back] == [[1, 0, 0], [0, 1, 0], [0, 0, 1]]


def test_a_usd_material_with_its_preview_fallback_is_one_material(tmp_path):
    source = tmp_path / "in.gltf"
    source.write_text(json.dumps(GLTF))
    _convert(source, tmp_path / "mid.usda")
    asset = read_asset(str(tmp_path / "mid.usda"))
    assert len(asset.materials) == 6  # both shaders are read, so the rules check both
    primary = [m for m in asset.materials if not m.extra.get("fallback_of")]
    assert [(m.model, m.material_name, m.material_location.path) for m in primary] == [
        ("open_pbr_surface", "Mat", "/Looks/Mat"), ("open_pbr_surface", "Mat_2", "/Looks/Mat_2"),
        ("open_pbr_surface", "Other", "/Looks/Other")]
    validated = CliRunner().invoke(cli, ["validate", "--no-config", "--format", "json", str(tmp_path / "mid.usda")])
    assert json.loads(validated.stdout)["summary"]["materials"] == 3
    mtlx = tmp_path / "back.mtlx"
    _convert(tmp_path / "mid.usda", mtlx)
    text = mtlx.read_text()
    assert text.count("<surfacematerial") == 3 and "_Looks_" not in text


def test_iridescence_thickness_defaults_follow_gltf_both_ways(tmp_path):
    # KHR_materials_iridescence: iridescenceThicknessMaximum defaults to 400 nm (gltf_pbr's node: 100)
    source = tmp_path / "in.gltf"
    source.write_text(json.dumps({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_iridescence"],
                                  "materials": [{"name": "Absent", "extensions": {"KHR_materials_iridescence": {"iridescenceFactor": 1}}},
                                                {"name": "Hundred", "extensions": {"KHR_materials_iridescence": {
                                                    "iridescenceFactor": 1, "iridescenceThicknessMaximum": 100}}}]}))
    _convert(source, tmp_path / "mid.mtlx")
    thickness = {m.material_name: m.inputs["thin_film_thickness"].constant for m in read_asset(str(tmp_path / "mid.mtlx")).materials}
    assert thickness == {"Absent": pytest.approx(0.4), "Hundred": pytest.approx(0.1)}  # micrometres
    _convert(tmp_path / "mid.mtlx", tmp_path / "back.gltf")
    back = json.loads((tmp_path / "back.gltf").read_text())["materials"]
    assert [m["extensions"]["KHR_materials_iridescence"]["iridescenceThicknessMaximum"] for m in back] == [400.0, 100.0]


@pytest.mark.parametrize("middle", ["usda", "mtlx"])
def test_gltf_state_openpbr_cannot_hold_travels_and_comes_back(tmp_path, middle):
    state = {"name": "B", "doubleSided": True, "extras": {"studio": "x"},
             "extensions": {"KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.5}}}
    source = tmp_path / "in.gltf"
    source.write_text(json.dumps({"asset": {"version": "2.0"},
                                  "extensionsUsed": ["KHR_materials_diffuse_transmission", "KHR_materials_unlit"],
                                  "materials": [{"name": "A", "alphaMode": "MASK", "alphaCutoff": 0.3}, state,
                                                {"name": "C", "extensions": {"KHR_materials_unlit": {}}}]}))
    notes = _convert(source, tmp_path / f"mid.{middle}")
    said = " | ".join(f"{n['code']} {n['location']['material']}: {n['message']}" for n in notes)
    for kept in ("alphaMode MASK with alphaCutoff 0.3", "doubleSided true", "extras", "KHR_materials_unlit"):
        assert f"{kept} (glTF material state" in said
    # a thin material's diffuse transmission is OpenPBR's thin-walled subsurface, and comes back from it
    assert "KHR_materials_diffuse_transmission read as OpenPBR's thin-walled subsurface" in said
    _convert(tmp_path / f"mid.{middle}", tmp_path / "back.gltf")
    back = json.loads((tmp_path / "back.gltf").read_text())
    assert (back["materials"][0]["alphaMode"], back["materials"][0]["alphaCutoff"]) == ("MASK", 0.3)
    b = back["materials"][1]
    assert (b["doubleSided"], b["extras"], b["extensions"]["KHR_materials_diffuse_transmission"]) == (
        True, {"studio": "x"}, {"diffuseTransmissionFactor": 0.5})
    assert "KHR_materials_unlit" in back["materials"][2]["extensions"]
    assert {"KHR_materials_diffuse_transmission", "KHR_materials_unlit"} <= set(back["extensionsUsed"])


@pytest.mark.parametrize("text", ['{"extensions": [1, 2]}', '{"doubleSided": "yes"}', "not json", "[" * 5000,
                                  '{"extensions": {"X": 3}}'])
def test_a_hostile_side_channel_is_ignored_not_a_crash(tmp_path, text):
    from xml.sax.saxutils import quoteattr

    source = tmp_path / "in.mtlx"
    source.write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n'
                      '  <open_pbr_surface name="S" type="surfaceshader" />\n'
                      f'  <surfacematerial name="M" type="material" openpbr_gltf={quoteattr(text)}>\n'
                      '    <input name="surfaceshader" type="surfaceshader" nodename="S" />\n  </surfacematerial>\n</materialx>\n')
    _convert(source, tmp_path / "out.gltf")
    material = json.loads((tmp_path / "out.gltf").read_text())["materials"][0]
    assert "doubleSided" not in material and not material.get("extensions")


def test_a_restored_glTF_name_yields_to_a_rename_made_since(tmp_path):
    source = tmp_path / "in.gltf"
    source.write_text(json.dumps(GLTF))
    _convert(source, tmp_path / "mid.mtlx")
    text = (tmp_path / "mid.mtlx").read_text()
    assert 'name="Mat_2"' in text
    (tmp_path / "edited.mtlx").write_text(text.replace('name="Mat_2"', 'name="Chair"'))
    _convert(tmp_path / "edited.mtlx", tmp_path / "back.gltf")
    back = json.loads((tmp_path / "back.gltf").read_text())["materials"]
    assert [m["name"] for m in back] == ["Mat", "Chair", "Other"]
