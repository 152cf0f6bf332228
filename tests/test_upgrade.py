"""`openpbr upgrade`: legacy OpenPBR materials rewritten for 1.1.1, with every change reported."""

from __future__ import annotations

import hashlib

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.io import read_asset
from openpbr_tools.translate.upgrade import fold_ior_level, upgrade, upgrade_mtlx_file
from openpbr_tools.validate import validate_file


def shader(*inputs: str, attributes: str = "") -> str:
    body = "\n".join(f"  {line}" for line in inputs)
    return f'<open_pbr_surface name="S" type="surfaceshader"{attributes}>\n{body}\n</open_pbr_surface>'


def f0(ior: float) -> float:
    return ((ior - 1) / (ior + 1)) ** 2


@pytest.mark.parametrize("ior, level", [(1.5, 0.5), (1.5, 0.0), (1.5, 1.0), (1.33, 0.25), (2.4, 0.8), (0.7, 0.9)])
def test_folded_ior_has_the_levelled_reflectance_at_normal_incidence(ior, level):
    # v0.2 spec: level 0 -> zero reflectivity, 0.5 -> unchanged, 1 -> double
    assert f0(fold_ior_level(ior, level)) == pytest.approx(2 * level * f0(ior), abs=1e-12)


def test_level_one_doubles_glass_reflectance():
    # F0(1.5) = 0.04; doubled 0.08; n = (1 + sqrt(0.08)) / (1 - sqrt(0.08)) = 1.788789...
    assert fold_ior_level(1.5, 1.0) == pytest.approx(1.7887887, abs=1e-6)


def _upgraded(write_mtlx, *inputs, name="doc.mtlx"):
    (material,) = read_asset(write_mtlx(shader(*inputs), name=name)).materials
    return upgrade(material)


def _codes(result):
    return [d.code for d in result.diagnostics]


def test_renames_are_exact_and_reported(write_mtlx):
    result = _upgraded(write_mtlx, '<input name="base_roughness" type="float" value="0.3" />',
                       '<input name="specular_anisotropy" type="float" value="0.4" />',
                       '<input name="subsurface_anisotropy" type="float" value="-0.2" />')
    inputs = result.material.inputs
    assert inputs["base_diffuse_roughness"].constant == 0.3
    assert inputs["specular_roughness_anisotropy"].constant == 0.4
    assert inputs["subsurface_scatter_anisotropy"].constant == -0.2
    assert _codes(result).count("OPBR1101") == 3
    assert result.material.version == "1.1.1"


def test_thin_film_nanometres_become_micrometres_with_the_film_switched_on(write_mtlx):
    result = _upgraded(write_mtlx, '<input name="base_roughness" type="float" value="0.3" />',
                       '<input name="thin_film_thickness" type="float" value="480" />')
    inputs = result.material.inputs
    assert inputs["thin_film_thickness"].constant == pytest.approx(0.48)
    assert inputs["thin_film_weight"].constant == 1.0
    assert inputs["thin_film_ior"].constant == 1.5  # 1.1 changed the default to 1.4: pinned
    assert "OPBR1105" in _codes(result)


def test_colour_opacity_becomes_its_mean_and_is_reported_approximate(write_mtlx):
    result = _upgraded(write_mtlx, '<input name="base_roughness" type="float" value="0.3" />',
                       '<input name="geometry_opacity" type="color3" value="0.2, 0.5, 0.8" />')
    opacity = result.material.inputs["geometry_opacity"]
    assert opacity.type == "float" and opacity.constant == pytest.approx(0.5)
    assert "OPBR1103" in _codes(result)


def test_grey_colour_opacity_is_exact(write_mtlx):
    result = _upgraded(write_mtlx, '<input name="base_roughness" type="float" value="0.3" />',
                       '<input name="geometry_opacity" type="color3" value="0.4, 0.4, 0.4" />')
    assert "OPBR1103" not in _codes(result)


def test_textured_ior_level_is_reported_as_not_carried(write_mtlx):
    fragment = ('<image name="lvl" type="float"><input name="file" type="filename" value="lvl.png" /></image>\n'
                + shader('<input name="specular_ior_level" type="float" nodename="lvl" />'))
    (material,) = read_asset(write_mtlx(fragment)).materials
    result = upgrade(material)
    assert "OPBR1104" in _codes(result) and "specular_ior_level" not in result.material.inputs


def test_conflicting_old_and_new_names_keep_the_new_one(write_mtlx):
    result = _upgraded(write_mtlx, '<input name="base_roughness" type="float" value="0.3" />',
                       '<input name="base_diffuse_roughness" type="float" value="0.7" />')
    assert result.material.inputs["base_diffuse_roughness"].constant == 0.7
    assert "OPBR1104" in _codes(result)


def test_metal_with_weighted_tint_reports_the_1_1_1_edge_change(write_mtlx):
    (material,) = read_asset(write_mtlx(shader(
        '<input name="base_metalness" type="float" value="1" />',
        '<input name="specular_weight" type="float" value="0.5" />',
        '<input name="specular_color" type="color3" value="1, 0.8, 0.6" />', attributes=' version="1.1"'))).materials
    assert "OPBR1107" in _codes(upgrade(material))


def test_rotation_is_carried_by_a_rotated_tangent_that_materialx_accepts(write_mtlx, tmp_path):
    import MaterialX as mx

    from openpbr_tools.io.mtlx.library import standard_library

    path = write_mtlx(shader('<input name="specular_anisotropy" type="float" value="0.6" />',
                             '<input name="specular_rotation" type="float" value="0.125" />',
                             '<input name="base_roughness" type="float" value="0.1" />'))
    result = upgrade_mtlx_file(str(path))
    document = mx.createDocument()
    mx.readFromXmlString(document, result.text)
    rotate = [n for n in document.getNodes() if n.getCategory() == "rotate3d"]
    assert len(rotate) == 1 and float(rotate[0].getInputValue("amount")) == pytest.approx(45.0)
    assert document.getNode("S").getInput("geometry_tangent").getNodeName() == rotate[0].getName()
    document.setDataLibrary(standard_library())
    assert document.validate()[0], document.validate()[1]


def test_upgraded_document_validates_as_current_and_keeps_the_rest(write_mtlx, tmp_path):
    fragment = (shader('<input name="base_roughness" type="float" value="0.3" />',
                       '<input name="coat_ior_level" type="float" value="0.25" />',
                       '<input name="coat_ior" type="float" value="1.6" />')
                + '\n<look name="L"><materialassign name="a" material="M" geom="/x" /></look>')
    source = write_mtlx(fragment)
    before = hashlib.sha256(source.read_bytes()).hexdigest()
    out = tmp_path / "out.mtlx"
    run = CliRunner().invoke(cli, ["upgrade", str(source), "-o", str(out)])
    assert run.exit_code == 0, run.output
    assert hashlib.sha256(source.read_bytes()).hexdigest() == before  # the input is never modified
    codes = [d.code for d in validate_file(str(out)).diagnostics]
    assert not {"OPBR102", "OPBR402", "OPBR403"} & set(codes)
    assert '<look name="L">' in out.read_text()
    (material,) = read_asset(out).materials
    assert f0(material.inputs["coat_ior"].constant) == pytest.approx(2 * 0.25 * f0(1.6))


def test_upgrade_refuses_to_overwrite_without_force_and_never_writes_its_input(write_mtlx, tmp_path):
    source = write_mtlx(shader('<input name="base_roughness" type="float" value="0.3" />'))
    out = tmp_path / "out.mtlx"
    out.write_text("keep me")
    assert CliRunner().invoke(cli, ["upgrade", str(source), "-o", str(out)]).exit_code == 2
    assert out.read_text() == "keep me"
    assert CliRunner().invoke(cli, ["upgrade", str(source), "-o", str(out), "--force"]).exit_code == 0
    assert CliRunner().invoke(cli, ["upgrade", str(source), "-o", str(source), "--force"]).exit_code == 2


def test_upgrade_output_is_deterministic(write_mtlx):
    path = write_mtlx(shader('<input name="specular_anisotropy" type="float" value="0.6" />',
                             '<input name="specular_rotation" type="float" value="0.3" />'))
    assert upgrade_mtlx_file(str(path)).text == upgrade_mtlx_file(str(path)).text


def test_unreadable_input_exits_two(tmp_path):
    bad = tmp_path / "bad.mtlx"
    bad.write_bytes(b"\x00\xff")
    run = CliRunner().invoke(cli, ["upgrade", str(bad), "-o", str(tmp_path / "o.mtlx")])
    assert run.exit_code == 2 and "Traceback" not in run.output and not (tmp_path / "o.mtlx").exists()
