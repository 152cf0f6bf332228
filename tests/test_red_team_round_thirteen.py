"""Session 26's red team: broken files it missed (set B, black-box) and false alarms and losses on published assets
(set P). Each case is small and written here; the expected verdicts come from the specifications and the anchors
(the Khronos glTF-Validator's codes, MaterialX's validate(), OpenUSD's hdMtlx), cited per test."""

from __future__ import annotations

import base64
import json
import struct

import numpy as np
import pytest
from PIL import Image

from openpbr_tools.convert import convert_file
from openpbr_tools.io import read_asset
from openpbr_tools.translate.common import Settings
from openpbr_tools.validate import validate_paths


def _codes(path) -> set[tuple[str, str]]:
    report = validate_paths([str(path)])
    return {(d.code, str(d.severity)) for d in report.diagnostics}


def _messages(path, code: str) -> list[str]:
    return [d.message for d in validate_paths([str(path)]).diagnostics if d.code == code]


# -- glTF: references, node hierarchy, POSITION bounds (the validator's UNRESOLVED_REFERENCE, NODE_LOOP,
#    SCENE_NON_ROOT_NODE, MESH_PRIMITIVE_POSITION_ACCESSOR_WITHOUT_BOUNDS: glTF 2.0 3.3, 3.5.3, 3.7.2.1) -------------

def _triangle() -> dict:
    positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    uvs = struct.pack("<6f", 0, 0, 1, 0, 0, 1)
    indices = struct.pack("<3H", 0, 1, 2) + b"\0\0"
    data = positions + uvs + indices
    return {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.1, 1.0]}}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36, "target": 34962},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 24, "target": 34962},
                        {"buffer": 0, "byteOffset": 60, "byteLength": 6, "target": 34963}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
    }


def _write(tmp_path, name: str, document: dict):
    path = tmp_path / name
    path.write_text(json.dumps(document), encoding="utf-8")
    return path


def test_the_clean_triangle_is_quiet(tmp_path):
    assert not {c for c in _codes(_write(tmp_path, "t.gltf", _triangle())) if c[1] == "error"}


@pytest.mark.parametrize("where, change, expected", [
    ("TEXCOORD_0 names accessor 9", lambda d: d["meshes"][0]["primitives"][0]["attributes"].update(TEXCOORD_0=9),
     "TEXCOORD_0 9 names no accessor"),
    ("indices name accessor 12", lambda d: d["meshes"][0]["primitives"][0].update(indices=12),
     "indices 12 names no accessor"),
    ("an accessor names bufferView 7", lambda d: d["accessors"][1].update(bufferView=7),
     "bufferView 7 names no bufferView"),
    ("a node names mesh 4", lambda d: d["nodes"][0].update(mesh=4), "mesh 4 names no mesh"),
    ("a bufferView names buffer 2", lambda d: d["bufferViews"][2].update(buffer=2), "buffer 2 names no buffer"),
    ("a scene names node 5", lambda d: d["scenes"][0].update(nodes=[0, 5]), "nodes 5 names no node"),
])
def test_a_reference_to_nothing_is_an_error(tmp_path, where, change, expected):
    document = _triangle()
    change(document)
    path = _write(tmp_path, "t.gltf", document)
    assert ("OPBR802", "error") in _codes(path), where
    assert any(expected in m for m in _messages(path, "OPBR802")), where


def test_a_node_loop_and_a_scene_listing_a_child_are_errors(tmp_path):
    document = _triangle()
    document["nodes"] = [{"children": [1]}, {"children": [0], "mesh": 0}]
    messages = _messages(_write(tmp_path, "t.gltf", document), "OPBR1210")
    assert any("0 -> 1 -> 0 form a loop" in m for m in messages)
    assert any("scene 0 lists node 0, which is the child of node 1" in m for m in messages)


def test_a_node_with_two_parents_is_an_error(tmp_path):
    document = _triangle()
    document["nodes"] = [{"children": [2]}, {"children": [2]}, {"mesh": 0}]
    document["scenes"] = [{"nodes": [0, 1]}]
    assert any("node 2 is a child of nodes 0 and 1" in m for m in _messages(_write(tmp_path, "t.gltf", document),
                                                                           "OPBR1210"))


def test_positions_without_bounds_are_an_error(tmp_path):
    document = _triangle()
    del document["accessors"][0]["min"], document["accessors"][0]["max"]
    assert any("accessor 0 holds the POSITION" in m and "no min and max" in m
               for m in _messages(_write(tmp_path, "t.gltf", document), "OPBR1210"))


# -- MaterialX ----------------------------------------------------------------------------------------------------

def test_a_placement_value_materialx_cannot_parse_is_reported_not_a_crash(tmp_path):
    """MSVC prints NaN as '-nan(ind)'; MaterialX's validate() says "Invalid value" (OPBR004); the reader crashed."""
    path = tmp_path / "m.mtlx"
    path.write_text("""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <place2d name="p2d" type="vector2">
    <input name="rotate" type="float" value="-nan(ind)" />
  </place2d>
  <image name="img" type="color3">
    <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />
    <input name="texcoord" type="vector2" nodename="p2d" />
  </image>
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodename="img" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
""")
    Image.new("RGB", (4, 4), (200, 100, 50)).save(tmp_path / "albedo.png")
    codes = _codes(path)
    assert ("OPBR004", "error") in codes and not any(code == "OPBR011" for code, _ in codes)
    convert_file(str(path), str(tmp_path / "out.gltf"), None, Settings())  # no exception


def test_a_material_fed_a_colour_has_no_shader(tmp_path):
    path = tmp_path / "m.mtlx"
    path.write_text("""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <nodegraph name="NG">
    <constant name="c" type="color3"><input name="value" type="color3" value="1, 0, 0" /></constant>
    <output name="out" type="color3" nodename="c" />
  </nodegraph>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodegraph="NG" output="out" />
  </surfacematerial>
</materialx>
""")
    codes = _codes(path)
    assert ("OPBR801", "error") in codes and not any(code == "OPBR805" for code, _ in codes)


def test_a_node_of_a_namespaced_definition_is_known(tmp_path):
    """OpenUSD's testUsdImagingGLMaterialXCustomNodes: the definition comes by XInclude from a document with
    namespace="TestNamespace"; the node names that namespace. MaterialX's validate() passes it."""
    (tmp_path / "defs").mkdir()
    (tmp_path / "defs" / "custom.mtlx").write_text("""<?xml version="1.0"?>
<materialx version="1.39" namespace="TestNamespace">
  <nodedef name="ND_test_color3" node="color3val">
    <output name="out" type="color3" />
  </nodedef>
  <nodegraph name="NG_test_color3" nodedef="ND_test_color3">
    <constant name="c" type="color3"><input name="value" type="color3" value="1, 0, 0" /></constant>
    <output name="out" type="color3" nodename="c" />
  </nodegraph>
</materialx>
""")
    path = tmp_path / "m.mtlx"
    path.write_text("""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <xi:include href="./defs/custom.mtlx" />
  <color3val name="myColor" type="color3" namespace="TestNamespace" />
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodename="myColor" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
""")
    assert not any(code == "OPBR104" for code, _ in _codes(path))


# -- USD ------------------------------------------------------------------------------------------------------------

_STAGE = """#usda 1.0
(
    defaultPrim = "Root"
    metersPerUnit = 1
    upAxis = "Y"
)
def Xform "Root"
{{
    def Scope "Looks"
    {{
        def Material "Mat"
        {{
{body}
        }}
    }}
}}
"""

_PREVIEW = """            token outputs:surface.connect = </Root/Looks/Mat/Preview.outputs:surface>
            def Shader "Preview"
            {{
                uniform token info:id = "UsdPreviewSurface"
                color3f inputs:diffuseColor.connect = </Root/Looks/Mat/Tex.outputs:rgb>
{more}
                token outputs:surface
            }}
            def Shader "Tex"
            {{
                uniform token info:id = "UsdUVTexture"
                asset inputs:file = @./albedo.png@
                token inputs:sourceColorSpace = "{space}"
                float2 inputs:st.connect = </Root/Looks/Mat/{st}>
                float3 outputs:rgb
                float outputs:a
            }}
{nodes}"""

_READER = """            def Shader "Reader"
            {{
                uniform token info:id = "UsdPrimvarReader_{type}"
                string inputs:varname = "st"
                {type}{suffix} outputs:result
            }}
"""


def _stage(tmp_path, more: str = "", space: str = "sRGB", st: str = "Reader.outputs:result", nodes: str | None = None,
           mode: str = "RGB"):
    path = tmp_path / "s.usda"
    if nodes is None:
        nodes = _READER.format(type="float2", suffix="")
    path.write_text(_STAGE.format(body=_PREVIEW.format(more=more, space=space, st=st, nodes=nodes)))
    Image.new(mode, (4, 4), (64, 128, 200) if mode == "RGB" else (64, 128, 200, 255)).save(tmp_path / "albedo.png")
    return path


def test_the_clean_preview_stage_is_quiet(tmp_path):
    assert not {c for c in _codes(_stage(tmp_path)) if c[1] in ("error", "warning")}


def test_texture_coordinates_from_a_missing_prim_are_dangling(tmp_path):
    """UsdUVTexture's st connected to a reader that does not exist: every point samples (0, 0) (UsdShade leaves the
    input at its fallback); OPBR802 is reported for the same defect one connection downstream."""
    path = _stage(tmp_path, nodes="")
    assert ("OPBR802", "error") in _codes(path)
    assert any("inputs:st" in m and "is dangling" in m for m in _messages(path, "OPBR802"))


def test_a_transform_fed_by_a_missing_reader_is_dangling(tmp_path):
    nodes = """            def Shader "Xf"
            {
                uniform token info:id = "UsdTransform2d"
                float2 inputs:in.connect = </Root/Looks/Mat/stReader.outputs:result>
                float2 inputs:scale = (2, 2)
                float2 outputs:result
            }
"""
    path = _stage(tmp_path, st="Xf.outputs:result", nodes=nodes)
    assert any("inputs:in" in m and "is dangling" in m for m in _messages(path, "OPBR802"))


def test_a_float3_reader_into_st_is_a_type_mismatch(tmp_path):
    """UsdUVTexture's st is float2 (UsdPreviewSurface specification); a UsdPrimvarReader_float3's result is float3."""
    path = _stage(tmp_path, nodes=_READER.format(type="float3", suffix=""))
    assert ("OPBR1005", "error") in _codes(path)


def test_a_mask_read_from_an_rgb_image_cuts_nothing(tmp_path):
    """UsdUVTexture gives alpha 1 where the image has none: with opacityThreshold 0.5 nothing is cut."""
    more = ("                float inputs:opacity.connect = </Root/Looks/Mat/Tex.outputs:a>\n"
            "                float inputs:opacityThreshold = 0.5")
    assert ("OPBR1007", "warning") in _codes(_stage(tmp_path, more=more))
    assert ("OPBR1007", "warning") not in _codes(_stage(tmp_path, more=more, mode="RGBA"))


def test_a_cycle_in_a_usd_network_is_an_error(tmp_path):
    """Two MaterialX multiply nodes feeding each other: MaterialX reports the same network in a .mtlx as "Cycle in
    upstream path"; no renderer evaluates it."""
    body = """            token outputs:mtlx:surface.connect = </Root/Looks/Mat/OpenPBR.outputs:out>
            def Shader "OpenPBR"
            {
                uniform token info:id = "ND_open_pbr_surface_surfaceshader"
                color3f inputs:base_color.connect = </Root/Looks/Mat/A.outputs:out>
                token outputs:out
            }
            def Shader "A"
            {
                uniform token info:id = "ND_multiply_color3FA"
                color3f inputs:in1.connect = </Root/Looks/Mat/B.outputs:out>
                float inputs:in2 = 0.5
                color3f outputs:out
            }
            def Shader "B"
            {
                uniform token info:id = "ND_multiply_color3FA"
                color3f inputs:in1.connect = </Root/Looks/Mat/A.outputs:out>
                float inputs:in2 = 2
                color3f outputs:out
            }"""
    path = tmp_path / "c.usda"
    path.write_text(_STAGE.format(body=body))
    assert any("cycle" in m for m in _messages(path, "OPBR802"))


def test_materialx_1_38_normalmap_id_is_read_as_its_1_39_name(tmp_path):
    """OpenUSD's mxNormalMap.usda authors info:id ND_normalmap, MaterialX 1.38's name; hdMtlx reads it as
    ND_normalmap_float (HdMtlxGetNodeDefName), as MaterialX's 1.39 upgrade renames it. No unknown id, and a
    conversion keeps the normal map."""
    body = """            token outputs:mtlx:surface.connect = </Root/Looks/Mat/OpenPBR.outputs:out>
            def Shader "OpenPBR"
            {
                uniform token info:id = "ND_open_pbr_surface_surfaceshader"
                float3 inputs:geometry_normal.connect = </Root/Looks/Mat/NormalMap.outputs:out>
                token outputs:out
            }
            def Shader "NormalMap"
            {
                uniform token info:id = "ND_normalmap"
                float3 inputs:in.connect = </Root/Looks/Mat/Image.outputs:out>
                float3 outputs:out
            }
            def Shader "Image"
            {
                uniform token info:id = "ND_image_vector3"
                asset inputs:file = @./normal.png@ (
                    colorSpace = "raw"
                )
                float3 outputs:out
            }"""
    path = tmp_path / "n.usda"
    path.write_text(_STAGE.format(body=body))
    Image.new("RGB", (4, 4), (128, 128, 255)).save(tmp_path / "normal.png")
    assert not any(code == "OPBR1003" for code, _ in _codes(path))
    material = read_asset(str(path)).materials[0]
    assert material.inputs["geometry_normal"].texture is not None
    conversion = convert_file(str(path), str(tmp_path / "out.gltf"), None, Settings())
    written = json.loads((tmp_path / "out.gltf").read_text())
    assert "normalTexture" in written["materials"][0]
    assert not any(d.code == "OPBR1104" and d.location.input == "geometry_normal" for d in conversion.diagnostics)


def test_a_raw_colour_texture_reaches_gltf_srgb_encoded(tmp_path):
    """A UsdUVTexture of sourceColorSpace raw feeds its texels to diffuseColor as they are (linear); glTF decodes a
    base colour texture from sRGB, so the written texels are the sRGB encoding of the source's (IEC 61966-2-1):
    64/255 linear is 137/255 encoded (OpenUSD's testPreviewSurfaceSourceColorSpace: 15.7 mean CIEDE2000 before)."""
    path = _stage(tmp_path, space="raw")
    convert_file(str(path), str(tmp_path / "out.gltf"), None, Settings())
    written = json.loads((tmp_path / "out.gltf").read_text())
    image = written["images"][written["textures"][
        written["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"]]["source"]]
    texel = Image.open(tmp_path / image["uri"]).convert("RGB").getpixel((0, 0))
    expected = [round(255 * (12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055))
                for v in (64 / 255, 128 / 255, 200 / 255)]
    assert list(texel) == pytest.approx(expected, abs=1)


def test_an_absolute_texture_path_inside_a_package_points_outside_it(tmp_path):
    """A .usda naming /Users/jane/... gets OPBR704 (its path leaves the asset); the same layer packaged in a .usdz
    got only OPBR701."""
    import zipfile

    text = _stage(tmp_path).read_text().replace("@./albedo.png@", "@/Users/jane/proj/textures/albedo.png@")
    package = tmp_path / "p.usdz"
    with zipfile.ZipFile(package, "w", zipfile.ZIP_STORED) as archive:  # (usdzip's layout: stored, data 64-aligned)
        name = "s.usda"
        start = 30 + len(name) + 4  # local header, name, one extra field's header
        info = zipfile.ZipInfo(name)
        info.extra = struct.pack("<HH", 0x1986, (-start) % 64) + bytes((-start) % 64)
        archive.writestr(info, text.encode())
    codes = _codes(package)
    assert ("OPBR704", "warning") in codes and ("OPBR701", "error") in codes


def test_json_named_glb_is_read_as_json(tmp_path):
    """A GLB named .gltf is read as a GLB; JSON named .glb was refused (OPBR002, exit 2), which hid its defects. The
    Khronos glTF-Validator reads both by their content."""
    document = _triangle()
    document["materials"][0]["alphaCutoff"] = -1
    path = tmp_path / "t.glb"
    path.write_text(json.dumps(document), encoding="utf-8")
    codes = _codes(path)
    assert ("OPBR301", "error") in codes and not any(code == "OPBR002" for code, _ in codes)


# -- set D (the second round) ------------------------------------------------------------------------------------

def test_a_rotation_in_radians_is_read_in_degrees(tmp_path):
    """place2d's rotate is in degrees; an input of unit="radian" is converted by MaterialX's unit system, so 1.5708
    radians is 90 degrees: no OPBR719 ("90 degrees written in radians?"), and a glTF output rotates by pi / 2."""
    Image.new("RGB", (4, 4), (200, 100, 50)).save(tmp_path / "albedo.png")
    path = tmp_path / "m.mtlx"
    path.write_text("""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <texcoord name="tc" type="vector2" />
  <place2d name="p2d" type="vector2">
    <input name="texcoord" type="vector2" nodename="tc" />
    <input name="rotate" type="float" value="1.5708" unittype="angle" unit="radian" />
  </place2d>
  <image name="img" type="color3">
    <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />
    <input name="texcoord" type="vector2" nodename="p2d" />
  </image>
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodename="img" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
""")
    assert not any(code == "OPBR719" for code, _ in _codes(path))
    assert read_asset(str(path)).materials[0].inputs["base_color"].texture.uv.rotate == pytest.approx(90.0, abs=1e-3)


_PREVIEW_TEXTURED = """            token outputs:surface.connect = </Root/Looks/Mat/Preview.outputs:surface>
            def Shader "Preview"
            {{
                uniform token info:id = "UsdPreviewSurface"
                color3f inputs:diffuseColor.connect = </Root/Looks/Mat/Tex.outputs:rgb>
                token outputs:surface
            }}
            def Shader "Tex"
            {{
                uniform token info:id = "UsdUVTexture"
{file}
                float2 inputs:st.connect = </Root/Looks/Mat/Reader.outputs:result>
                float3 outputs:rgb
            }}
""" + _READER.format(type="float2", suffix="").replace("{", "{{").replace("}", "}}")


def test_usd_core_errors_are_errors_here_too(tmp_path):
    """usd-core reports, as errors: a texture file that does not resolve at a time sample (the readers read the
    default's), and a UsdUVTexture fallback of another shape than its float4 declaration. They were OPBR1010
    warnings (exit 0)."""
    Image.new("RGB", (4, 4), (64, 128, 200)).save(tmp_path / "albedo.png")
    sampled = ('                asset inputs:file = @./albedo.png@\n'
               '                asset inputs:file.timeSamples = {\n                    1: @./albedo.png@,\n'
               '                    2: @./albedo_v002.png@,\n                }')
    path = tmp_path / "t.usda"
    path.write_text(_STAGE.format(body=_PREVIEW_TEXTURED.format(file=sampled)))
    assert ("OPBR701", "error") in _codes(path)
    fallback = '                asset inputs:file = @./albedo.png@\n                float3 inputs:fallback = (1, 0, 1)'
    path.write_text(_STAGE.format(body=_PREVIEW_TEXTURED.format(file=fallback)))
    assert ("OPBR201", "error") in _codes(path)


# -- set C (conversion fidelity on published assets) -------------------------------------------------------------

def test_a_textured_preview_emission_keeps_its_brightness_per_texel_in_gltf(tmp_path):
    """usd-wg's McUsd lava: a UsdPreviewSurface emissiveColor texture goes through OpenPBR as a colour and a luminance
    per texel; glTF's emissive_strength holds one value, so its mean was written and the texture held the colours
    normalised (7.16 mean CIEDE2000). An 8-bit texture fits glTF as it is: its texels come back, no strength."""
    body = _PREVIEW.format(more="", space="sRGB", st="Reader.outputs:result",
                           nodes=_READER.format(type="float2", suffix="")).replace(
        "color3f inputs:diffuseColor.connect = </Root/Looks/Mat/Tex.outputs:rgb>",
        "color3f inputs:emissiveColor.connect = </Root/Looks/Mat/Tex.outputs:rgb>\n"
        "                color3f inputs:diffuseColor = (0, 0, 0)")
    path = tmp_path / "e.usda"
    path.write_text(_STAGE.format(body=body))
    image = Image.new("RGB", (4, 4))
    image.putdata([(255, 40, 0), (40, 10, 0), (200, 120, 30), (5, 5, 5)] * 4)
    image.save(tmp_path / "albedo.png")
    convert_file(str(path), str(tmp_path / "out.gltf"), None, Settings())
    material = json.loads((tmp_path / "out.gltf").read_text())["materials"][0]
    assert material.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0) == 1.0
    written = json.loads((tmp_path / "out.gltf").read_text())
    uri = written["images"][written["textures"][material["emissiveTexture"]["index"]]["source"]]["uri"]
    texels = [tuple(t) for t in np.asarray(Image.open(tmp_path / uri).convert("RGB")).reshape(-1, 3).tolist()]
    for got, wanted in zip(texels, [tuple(t) for t in np.asarray(image).reshape(-1, 3).tolist()]):
        assert got == pytest.approx(wanted, abs=2)


def test_a_preview_ior_below_one_becomes_its_reciprocal(tmp_path):
    """The preview's Fresnel F0 = ((n - 1) / (n + 1))^2 is the same for n and 1 / n (0.5 and 2: 1/9); OpenPBR's IOR
    below 1 is a medium denser outside. OpenUSD's nativeClearcoat USD_Clearcoat_06 (ior 0.5, a clear coat) came out
    as an OpenPBR coat and base of IOR 0.5, 14.4 mean CIEDE2000 off."""
    more = "                float inputs:ior = 0.5\n                float inputs:clearcoat = 1"
    path = _stage(tmp_path, more=more)
    conversion = convert_file(str(path), str(tmp_path / "out.mtlx"), None, Settings())
    material = conversion.materials[0]
    coat = material.inputs["coat_ior"].value.value
    assert ((coat - 1) / (coat + 1)) ** 2 == pytest.approx(((0.5 - 1) / (0.5 + 1)) ** 2)
    assert coat > 1 and any("reciprocal" in d.message and d.location.input == "ior" for d in conversion.diagnostics)


def test_fuzz_over_a_metal_is_said_to_vanish_in_standard_surface(tmp_path):
    """Standard Surface's sheen lies over its dielectric base only (MaterialX's standard_surface.mtlx: sheen_layer is
    on the dielectric side of metalness_mix): glTF's SheenChair fabric, a metal with sheen, had only the velvet fit's
    note."""
    from openpbr_tools.model import Constant, Input, Location, Material
    from openpbr_tools import tables
    from openpbr_tools.rules import Context
    from openpbr_tools.translate.convert import convert

    table = tables.table("open_pbr_surface")
    where = Location("m.mtlx", 1, "S")
    values = {"base_metalness": 1.0, "fuzz_weight": 1.0, "fuzz_color": (1.0, 0.0, 0.75)}
    source = Material("S", "open_pbr_surface", where, {n: Input(n, table[n].type, Constant(v), where.with_input(n))
                                                       for n, v in values.items()}, version=table.version)
    notes = convert(source, "standard_surface", Settings(context=Context())).diagnostics
    assert any(d.location.input == "fuzz_weight" and str(d.severity) == "warning" and "none of it shows" in d.message
               for d in notes)


def test_verify_does_not_blame_a_conversion_for_textures_it_could_not_read(tmp_path):
    """A texture outside the asset's folder (MaterialX's examples name ../../../Images) is read by neither side
    without --allow-outside: each renders its fallback, and a correct conversion was reported as OPBR1109, 22-29
    mean CIEDE2000 off (the red team's C6). The figure is now an info that says it measures nothing."""
    from openpbr_tools.verification import verify

    (tmp_path / "images").mkdir()
    Image.new("RGB", (4, 4), (30, 200, 40)).save(tmp_path / "images" / "albedo.png")
    (tmp_path / "asset").mkdir()
    path = tmp_path / "asset" / "m.mtlx"
    path.write_text("""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="img" type="color3">
    <input name="file" type="filename" value="../images/albedo.png" colorspace="srgb_texture" />
  </image>
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodename="img" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
""")
    conversion = convert_file(str(path), str(tmp_path / "asset" / "out.mtlx"), "UsdPreviewSurface", Settings())
    notes = verify(conversion, 0.0)
    assert notes and all(d.code == "OPBR1108" and "not a measure of the conversion" in d.message for d in notes)
    allowed = convert_file(str(path), str(tmp_path / "asset" / "out2.mtlx"), "UsdPreviewSurface", Settings(),
                           allow_outside=(str(tmp_path / "images"),))
    assert not any("not a measure" in d.message for d in verify(allowed))
