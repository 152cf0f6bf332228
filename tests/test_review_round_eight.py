"""The defects a review of session 21's diff reproduced, each held by the case that showed it: a baked texture named
like the input's own texture, an include that climbs back inside the asset, a SARIF file name that is not UTF-8,
primitives that share everything but their UVs, corners a float32 step apart across a weld cell, and upgrade's output
naming a file its input includes."""

from __future__ import annotations

import hashlib
import json
import os
import zlib
from urllib.parse import unquote

import pytest
from click.testing import CliRunner
from PIL import Image

from cli.group import cli
from openpbr_tools.io.gltf import surfaces
from redteam_support import findings, report
from test_gltf_surfaces import _NORMAL_MAPPED, gltf, mesh
from test_gltf_geometry_round_seven import _FLOAT, data_uri, document, png

_SHADER = '''<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
{body}</materialx>
'''


def _digest(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_a_baked_texture_never_writes_over_the_inputs_own_texture(tmp_path):
    """The input reads out_textures/P_diffuseColor.png, the name a UsdPreviewSurface bake of P's diffuse colour
    takes in the output's texture folder: the bake takes the next free name, and the input's file is untouched."""
    (tmp_path / "out_textures").mkdir()
    texture = tmp_path / "out_textures" / "P_diffuseColor.png"
    image = Image.new("RGB", (4, 4))
    image.putdata([(16 * i, 255 - 16 * i, 100) for i in range(16)])
    image.save(texture)
    before = _digest(texture)
    source = tmp_path / "in.mtlx"
    source.write_text(_SHADER.format(body='''  <image name="tex" type="color3">
    <input name="file" type="filename" value="out_textures/P_diffuseColor.png" colorspace="srgb_texture" />
  </image>
  <open_pbr_surface name="P" type="surfaceshader">
    <input name="base_weight" type="float" value="0.5" />
    <input name="base_color" type="color3" nodename="tex" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="P" />
  </surfacematerial>
'''), encoding="utf-8")
    for _ in range(2):  # and a re-run with --force keeps its own name (the same bytes)
        result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(tmp_path / "out.usda"), "--force"])
        assert result.exit_code == 0, result.output
    assert _digest(texture) == before
    assert sorted(os.listdir(tmp_path / "out_textures")) == ["P_diffuseColor.png", "P_diffuseColor_2.png"]


def test_an_include_that_climbs_back_inside_the_asset_is_read(tmp_path):
    """main.mtlx includes libs/x.mtlx, which includes ../common.mtlx: MaterialX reads common's material M as the
    asset's own, and its base_weight 3 is out of range; nothing leaves the asset's folder."""
    (tmp_path / "libs").mkdir()
    include = '<?xml version="1.0"?>\n<materialx xmlns:xi="http://www.w3.org/2001/XInclude" version="1.39">\n' \
              '  <xi:include href="{}" />\n</materialx>\n'
    (tmp_path / "main.mtlx").write_text(include.format("libs/x.mtlx"), encoding="utf-8")
    (tmp_path / "libs" / "x.mtlx").write_text(include.format("../common.mtlx"), encoding="utf-8")
    (tmp_path / "common.mtlx").write_text(_SHADER.format(body='''  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_weight" type="float" value="3.0" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
'''), encoding="utf-8")
    found = findings(tmp_path / "main.mtlx")
    assert [f[0] for f in found] == ["OPBR301"]  # (no OPBR009: the include stays inside the asset)


def test_a_sarif_report_names_a_file_whose_name_is_not_utf8(tmp_path, monkeypatch):
    name = os.fsdecode(b"caf\xe9.gltf")
    monkeypatch.chdir(tmp_path)
    with open(os.fsencode(tmp_path) + b"/caf\xe9.gltf", "w", encoding="utf-8") as handle:
        json.dump({"asset": {"version": "2.0"}, "materials": [{"name": "M", "pbrMetallicRoughness":
                                                               {"roughnessFactor": 2.0}}]}, handle)
    result = CliRunner().invoke(cli, ["validate", "--no-config", "--format", "sarif", "."])
    assert result.exit_code == 1  # (the roughness: a finding; it was an uncaught UnicodeEncodeError)
    (uri,) = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
              for r in json.loads(result.stdout)["runs"][0]["results"]}
    assert os.fsdecode(unquote(uri, errors="surrogateescape")).endswith(name) and uri.endswith("caf%E9.gltf")


def test_primitives_that_differ_only_in_their_uvs_are_judged_each_on_its_own(tmp_path):
    """OPBR1247 reads the normal map's UV set: two primitives sharing positions, normals, tangents and indices but
    not their TEXCOORD_0 are two verdicts (the first one's was reused for both)."""
    positions, normals, tangents, straight_uvs, indices = mesh()  # tangents along +u everywhere, w = +1
    _, _, _, uvs, _ = mesh(mirrored=(1, 3, 5))  # three faces' islands mirrored: those tangents are wrong there
    root = document({"POSITION": ("VEC3", positions, _FLOAT), "NORMAL": ("VEC3", normals, _FLOAT),
                     "TANGENT": ("VEC4", tangents, _FLOAT), "TEXCOORD_0": ("VEC2", uvs, _FLOAT),
                     "uv_straight": ("VEC2", straight_uvs, _FLOAT)}, indices, _NORMAL_MAPPED,
                    images=[{"uri": data_uri(png(4, (128, 128, 255)))}])
    first = root["meshes"][0]["primitives"][0]
    second = {**first, "attributes": {**first["attributes"], "TEXCOORD_0": first["attributes"]["TANGENT"] + 2}}
    # (accessor order in the helper: POSITION, NORMAL, TANGENT, TEXCOORD_0, uv_straight, indices)
    assert root["accessors"][second["attributes"]["TEXCOORD_0"]]["type"] == "VEC2"
    for order, broken in (([second, first], "/meshes/0/primitives/1"), ([first, second], "/meshes/0/primitives/0")):
        root["meshes"][0]["primitives"] = order
        path = tmp_path / "m.gltf"
        path.write_text(json.dumps(root), encoding="utf-8")
        assert [f[2] for f in findings(path) if f[0] == "OPBR1247"] == [f"{broken}/attributes"]


def test_corners_a_float32_step_apart_across_a_weld_cell_are_one(tmp_path):
    """A closed unit cube split per face, one corner's copies moved by a float32 step to either side of where a
    single rounding grid would cut: still closed, so a volume on it is no finding."""
    positions, normals, tangents, uvs, indices = mesh()
    cut = 0.5 + 2.0 * surfaces.WELD * 0.5  # (a rounding grid of WELD over the extent 1 cuts at half a cell)
    moved = [p for p in positions]
    for index in range(0, len(moved), 3):
        if moved[index] == 0.5 and moved[index + 1] == 0.5 and moved[index + 2] == 0.5:
            moved[index] = cut + (1e-7 if index % 2 else -1e-7)
    glass = {"name": "Glass", "pbrMetallicRoughness": {"metallicFactor": 0.0},
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                            "KHR_materials_volume": {"thicknessFactor": 0.02}}}
    root = document({"POSITION": ("VEC3", moved, _FLOAT), "NORMAL": ("VEC3", normals, _FLOAT)}, indices, glass,
                    extensionsUsed=sorted(glass["extensions"]))
    path = tmp_path / "cube.gltf"
    path.write_text(json.dumps(root), encoding="utf-8")
    assert "OPBR1248" not in {f[0] for f in findings(path)}


def test_upgrade_never_writes_over_a_file_its_input_includes(tmp_path):
    library = tmp_path / "lib.mtlx"
    library.write_text(_SHADER.format(body='  <open_pbr_surface name="S" type="surfaceshader" />\n'), encoding="utf-8")
    source = tmp_path / "main.mtlx"
    source.write_text('<?xml version="1.0"?>\n<materialx xmlns:xi="http://www.w3.org/2001/XInclude" version="1.39">\n'
                      '  <xi:include href="lib.mtlx" />\n</materialx>\n', encoding="utf-8")
    before = _digest(library)
    result = CliRunner().invoke(cli, ["upgrade", str(source), "-o", str(library), "--force"])
    assert result.exit_code == 2 and "a file the input reads" in result.output
    assert _digest(library) == before
