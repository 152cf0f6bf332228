"""Writing USD: what the writer authors, that usd-core accepts it, and that reading it back gives
the same materials (values, textures, connections)."""

from __future__ import annotations

import os
import zipfile

import pytest
from PIL import Image

from openpbr_tools.io import read_asset
from openpbr_tools.io.usd.writer import write_usd
from openpbr_tools.resources import data_dir

SAMPLES = data_dir("samples")


def comparable(asset) -> dict:
    """Everything a material means, without where it was written (locations, node paths)."""
    found = {}
    for material in asset.materials:
        inputs = {}
        for name, entry in material.inputs.items():
            value = entry.value
            if entry.texture is not None:
                t = entry.texture
                uv = None if t.uv is None else (t.uv.scale, t.uv.rotate, t.uv.offset, t.uv.pivot)
                value = ("texture", os.path.basename(t.file), t.image_type, t.channels, t.colorspace, uv, t.texcoord,
                         t.scale, t.bias, t.wrap, t.fallback, t.normal_map)
            elif entry.constant is not None:
                value = ("constant", entry.constant)
            inputs[name] = value
        key = (material.model, material.name.rsplit("/", 1)[-1])
        found[key] = (material.version, inputs)
    return found


def usd_core(path) -> list[dict]:
    from pxr import Usd

    from openpbr_tools.io.usd.validators import usd_core_findings

    return usd_core_findings(Usd.Stage.Open(str(path)))


HEADER = '#usda 1.0\n(\n    defaultPrim = "Looks"\n    metersPerUnit = 1\n    upAxis = "Z"\n)\n\n'
STAGE = HEADER + '''def Scope "Looks"
{
    def Material "Wood"
    {
        float inputs:coat = 0.25
        token outputs:mtlx:surface.connect = </Looks/Wood/S.outputs:out>
        token outputs:surface.connect = </Looks/Wood/P.outputs:surface>

        def Shader "S"
        {
            uniform token info:id = "ND_open_pbr_surface_surfaceshader"
            color3f inputs:base_color.connect = </Looks/Wood/albedo.outputs:out>
            float inputs:specular_roughness.connect = </Looks/Wood/rough.outputs:out>
            float3 inputs:geometry_normal.connect = </Looks/Wood/nmap.outputs:out>
            float inputs:coat_weight.connect = </Looks/Wood.inputs:coat>
            float inputs:transmission_depth = 2
            color3f inputs:specular_color = (0.9, 0.8, 0.7) (colorSpace = "srgb_texture")
            bool inputs:geometry_thin_walled = 1
            token outputs:out
        }
        def Shader "albedo"
        {
            uniform token info:id = "ND_image_color3"
            asset inputs:file = @tex/albedo.png@ (colorSpace = "srgb_texture")
            float2 inputs:texcoord.connect = </Looks/Wood/place.outputs:out>
            string inputs:uaddressmode = "mirror"
            color3f outputs:out
        }
        def Shader "place"
        {
            uniform token info:id = "ND_place2d_vector2"
            float2 inputs:scale = (2, 2)
            float inputs:rotate = 30
            float2 inputs:pivot = (0.5, 0.5)
            float2 inputs:texcoord.connect = </Looks/Wood/uv.outputs:out>
            float2 outputs:out
        }
        def Shader "uv"
        {
            uniform token info:id = "ND_texcoord_vector2"
            int inputs:index = 1
            float2 outputs:out
        }
        def Shader "orm"
        {
            uniform token info:id = "ND_image_color3"
            asset inputs:file = @tex/orm.png@ (colorSpace = "none")
            color3f outputs:out
        }
        def Shader "rough"
        {
            uniform token info:id = "ND_extract_color3"
            color3f inputs:in.connect = </Looks/Wood/orm.outputs:out>
            int inputs:index = 1
            float outputs:out
        }
        def Shader "nimg"
        {
            uniform token info:id = "ND_image_vector3"
            asset inputs:file = @tex/normal.png@ (colorSpace = "none")
            float3 outputs:out
        }
        def Shader "nmap"
        {
            uniform token info:id = "ND_normalmap_float"
            float3 inputs:in.connect = </Looks/Wood/nimg.outputs:out>
            float inputs:scale = 0.8
            float3 outputs:out
        }
        def Shader "P"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor.connect = </Looks/Wood/diffuse.outputs:rgb>
            float inputs:roughness.connect = </Looks/Wood/ptex.outputs:g>
            normal3f inputs:normal.connect = </Looks/Wood/pnormal.outputs:rgb>
            token inputs:opacityMode = "presence"
            float inputs:opacity = 0.5
            token outputs:surface
        }
        def Shader "diffuse"
        {
            uniform token info:id = "UsdUVTexture"
            asset inputs:file = @tex/albedo.png@
            token inputs:sourceColorSpace = "sRGB"
            float2 inputs:st.connect = </Looks/Wood/xf.outputs:result>
            token inputs:wrapS = "repeat"
            token inputs:wrapT = "mirror"
            float4 inputs:fallback = (1, 0, 1, 1)
            float3 outputs:rgb
        }
        def Shader "xf"
        {
            uniform token info:id = "UsdTransform2d"
            float2 inputs:in.connect = </Looks/Wood/st.outputs:result>
            float inputs:rotation = 90
            float2 inputs:scale = (4, 4)
            float2 inputs:translation = (0.5, 0)
            float2 outputs:result
        }
        def Shader "st"
        {
            uniform token info:id = "UsdPrimvarReader_float2"
            string inputs:varname = "st"
            float2 outputs:result
        }
        def Shader "ptex"
        {
            uniform token info:id = "UsdUVTexture"
            asset inputs:file = @tex/orm.png@
            token inputs:sourceColorSpace = "raw"
            float2 inputs:st.connect = </Looks/Wood/st.outputs:result>
            float outputs:g
        }
        def Shader "pnormal"
        {
            uniform token info:id = "UsdUVTexture"
            asset inputs:file = @tex/normal.png@
            token inputs:sourceColorSpace = "raw"
            float4 inputs:scale = (2, 2, 2, 1)
            float4 inputs:bias = (-1, -1, -1, 0)
            float2 inputs:st.connect = </Looks/Wood/st.outputs:result>
            float3 outputs:rgb
        }
    }
}
'''


@pytest.fixture
def wood(tmp_path):
    (tmp_path / "src" / "tex").mkdir(parents=True)
    for name in ("albedo.png", "orm.png", "normal.png"):
        Image.new("RGB", (4, 4), (90, 60, 30)).save(tmp_path / "src" / "tex" / name)
    path = tmp_path / "src" / "wood.usda"
    path.write_text(STAGE)
    return path


@pytest.mark.parametrize("suffix", [".usda", ".usdc", ".usdz"])
def test_usd_read_write_read_keeps_values_textures_and_connections(wood, tmp_path, suffix):
    original = read_asset(wood)
    out = tmp_path / "out" / f"wood{suffix}"
    out.parent.mkdir()
    assert write_usd(original.materials, out, source=original) == []
    again = read_asset(out)
    assert comparable(again) == comparable(original)
    assert again.meters_per_unit == 1.0 and again.extra["up_axis"] == "Z"
    openpbr = next(m for m in again.materials if m.model == "open_pbr_surface")
    assert openpbr.inputs["coat_weight"].interface_name == "coat"
    assert openpbr.inputs["specular_color"].authored_colorspace == "srgb_texture"
    assert {m.material_location.path for m in again.materials} == {"/Looks/Wood"}  # both shaders on one Material
    assert {m.material_name for m in again.materials} == {"Wood"}
    assert [m.model for m in again.materials if not m.extra.get("fallback_of")] == ["open_pbr_surface"]


def test_written_stage_passes_usd_cores_validators(wood, tmp_path):
    original = read_asset(wood)
    out = tmp_path / "out.usda"
    write_usd(original.materials, out, source=original)
    assert usd_core(out) == []


def test_written_paths_are_relative_to_the_new_file(wood, tmp_path):
    original = read_asset(wood)
    out = tmp_path / "elsewhere" / "copy.usda"
    out.parent.mkdir()
    write_usd(original.materials, out, source=original)
    files = {t.file for m in read_asset(out).materials for _, t in m.textures()}
    assert files == {"../src/tex/albedo.png", "../src/tex/orm.png", "../src/tex/normal.png"}
    assert all((out.parent / f).exists() for f in files)


def test_usdz_carries_its_textures_with_the_root_layer_first(wood, tmp_path):
    original = read_asset(wood)
    out = tmp_path / "wood.usdz"
    write_usd(original.materials, out, source=original)
    with zipfile.ZipFile(out) as package:
        names = package.namelist()
        assert all(info.compress_type == zipfile.ZIP_STORED for info in package.infolist())
    assert names[0].endswith(".usdc") and set(names[1:]) == {"tex/albedo.png", "tex/orm.png", "tex/normal.png"}
    again = read_asset(out)
    assert all(t.packaged and t.file in again.extra["package_files"] for m in again.materials for _, t in m.textures())


@pytest.mark.parametrize("sample", ["textured_wood.mtlx", "car_paint.mtlx", "tinted_glass.mtlx", "brushed_aluminium.mtlx",
                                    "broken/legacy_openpbr_0_2.mtlx"])
def test_materialx_materials_survive_the_trip_through_usd(tmp_path, sample):
    original = read_asset(SAMPLES / sample)
    out = tmp_path / "look.usdc"
    write_usd(original.materials, out, source=original)
    again = read_asset(out)
    assert comparable(again) == comparable(original)
    assert [f["identifier"] for f in usd_core(out) if "UnresolvableDependency" not in f["identifier"]] == []


def test_openpbr_shader_id_version_and_colour_space_are_authored(tmp_path):
    from pxr import Usd, UsdShade

    original = read_asset(SAMPLES / "car_paint.mtlx")  # document colour space acescg
    out = tmp_path / "paint.usda"
    write_usd(original.materials, out, source=original)
    stage = Usd.Stage.Open(str(out))
    (material,) = [p for p in stage.Traverse() if p.IsA(UsdShade.Material)]
    source = UsdShade.Material(material).GetSurfaceOutput("mtlx").GetConnectedSources()[0][0]
    shader = UsdShade.Shader(source.source.GetPrim())
    assert shader.GetShaderId() == "ND_open_pbr_surface_surfaceshader"
    assert shader.GetPrim().GetCustomDataByKey("openpbr:version") == "1.1.1"
    assert material.GetAttribute("colorSpace:name").Get() == "lin_ap1_scene"
    assert read_asset(out).materials[0].colorspace == "acescg"


def test_legacy_openpbr_gets_its_versioned_id(tmp_path):
    from pxr import Usd, UsdShade

    original = read_asset(SAMPLES / "broken" / "legacy_openpbr_0_2.mtlx")
    out = tmp_path / "legacy.usda"
    write_usd(original.materials, out, source=original)
    stage = Usd.Stage.Open(str(out))
    ids = {str(UsdShade.Shader(p).GetShaderId()) for p in stage.Traverse() if p.IsA(UsdShade.Shader)}
    legacy = {m.version for m in original.materials} - {"1.1.1"}
    assert {f"ND_open_pbr_surface_surfaceshader_{v.replace('.', '')}" for v in legacy} <= ids


def test_lengths_with_a_unit_are_converted_to_stage_units(tmp_path, write_mtlx):
    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                      '  <input name="transmission_depth" type="float" value="2" unittype="distance" unit="centimeter" />\n'
                      "</open_pbr_surface>")
    original = read_asset(path)
    out = tmp_path / "m.usda"
    write_usd(original.materials, out, source=original, meters_per_unit=1.0)
    again = read_asset(out)
    assert again.meters_per_unit == 1.0
    assert again.materials[0].inputs["transmission_depth"].constant == pytest.approx(0.02)  # 2 cm in metres


def test_usd_lengths_follow_a_change_of_stage_unit(wood, tmp_path):
    original = read_asset(wood)  # metersPerUnit 1, transmission_depth 2 (metres)
    out = tmp_path / "cm.usda"
    write_usd(original.materials, out, source=original, meters_per_unit=0.01)
    openpbr = next(m for m in read_asset(out).materials if m.model == "open_pbr_surface")
    assert openpbr.inputs["transmission_depth"].constant == pytest.approx(200.0)


_PROCEDURAL = ('#usda 1.0\n\ndef Material "M"\n{\n    token outputs:mtlx:surface.connect = </M/S.outputs:surface>\n'
               '    def Shader "S"\n    {\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n'
               "        color3f inputs:base_color.connect = </M/noise.outputs:out>\n        token outputs:surface\n    }\n"
               '    def Shader "noise"\n    {\n        uniform token info:id = "{node}"\n        color3f outputs:out\n    }\n}\n')


def test_a_procedural_network_of_materialx_nodes_is_written_again(tmp_path):
    from pxr import Usd, UsdShade

    (tmp_path / "p.usda").write_text(_PROCEDURAL.replace("{node}", "ND_noise2d_color3"))
    original = read_asset(tmp_path / "p.usda")
    notes = write_usd(original.materials, tmp_path / "q.usda", source=original)
    assert notes == []
    stage = Usd.Stage.Open(str(tmp_path / "q.usda"))
    shader = next(UsdShade.Shader(p) for p in stage.Traverse()
                  if UsdShade.Shader(p).GetShaderId() == "ND_open_pbr_surface_surfaceshader")
    upstream, output, _ = shader.GetInput("base_color").GetConnectedSource()
    assert str(UsdShade.Shader(upstream.GetPrim()).GetShaderId()) == "ND_noise2d_color3" and output == "out"


def test_an_opaque_procedural_connection_is_reported_not_dropped_silently(tmp_path):
    # a shader no MaterialX definition describes: not captured, so not written, and said so
    (tmp_path / "p.usda").write_text(_PROCEDURAL.replace("{node}", "MyStudioNoise"))
    original = read_asset(tmp_path / "p.usda")
    notes = write_usd(original.materials, tmp_path / "q.usda", source=original)
    assert len(notes) == 1 and "MyStudioNoise" in notes[0].message


def test_packaged_textures_are_not_reported_missing(wood, tmp_path):
    from openpbr_tools.validate import validate_file

    original = read_asset(wood)
    out = tmp_path / "wood.usdz"
    write_usd(original.materials, out, source=original)
    assert "OPBR701" not in [d.code for d in validate_file(str(out)).diagnostics]


def test_an_input_authored_with_the_wrong_type_is_written_as_authored(tmp_path, write_mtlx):
    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader">\n'
                      '  <input name="base_color" type="float" value="0.5" />\n</open_pbr_surface>')
    original = read_asset(path)
    out = tmp_path / "w.usda"
    assert write_usd(original.materials, out, source=original) == []
    entry = read_asset(out).materials[0].inputs["base_color"]
    assert (entry.source_type, entry.constant) == ("float", 0.5)
