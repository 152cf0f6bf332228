"""`--allow-outside` (and the configuration's `allow-outside`): a folder outside an asset's own that
its textures, XIncludes, USD arcs and glTF resources may be read from. Without it, each is reported
(OPBR704, OPBR009, OPBR1011) and never opened; with it, the same files are read and the findings go.
Decided by the one path guard (openpbr_tools.io.paths) for every command."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner
from PIL import Image

from cli.group import cli
from openpbr_tools.validate import Options, validate_paths

LOOK = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709" xmlns:xi="http://www.w3.org/2001/XInclude">
  <xi:include href="../shared/lib.mtlx" />
  <image name="img" type="color3">
    <input name="file" type="filename" value="../shared/albedo.png" colorspace="srgb_texture" />
  </image>
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodename="img" />
    <input name="specular_roughness" type="float" nodename="rough" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
"""
LIBRARY = """<?xml version="1.0"?>
<materialx version="1.39">
  <constant name="rough" type="float">
    <input name="value" type="float" value="0.4" />
  </constant>
</materialx>
"""
STAGE = """#usda 1.0
(
    defaultPrim = "World"
    metersPerUnit = 1
    upAxis = "Y"
)

def Xform "World" (
    references = @../shared/geometry.usda@
)
{
}
"""
GEOMETRY = '#usda 1.0\n(\n    defaultPrim = "G"\n    metersPerUnit = 1\n    upAxis = "Y"\n)\n\ndef Xform "G"\n{\n}\n'


@pytest.fixture()
def tree(tmp_path):
    (tmp_path / "asset").mkdir()
    (tmp_path / "shared").mkdir()
    Image.new("RGB", (4, 4), (200, 100, 50)).save(tmp_path / "shared" / "albedo.png")
    (tmp_path / "shared" / "lib.mtlx").write_text(LIBRARY)
    (tmp_path / "shared" / "geometry.usda").write_text(GEOMETRY)
    (tmp_path / "asset" / "look.mtlx").write_text(LOOK)
    (tmp_path / "asset" / "stage.usda").write_text(STAGE)
    (tmp_path / "asset" / "m.gltf").write_text(json.dumps({
        "asset": {"version": "2.0"}, "images": [{"uri": "../shared/albedo.png"}], "textures": [{"source": 0}],
        "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]}))
    return tmp_path


def _codes(path, allow=()) -> set[str]:
    report = validate_paths([str(path)], options=Options(use_config=False, jobs=1, allow_outside=tuple(map(str, allow))))
    return {d.code for d in report.diagnostics if str(d.severity) in ("error", "warning")}


@pytest.mark.parametrize("name, refused", [
    ("look.mtlx", {"OPBR009"}),  # the include (the texture, an image that is there, is OPBR723: information)
    ("stage.usda", set()),  # its ../shared/geometry.usda is there: OPBR1039, an info (not opened), below
    ("m.gltf", {"OPBR704"}),
])
def test_outside_references_are_reported_and_allowed_folders_are_read(tree, name, refused):
    assert refused <= _codes(tree / "asset" / name)
    assert not _codes(tree / "asset" / name, allow=[tree / "shared"])
    if name == "stage.usda":
        shared = validate_paths([str(tree / "asset" / name)], options=Options(use_config=False, jobs=1))
        assert "OPBR1039" in {d.code for d in shared.diagnostics}
        allowed = validate_paths([str(tree / "asset" / name)],
                                 options=Options(use_config=False, jobs=1, allow_outside=(str(tree / "shared"),)))
        assert "OPBR1039" not in {d.code for d in allowed.diagnostics}


def test_allowing_one_folder_does_not_allow_its_neighbours(tree):
    (tree / "other").mkdir()
    assert {"OPBR009"} <= _codes(tree / "asset" / "look.mtlx", allow=[tree / "other"])
    report = validate_paths([str(tree / "asset" / "look.mtlx")],
                            options=Options(use_config=False, jobs=1, allow_outside=(str(tree / "other"),)))
    assert "OPBR723" in {d.code for d in report.diagnostics}  # the texture in ../shared: not read


def test_the_configuration_allows_folders_relative_to_itself(tree, monkeypatch):
    (tree / "asset" / ".openpbr.toml").write_text('allow-outside = ["../shared"]\n')
    monkeypatch.chdir(tree / "asset")  # the project the command runs in
    report = validate_paths([str(tree / "asset" / "look.mtlx")], options=Options(jobs=1))
    assert not [d for d in report.diagnostics if str(d.severity) in ("error", "warning")]


def test_a_configuration_shipped_inside_an_asset_validated_from_elsewhere_widens_nothing(tree, monkeypatch, tmp_path_factory):
    """The red team's M-15: an asset folder carrying its own .openpbr.toml with allow-outside = ["/"], validated
    from another working directory, would grant itself the whole disk. Only the invoking project's configuration
    widens the guard; the texture outside stays a finding and is never opened."""
    (tree / "asset" / ".openpbr.toml").write_text('allow-outside = ["/"]\n')
    for where in (tmp_path_factory.mktemp("elsewhere"), tree):  # beside it, and above it (the review's case)
        monkeypatch.chdir(where)
        report = validate_paths([str(tree / "asset" / "look.mtlx")], options=Options(jobs=1))
        assert "OPBR723" in {d.code for d in report.diagnostics}  # ../shared/... climbs out: named, not read


def test_the_validate_command_takes_allow_outside(tree):
    look = str(tree / "asset" / "look.mtlx")
    refused = CliRunner().invoke(cli, ["validate", "--no-config", look])
    allowed = CliRunner().invoke(cli, ["validate", "--no-config", look, "--allow-outside", str(tree / "shared")])
    assert refused.exit_code == 1 and allowed.exit_code == 0, allowed.output


def test_convert_reads_the_allowed_folder_and_refuses_without_it(tree):
    look = tree / "asset" / "plain.mtlx"
    look.write_text(LOOK.replace('    <input name="specular_roughness" type="float" nodename="rough" />\n', ""))
    refused = CliRunner().invoke(cli, ["convert", str(look), "-o", str(tree / "refused.gltf")])
    assert refused.exit_code == 2 and "--allow-outside" in refused.output and not (tree / "refused.gltf").exists()
    result = CliRunner().invoke(cli, ["convert", str(look), "-o", str(tree / "out.gltf"),
                                      "--allow-outside", str(tree / "shared")])
    assert result.exit_code == 0, result.output
    gltf = json.loads((tree / "out.gltf").read_text())
    assert "baseColorTexture" in gltf["materials"][0]["pbrMetallicRoughness"] and len(gltf["images"]) == 1
