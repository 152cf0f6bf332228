"""``openpbr preview`` and ``openpbr compare`` on small .mtlx files."""

import json

import pytest
from click.testing import CliRunner

from cli.group import cli

HEADER = '<?xml version="1.0"?>\n<materialx version="1.39">\n'
FOOTER = "</materialx>\n"


def shader(node, name, inputs):
    lines = [f'  <{node} name="{name}" type="surfaceshader">']
    for key, (kind, value) in inputs.items():
        lines.append(f'    <input name="{key}" type="{kind}" value="{value}" />')
    lines.append(f"  </{node}>")
    lines.append(f'  <surfacematerial name="M_{name}" type="material">')
    lines.append(f'    <input name="surfaceshader" type="surfaceshader" nodename="{name}" />')
    lines.append("  </surfacematerial>")
    return "\n".join(lines) + "\n"


@pytest.fixture
def files(tmp_path):
    openpbr = HEADER
    openpbr += shader("open_pbr_surface", "red", {"base_color": ("color3", "0.8, 0.1, 0.1"), "specular_roughness": ("float", "0.4")})
    openpbr += shader("open_pbr_surface", "gold", {"base_color": ("color3", "1, 0.77, 0.34"), "base_metalness": ("float", "1"), "specular_roughness": ("float", "0.3")})
    openpbr += FOOTER
    gltf = HEADER
    gltf += shader("gltf_pbr", "red", {"base_color": ("color3", "0.8, 0.1, 0.1"), "metallic": ("float", "0"), "roughness": ("float", "0.4")})
    gltf += shader("gltf_pbr", "gold", {"base_color": ("color3", "1, 0.77, 0.34"), "metallic": ("float", "1"), "roughness": ("float", "0.3")})
    gltf += FOOTER
    blue = HEADER + shader("UsdPreviewSurface", "blue", {"diffuseColor": ("color3", "0.1, 0.2, 0.8")}) + FOOTER
    paths = {"openpbr": tmp_path / "a.mtlx", "gltf": tmp_path / "b.mtlx", "blue": tmp_path / "blue.mtlx"}
    paths["openpbr"].write_text(openpbr)
    paths["gltf"].write_text(gltf)
    paths["blue"].write_text(blue)
    return paths


def test_preview_writes_a_contact_sheet(files, tmp_path):
    from PIL import Image

    out = tmp_path / "sheet.png"
    result = CliRunner().invoke(cli, ["preview", str(files["openpbr"]), "-o", str(out), "--size", "64"])
    assert result.exit_code == 0, result.output
    with Image.open(out) as image:
        assert image.format == "PNG"
        assert image.size[0] == 2 * 64 and image.size[1] > 64  # two swatches and a label row
        red = image.getpixel((32, 32))
        assert red[0] > 2 * red[1]


def test_preview_of_an_unreadable_file_exits_2(tmp_path):
    bad = tmp_path / "broken.mtlx"
    bad.write_text("<materialx")
    result = CliRunner().invoke(cli, ["preview", str(bad), "-o", str(tmp_path / "x.png")])
    assert result.exit_code == 2


def test_compare_reports_each_pair_as_json(files):
    result = CliRunner().invoke(cli, ["compare", str(files["openpbr"]), str(files["gltf"]), "--format", "json", "--size", "48"])
    assert result.exit_code == 0, result.output
    report = json.loads(result.output)
    names = sorted(pair["a"]["name"] for pair in report["pairs"])
    assert names == ["gold", "red"]
    for pair in report["pairs"]:
        assert set(pair["preview"]) == {"mean", "p95", "max", "samples"}
        assert pair["preview"]["mean"] < 2.0  # same look in both models


def test_compare_exits_1_above_the_threshold(files):
    result = CliRunner().invoke(cli, ["compare", str(files["openpbr"]), str(files["gltf"]), "--threshold", "0.01", "--size", "48"])
    assert result.exit_code == 1
    assert "FAIL" in result.output


def test_single_materials_are_paired_whatever_their_names(files, tmp_path):
    other = tmp_path / "other.mtlx"
    other.write_text(HEADER + shader("open_pbr_surface", "anything", {"base_color": ("color3", "0.1, 0.2, 0.8")}) + FOOTER)
    result = CliRunner().invoke(cli, ["compare", str(files["blue"]), str(other), "--format", "json", "--size", "32"])
    assert result.exit_code == 0, result.output
    assert len(json.loads(result.output)["pairs"]) == 1


def test_compare_without_common_names_exits_2(files):
    result = CliRunner().invoke(cli, ["compare", str(files["openpbr"]), str(files["blue"])])
    # Two materials against one: nothing matches by name.
    assert result.exit_code == 2
