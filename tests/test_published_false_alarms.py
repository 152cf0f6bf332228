"""Findings that published, working assets used to get and must not: each test is the smallest
document with the construct a published file uses (the file it comes from is named)."""

from __future__ import annotations

import pytest

from glsupport import validated
from openpbr_tools.io import read_asset


def test_a_multi_output_image_connection_takes_the_type_of_the_named_output(write_mtlx, codes_of):
    # MaterialX's resources/Materials/Examples/GltfPbr/gltf_pbr_boombox.mtlx
    path = write_mtlx('''<gltf_colorimage name="img" type="multioutput">
  <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />
</gltf_colorimage>
<gltf_pbr name="S" type="surfaceshader">
  <input name="base_color" type="color3" nodename="img" output="outcolor" />
  <input name="alpha" type="float" nodename="img" output="outa" />
</gltf_pbr>''', files=("albedo.png",))
    assert "OPBR702" not in codes_of(path)
    inputs = read_asset(str(path)).materials[0].inputs
    assert inputs["base_color"].texture.image_type == "color3" and inputs["base_color"].texture.channels is None
    assert inputs["alpha"].texture.image_type == "float" and inputs["alpha"].texture.channels == (3,)


def test_the_alpha_of_an_srgb_texture_is_not_colour_managed_in_usd(tmp_path):
    # OpenUSD testPreviewSurfaceOpacityThreshold.usda, usd-wg AlphaBlendSortTest.usda
    from openpbr_tools.validate import validate_paths

    (tmp_path / "cutout.png").write_bytes(b"")
    (tmp_path / "m.usda").write_text('''#usda 1.0
(
    metersPerUnit = 1
)
def Material "M"
{
    token outputs:surface.connect = </M/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        float inputs:opacity.connect = </M/T.outputs:a>
        color3f inputs:diffuseColor.connect = </M/T.outputs:rgb>
        token outputs:surface
    }
    def Shader "T"
    {
        uniform token info:id = "UsdUVTexture"
        asset inputs:file = @cutout.png@
        token inputs:sourceColorSpace = "sRGB"
        float outputs:a
        float3 outputs:rgb
    }
}
''', encoding="utf-8")
    codes = {d.code for d in validate_paths([str(tmp_path / "m.usda")]).diagnostics}
    assert "OPBR504" not in codes


def test_the_alpha_of_a_color4_image_is_not_colour_managed_in_materialx(write_mtlx, codes_of):
    path = write_mtlx('''<image name="img" type="color4">
  <input name="file" type="filename" value="cutout.png" colorspace="srgb_texture" />
</image>
<extract name="a" type="float">
  <input name="in" type="color4" nodename="img" />
  <input name="index" type="integer" value="3" />
</extract>
<open_pbr_surface name="S" type="surfaceshader">
  <input name="geometry_opacity" type="float" nodename="a" />
</open_pbr_surface>''', files=("cutout.png",))
    assert "OPBR504" not in codes_of(path)


def test_the_red_of_an_srgb_color4_image_on_a_data_input_is_still_reported(write_mtlx, codes_of):
    path = write_mtlx('''<image name="img" type="color4">
  <input name="file" type="filename" value="rough.png" colorspace="srgb_texture" />
</image>
<extract name="r" type="float">
  <input name="in" type="color4" nodename="img" />
  <input name="index" type="integer" value="0" />
</extract>
<open_pbr_surface name="S" type="surfaceshader">
  <input name="specular_roughness" type="float" nodename="r" />
</open_pbr_surface>''', files=("rough.png",))
    assert "OPBR504" in codes_of(path)


LOOK = '''<?xml version="1.0"?>
<materialx version="1.39">
  <xi:include href="{href}" />
  <look name="L">
    <materialassign name="assign" material="Mb" geom="/a" />
  </look>
</materialx>
'''
LIBRARY = '''<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <open_pbr_surface name="Sb" type="surfaceshader" />
  <surfacematerial name="Mb" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="Sb" />
  </surfacematerial>
</materialx>
'''


def test_a_look_file_whose_materials_come_from_an_include_is_clean(tmp_path):
    # MaterialX's standard_surface_look_brass_tiled.mtlx: looks, with the materials included
    from openpbr_tools.validate import validate_paths

    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "materials.mtlx").write_text(LIBRARY, encoding="utf-8")
    (tmp_path / "look.mtlx").write_text(LOOK.format(href="lib/materials.mtlx"), encoding="utf-8")
    found = validate_paths([str(tmp_path / "look.mtlx")]).diagnostics
    assert [d for d in found if str(d.severity) != "info"] == []
    # the included materials are checked with the look file, where they are (session 21: set J's jm_b17)
    assert {d.location.file for d in found} == {str(tmp_path / "lib" / "materials.mtlx")}


@pytest.mark.parametrize("href, reason", [
    ("../materials.mtlx", "leads outside the asset's folder"),
    ("missing.mtlx", "does not exist"),
    ("look.mtlx", "a cycle"),
])
def test_an_include_that_cannot_be_followed_is_reported_and_its_consequences_too(tmp_path, href, reason):
    from openpbr_tools.validate import validate_paths

    (tmp_path / "materials.mtlx").write_text(LIBRARY, encoding="utf-8")
    folder = tmp_path / "asset"
    folder.mkdir()
    (folder / "look.mtlx").write_text(LOOK.format(href=href), encoding="utf-8")
    found = validate_paths([str(folder / "look.mtlx")]).diagnostics
    code = "OPBR009" if "outside" in reason else "OPBR010"  # refused here vs broken for MaterialX too
    assert [d.code for d in found if d.code in ("OPBR009", "OPBR010")] == [code]
    assert reason in next(d.message for d in found if d.code == code)
    assert "OPBR802" in {d.code for d in found}  # the material it would have provided is missing


def test_an_include_outside_the_folder_is_never_opened(tmp_path, monkeypatch):
    import builtins

    from openpbr_tools.io import read_asset

    (tmp_path / "materials.mtlx").write_text(LIBRARY, encoding="utf-8")
    folder = tmp_path / "asset"
    folder.mkdir()
    (folder / "look.mtlx").write_text(LOOK.format(href="../materials.mtlx"), encoding="utf-8")
    opened = []
    real_open = builtins.open
    monkeypatch.setattr(builtins, "open", lambda file, *a, **k: opened.append(str(file)) or real_open(file, *a, **k))
    read_asset(str(folder / "look.mtlx"))
    assert not [f for f in opened if f.endswith("materials.mtlx")]


def test_a_colour_space_on_a_float_image_in_a_node_graph_is_warned(write_mtlx):
    path = write_mtlx('''<nodegraph name="NG">
  <image name="rough" type="float">
    <input name="file" type="filename" value="rough.png" colorspace="srgb_texture" />
  </image>
  <output name="out" type="float" nodename="rough" />
</nodegraph>
<open_pbr_surface name="S" type="surfaceshader">
  <input name="specular_roughness" type="float" nodegraph="NG" output="out" />
</open_pbr_surface>''', files=("rough.png",))
    from openpbr_tools.validate import validate_paths

    found = [d for d in validate_paths([str(path)]).diagnostics if d.code == "OPBR507"]
    assert len(found) == 1 and str(found[0].severity) == "warning"


def test_a_colour_space_on_a_materialx_float_image_in_usd_is_warned(tmp_path):
    from openpbr_tools.validate import validate_paths

    (tmp_path / "rough.png").write_bytes(b"")
    (tmp_path / "m.usda").write_text('''#usda 1.0
(
    metersPerUnit = 1
)
def Material "M"
{
    token outputs:mtlx:surface.connect = </M/S.outputs:out>
    def Shader "S"
    {
        uniform token info:id = "ND_open_pbr_surface_surfaceshader"
        float inputs:specular_roughness.connect = </M/R.outputs:out>
        token outputs:out
    }
    def Shader "R"
    {
        uniform token info:id = "ND_image_float"
        asset inputs:file = @rough.png@ (
            colorSpace = "srgb_texture"
        )
        float outputs:out
    }
}
''', encoding="utf-8")
    found = [d for d in validate_paths([str(tmp_path / "m.usda")]).diagnostics if d.code == "OPBR507"]
    assert len(found) == 1


def test_a_document_without_colour_space_warns_only_for_openpbr_colours(write_mtlx, codes_of):
    # MaterialX's TestSuite: Standard Surface documents without a colorspace. Only OpenPBR's specification
    # names another default (ACEScg) than MaterialX's lin_rec709.
    standard = write_mtlx('''<?xml version="1.0"?>
<materialx version="1.39">
  <standard_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" value="0.8, 0.2, 0.1" />
  </standard_surface>
</materialx>
''', name="standard.mtlx")
    openpbr = write_mtlx('''<?xml version="1.0"?>
<materialx version="1.39">
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" value="0.8, 0.2, 0.1" />
  </open_pbr_surface>
</materialx>
''', name="openpbr.mtlx")
    assert "OPBR501" not in codes_of(standard) and "OPBR501" in codes_of(openpbr)


def _gltf(tmp_path, document: dict) -> str:
    import json

    path = tmp_path / "m.gltf"
    path.write_text(json.dumps(dict({"asset": {"version": "2.0"}}, **document)), encoding="utf-8")
    return str(path)


def test_a_volume_beside_transmission_switched_off_is_not_a_volume_without_transmission(tmp_path, codes_of):
    # Khronos' IORTestGrid: its T0 materials keep KHR_materials_transmission at 0 beside a volume (as the
    # Khronos validator, which warns only where the transmission extension is missing)
    off = {"KHR_materials_transmission": {"transmissionFactor": 0.0}, "KHR_materials_volume": {"thicknessFactor": 0.1}}
    path = _gltf(tmp_path, {"extensionsUsed": sorted(off), "materials": [{"name": "M", "extensions": off}]})
    assert "OPBR1211" not in codes_of(path)
    missing = {"KHR_materials_volume": {"thicknessFactor": 0.1}}
    path = _gltf(tmp_path, {"extensionsUsed": sorted(missing), "materials": [{"name": "M", "extensions": missing}]})
    assert "OPBR1211" in codes_of(path)


def test_a_required_spec_gloss_extension_is_one_the_toolkit_interprets(tmp_path, codes_of):
    # Khronos' Avocado_SpecGloss requires KHR_materials_pbrSpecularGlossiness, which conversions read by the
    # spec-gloss -> metal-rough solve (translate/spec_gloss.py): not OPBR1202, still OPBR1204 (archived)
    name = "KHR_materials_pbrSpecularGlossiness"
    path = _gltf(tmp_path, {"extensionsUsed": [name], "extensionsRequired": [name],
                            "materials": [{"name": "M", "extensions": {name: {"glossinessFactor": 0.5}}}]})
    codes = codes_of(path)
    assert "OPBR1202" not in codes and "OPBR1204" in codes


def _stage(tmp_path, body: str) -> str:
    path = tmp_path / "m.usda"
    path.write_text("#usda 1.0\n(\n    metersPerUnit = 1\n    upAxis = \"Y\"\n    defaultPrim = \"M\"\n)\n" + body,
                    encoding="utf-8")
    return str(path)


def test_a_surface_connected_to_another_declared_output_of_the_preview_shader_is_read(tmp_path):
    # OpenUSD testUsdImagingGLInstancingWithMaterials/ni_ni_material_binding_resolution.usda connects
    # outputs:surface to the UsdPreviewSurface's outputs:out, and Storm renders it
    path = _stage(tmp_path, '''def Material "M"
{
    token outputs:surface.connect = </M/Surface.outputs:out>
    def Shader "Surface"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0.0, 1.0, 0.0)
        token outputs:out
    }
}
''')
    asset = read_asset(path)
    assert [m.inputs["diffuseColor"].constant for m in asset.materials] == [(0.0, 1.0, 0.0)]
    assert not [o for o in asset.observations if o.kind == "dangling_reference"]


def _textured_stage(tmp_path, texture_lines: str) -> str:
    """A UsdPreviewSurface whose diffuseColor reads a UsdUVTexture with ``texture_lines``."""
    return _stage(tmp_path, f'''def Material "M"
{{
    token outputs:surface.connect = </M/Surface.outputs:surface>
    def Shader "Surface"
    {{
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor.connect = </M/Texture.outputs:rgb>
        token outputs:surface
    }}
    def Shader "Texture"
    {{
        uniform token info:id = "UsdUVTexture"
        {texture_lines}
        float3 outputs:rgb
    }}
}}
''')


def test_a_time_sampled_texture_file_is_read_as_its_first_sample(tmp_path):
    # OpenUSD testUsdImagingGLPreviewSurface/testPreviewSurfaceAnimated.usda: an animated UsdUVTexture file
    from openpbr_tools.validate import validate_paths

    (tmp_path / "grid.png").write_bytes(b"")
    path = _textured_stage(tmp_path, "asset inputs:file.timeSamples = {\n            1: @grid.png@,\n"
                                     "            2: @grid_1.png@,\n        }")
    (material,) = read_asset(path).materials
    assert material.inputs["diffuseColor"].texture.file == "grid.png"
    assert "OPBR705" not in {d.code for d in validate_paths([path]).diagnostics}


def test_a_uv_texture_fallback_is_written_with_the_images_width(tmp_path):
    # OpenUSD testPreviewSurfaceTextureFallback.usda: UsdUVTexture's fallback is a float4 (0, 0, 1, 1) while the
    # image it becomes reads rgb: written as a color3 default "0, 0, 1, 1", MaterialX rejected the document
    from openpbr_tools.convert import convert_file
    from openpbr_tools.translate.common import Settings

    (tmp_path / "missing_on_purpose.png").write_bytes(b"")
    path = _textured_stage(tmp_path, "asset inputs:file = @missing_on_purpose.png@\n"
                                     "        float4 inputs:fallback = (0, 0, 1, 1)")
    for target in ("open_pbr_surface", "UsdPreviewSurface"):
        out = tmp_path / f"{target}.mtlx"
        convert_file(path, str(out), target, Settings())
        validated(out)
        assert 'value="0, 0, 1"' in out.read_text()


def test_an_input_the_model_does_not_define_is_left_out_with_a_note(tmp_path):
    # OpenUSD testPreviewSurfaceTextureWithToken.usda authors inputs:test on its UsdPreviewSurface: carried as
    # is into a .mtlx, MaterialX rejected the document ("Node interface error")
    from openpbr_tools.convert import convert_file
    from openpbr_tools.translate.common import Settings

    path = _stage(tmp_path, '''def Material "M"
{
    token outputs:surface.connect = </M/Surface.outputs:surface>
    def Shader "Surface"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0.5, 0.2, 0.1)
        string inputs:test = "test"
        token outputs:surface
    }
}
''')
    out = tmp_path / "o.mtlx"
    conversion = convert_file(path, str(out), "UsdPreviewSurface", Settings())
    validated(out)
    assert 'name="test"' not in out.read_text()
    assert [(d.code, d.location.input) for d in conversion.diagnostics] == [("OPBR1104", "test")]


def test_verify_pairs_materials_that_share_a_name_in_order(tmp_path):
    # Khronos' IridescenceSuzanne names its three materials "Material": each was compared with all three
    # written back, and a glTF -> glTF identity measured 27.8 mean CIEDE2000
    from openpbr_tools.convert import convert_file
    from openpbr_tools.translate.common import Settings
    from openpbr_tools.verification import measure

    colours = ([0.9, 0.1, 0.1, 1.0], [0.1, 0.2, 0.9, 1.0], [0.1, 0.8, 0.2, 1.0])
    path = _gltf(tmp_path, {"materials": [{"name": "Material", "pbrMetallicRoughness": {"baseColorFactor": c}}
                                          for c in colours]})
    conversion = convert_file(path, str(tmp_path / "out" / "o.gltf"), "gltf_pbr", Settings())
    assert [round(delta.mean, 3) for _, delta in measure(conversion)] == [0.0, 0.0, 0.0]
