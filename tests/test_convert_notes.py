"""The loss report of `openpbr convert` is typed data: every entry has a rule code that `openpbr rules`
documents, and is located at the source material and input it concerns; no code grades a note by
its wording (a reworded message keeps its code)."""

from __future__ import annotations

import json
import shutil

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.resources import data_dir
from openpbr_tools.rules import all_rules

SAMPLES = sorted(p.name for p in data_dir("samples").glob("*.mtlx")) + ["broken/vendor_export.mtlx",
                                                                         "broken/legacy_openpbr_0_2.mtlx"]
OUTPUTS = ("out.gltf", "out.glb", "out.usda", "out.usdz", "out.mtlx")


@pytest.fixture(scope="module")
def samples(tmp_path_factory):
    folder = tmp_path_factory.mktemp("samples")
    shutil.copytree(data_dir("samples"), folder, dirs_exist_ok=True)
    return folder


@pytest.mark.parametrize("output", OUTPUTS)
@pytest.mark.parametrize("sample", SAMPLES)
def test_every_note_has_a_documented_code_and_names_its_source_material_and_input(samples, tmp_path, sample, output):
    args = ["convert", str(samples / sample), "-o", str(tmp_path / output), "--format", "json"]
    if output.endswith(".mtlx"):
        args += ["--to", "standard_surface"]
    result = CliRunner().invoke(cli, args, catch_exceptions=False)
    if result.exit_code == 2:  # a packaged output refuses a texture outside the asset's folder: nothing written
        assert "outside the source asset's folder" in result.output and sample.startswith("broken/")
        assert not (tmp_path / output).exists()
        return
    report = json.loads(result.stdout)
    source = str(samples / sample)
    for entry in report["diagnostics"]:
        assert entry["code"] in all_rules(), entry
        location = entry["location"]
        assert location["file"] == source, entry
        assert location["material"] and location["input"], entry
        if "output" in entry:
            assert entry["output"]["file"] == str(tmp_path / output)


def test_a_writer_note_carries_the_place_in_the_written_file(tmp_path, write_mtlx):
    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                      '  <input name="specular_roughness" type="float" value="1.5" />\n</open_pbr_surface>')
    out = tmp_path / "out.gltf"
    result = CliRunner().invoke(cli, ["convert", str(path), "-o", str(out), "--format", "json"], catch_exceptions=False)
    clamped = [d for d in json.loads(result.stdout)["diagnostics"] if "clamped" in d["message"]]
    assert [d["code"] for d in clamped] == ["OPBR1104"]
    assert clamped[0]["location"]["input"] == "specular_roughness" and clamped[0]["location"]["material"] == "M"
    assert clamped[0]["output"] == {"file": str(out), "line": None, "path": "/materials/0", "input": None}


@pytest.mark.parametrize("output", ["out.gltf", "out.usda"])
def test_a_value_the_reader_could_not_read_is_reported_when_the_result_drops_it(tmp_path, write_mtlx, output):
    source = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                        '  <input name="base_weight" type="float" value="abc" />\n</open_pbr_surface>')
    result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / output), "--format", "json"])
    notes = [d for d in json.loads(result.stdout)["diagnostics"] if d["code"] == "OPBR1104"]
    assert [(n["severity"], n["location"].get("input")) for n in notes] == [("error", "base_weight")]


def test_a_gltf_alpha_mode_outside_its_enum_is_reported_not_dropped(tmp_path):
    source = tmp_path / "m.gltf"
    source.write_text(json.dumps({"asset": {"version": "2.0"}, "materials": [{"name": "M", "alphaMode": "TRANSPARENT"}]}))
    result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / "out.mtlx"), "--format", "json"])
    assert [d["code"] for d in json.loads(result.stdout)["diagnostics"]] == ["OPBR1104"]


def test_an_unreadable_value_kept_verbatim_in_the_same_model_is_not_reported_as_lost(tmp_path, write_mtlx):
    source = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                        '  <input name="base_weight" type="float" value="abc" />\n</open_pbr_surface>')
    result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / "out.mtlx"), "--format", "json"])
    assert "OPBR1104" not in {d["code"] for d in json.loads(result.stdout)["diagnostics"]}
    assert 'value="abc"' in (tmp_path / "out.mtlx").read_text()
