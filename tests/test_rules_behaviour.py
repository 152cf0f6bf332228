"""Behaviour of the rules beyond their documented examples: hints, inference, inheritance."""

from __future__ import annotations

import pytest

from openpbr_tools.validate import validate_file


def findings(path, code):
    return [d for d in validate_file(str(path)).diagnostics if d.code == code]


def shader(*inputs: str, attributes: str = "") -> str:
    body = "\n".join(f"  {line}" for line in inputs)
    return f'<open_pbr_surface name="S" type="surfaceshader"{attributes}>\n{body}\n</open_pbr_surface>'


def test_unknown_input_suggests_the_closest_name(write_mtlx):
    path = write_mtlx(shader('<input name="specular_roughnes" type="float" value="0.3" />'))
    (finding,) = findings(path, "OPBR101")
    assert finding.hint == "did you mean 'specular_roughness'?"
    assert finding.location.input == "specular_roughnes"


def test_misspelt_category_suggests_open_pbr_surface(write_mtlx):
    path = write_mtlx('<open_pbr_surfce name="S" type="surfaceshader" />')
    (finding,) = findings(path, "OPBR104")
    assert "open_pbr_surface" in finding.hint


@pytest.mark.parametrize(
    "name, meant",
    [("srgb_tx", "srgb_texture"), ("sRGB_Texture", "srgb_texture"), ("ACES - ACEScg", "acescg"),
     ("Utility - Raw", "none"), ("lin_rec709_scene", "lin_rec709")],
)
def test_unknown_colorspace_names_the_meant_one(write_mtlx, name, meant):
    path = write_mtlx(shader(f'<input name="base_color" type="color3" value="0.5, 0.5, 0.5" colorspace="{name}" />'))
    (finding,) = findings(path, "OPBR502")
    assert finding.hint == f"did you mean {meant!r}?"


def test_unknown_document_colorspace_is_reported_once(write_mtlx):
    document = ('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="ACEScg">\n'
                + shader('<input name="base_color" type="color3" value="0.5, 0.5, 0.5" />') + "\n</materialx>\n")
    assert len(findings(write_mtlx(document), "OPBR502")) == 1


@pytest.mark.parametrize(
    "inputs, version, basis_word",
    [
        (['<input name="transmission_dispersion" type="float" value="0.1" />'], "0.2", "inferred"),
        (['<input name="base_roughness" type="float" value="0.1" />'], "0.3", "consistent with 0.2 to 0.3"),
        (['<input name="base_diffuse_roughness" type="float" value="0.1" />',
          '<input name="specular_anisotropy" type="float" value="0.1" />'], "0.4", "inferred"),
        (['<input name="coat_darkening" type="float" value="0.5" />'], "1.1.1", "consistent with 0.5 to 1.1.1"),
    ],
)
def test_version_is_inferred_from_input_names(write_mtlx, inputs, version, basis_word):
    from openpbr_tools.io import read_asset

    (material,) = read_asset(write_mtlx(shader(*inputs))).materials
    assert material.version == version
    assert basis_word in material.version_basis


def test_legacy_input_names_its_versions_and_the_fix(write_mtlx):
    path = write_mtlx(shader('<input name="specular_ior_level" type="float" value="0.5" />',
                             '<input name="coat_darkening" type="float" value="1" />'))
    (finding,) = findings(path, "OPBR102")
    assert "0.2 to 0.3" in finding.message and "openpbr upgrade" in finding.hint


def test_decimal_comma_is_explained(write_mtlx):
    (finding,) = findings(write_mtlx(shader('<input name="specular_ior" type="float" value="1,5" />')), "OPBR202")
    assert "decimal comma" in finding.message


def test_colour_with_one_component_is_unparsable(write_mtlx):
    (finding,) = findings(write_mtlx(shader('<input name="base_color" type="color3" value="0.5" />')), "OPBR202")
    assert "1 components" in finding.message


@pytest.mark.parametrize("text", ["0.5abc", "inf", "-inf", "1e400"])
def test_trailing_garbage_and_overflow(write_mtlx, text):
    codes = [d.code for d in validate_file(str(write_mtlx(shader(f'<input name="base_weight" type="float" value="{text}" />')))).diagnostics]
    assert ("OPBR202" in codes) if text == "0.5abc" else ("OPBR203" in codes)


def test_data_texture_inheriting_document_colorspace_is_an_error(write_mtlx):
    document = ('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="srgb_texture">\n'
                '<image name="orm" type="color3"><input name="file" type="filename" value="orm.png" /></image>\n'
                '<extract name="g" type="float"><input name="in" type="color3" nodename="orm" /><input name="index" type="integer" value="1" /></extract>\n'
                + shader('<input name="specular_roughness" type="float" nodename="g" />') + "\n</materialx>\n")
    (finding,) = findings(write_mtlx(document, files=("orm.png",)), "OPBR504")
    assert "(inherited)" in finding.message


def test_linear_data_texture_in_matching_working_space_is_fine(write_mtlx):
    fragment = ('<image name="orm" type="color3"><input name="file" type="filename" value="orm.png" colorspace="lin_rec709" /></image>\n'
                '<extract name="g" type="float"><input name="in" type="color3" nodename="orm" /><input name="index" type="integer" value="1" /></extract>\n'
                + shader('<input name="specular_roughness" type="float" nodename="g" />'))
    assert not findings(write_mtlx(fragment, files=("orm.png",)), "OPBR504")


def test_udim_tiles_are_found(write_mtlx):
    fragment = ('<image name="img" type="color3"><input name="file" type="filename" value="tex/wood.&lt;UDIM&gt;.png" colorspace="srgb_texture" /></image>\n'
                + shader('<input name="base_color" type="color3" nodename="img" />'))
    assert findings(write_mtlx(fragment, name="a.mtlx"), "OPBR701")
    assert not findings(write_mtlx(fragment, name="b.mtlx", files=("tex/wood.1002.png",)), "OPBR701")


def test_fileprefix_is_applied_before_resolving(write_mtlx):
    fragment = ('<image name="img" type="color3"><input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" /></image>\n'
                + shader('<input name="base_color" type="color3" nodename="img" />'))
    document = ('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709" fileprefix="textures/">\n'
                + fragment + "\n</materialx>\n")
    assert findings(write_mtlx(document, files=("albedo.png",)), "OPBR701")
    assert not findings(write_mtlx(document, name="c.mtlx", files=("textures/albedo.png",)), "OPBR701")


def test_dark_metal_is_judged_in_linear_rec709_after_colour_conversion(write_mtlx):
    # ACEScg (0.35, 0.35, 0.35) is neutral grey: the same luminance 0.35 in linear Rec.709, below 0.40.
    inputs = ('<input name="base_metalness" type="float" value="1" />',
              '<input name="base_color" type="color3" value="0.35, 0.35, 0.35" />')
    document = ('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="acescg">\n'
                + shader(*inputs) + "\n</materialx>\n")
    assert findings(write_mtlx(document), "OPBR901")
    bright = document.replace("0.35, 0.35, 0.35", "0.9, 0.9, 0.9")
    assert not findings(write_mtlx(bright, name="bright.mtlx"), "OPBR901")


def test_standard_surface_values_are_range_checked(write_mtlx):
    fragment = '<standard_surface name="S" type="surfaceshader">\n  <input name="base" type="float" value="2" />\n</standard_surface>'
    assert findings(write_mtlx(fragment), "OPBR301")


def test_version_attribute_contradicting_nodedef(write_mtlx):
    path = write_mtlx(shader(attributes=' version="0.5" nodedef="ND_open_pbr_surface_surfaceshader"'))
    assert any("nodedef" in d.message for d in findings(path, "OPBR106"))


def test_uniform_input_connected_to_texture(write_mtlx):
    fragment = ('<image name="mask" type="float"><input name="file" type="filename" value="mask.png" colorspace="none" /></image>\n'
                + shader('<input name="geometry_thin_walled" type="boolean" nodename="mask" />'))
    assert findings(write_mtlx(fragment, files=("mask.png",)), "OPBR204")


def test_shader_reached_only_through_a_look_is_bound(write_mtlx):
    document = ('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
                + shader() + '\n<surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>\n'
                '<look name="L"><materialassign name="a" material="Missing" geom="/x" /></look>\n</materialx>\n')
    path = write_mtlx(document)
    assert any("Missing" in d.message for d in findings(path, "OPBR802"))
    assert not findings(path, "OPBR804")


def test_shader_node_of_the_wrong_type_has_no_definition(write_mtlx):
    path = write_mtlx('<open_pbr_surface name="S" type="material" />')
    assert any("outputs type 'material'" in d.message for d in findings(path, "OPBR105"))
