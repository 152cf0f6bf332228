"""The third red-team round (session 17: files written without reading this code), each finding proven
against the anchor that decides it: MaterialX's string resolver and GLSL generator, usd-core's asset
resolution inside a USDZ, the OpenUSD and glTF specifications."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from glsupport import shader_generator, validated
from redteam_support import codes as _codes, messages as _messages, mtlx as _mtlx, png as _png, report as _report






def _validates_and_generates(path) -> bool:
    """MaterialX's Document.validate() accepts the document (glsupport.validated) and its GLSL generator writes
    a pixel shader for its first renderable element."""
    import MaterialX.PyMaterialXGenShader as gs  # lazy: as glsupport.shader_generator

    _, generator, context = shader_generator()
    document = validated(path)  # held: an element of a released document is orphaned
    element = gs.findRenderableElements(document)[0]
    return bool(generator.generate("s", element, context).getSourceCode(gs.PIXEL_STAGE))


# -- a [token] in a file name: MaterialX's string resolver is the anchor ---------------------------------

_TOKEN = """
<nodegraph name="NG">
  <token name="resolution" type="string" value="{value}" />
  <image name="img" type="color3">
    <input name="file" type="filename" value="textures/wood_[resolution].png" colorspace="srgb_texture" />
  </image>
  <output name="out" type="color3" nodename="img" />
</nodegraph>
<open_pbr_surface name="S" type="surfaceshader">
  <input name="base_color" type="color3" nodegraph="NG" output="out" />
</open_pbr_surface>
<surfacematerial name="M" type="material">
  <input name="surfaceshader" type="surfaceshader" nodename="S" />
</surfacematerial>
"""


@pytest.mark.parametrize("value, exists", [("1k", True), ("4k", False)])
def test_a_token_in_a_file_name_is_substituted_as_materialx_resolves_it(tmp_path, value, exists):
    _png(tmp_path / "textures" / "wood_1k.png")
    path = _mtlx(tmp_path, _TOKEN.format(value=value))
    import MaterialX as mx

    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    resolved = document.getNodeGraph("NG").getNode("img").getInput("file").getResolvedValueString()
    assert resolved == f"textures/wood_{value}.png"  # the anchor
    assert ("OPBR701" in _codes(path)) is not exists
    if not exists:
        assert any("wood_4k.png" in m for m in _messages(path, "OPBR701"))


# -- a color4 image converted to color3: MaterialX's generator and validate() are the anchors -------------

_CONVERTED = """
<image name="img" type="color4">
  <input name="file" type="filename" value="leaf.png" colorspace="srgb_texture" />
</image>
<convert name="rgb" type="color3">
  <input name="in" type="color4" nodename="img" />
</convert>
<extract name="alpha" type="float">
  <input name="in" type="color4" nodename="img" />
  <input name="index" type="integer" value="3" />
</extract>
<open_pbr_surface name="S" type="surfaceshader">
  <input name="base_color" type="color3" nodename="rgb" />
  <input name="geometry_opacity" type="float" nodename="alpha" />
</open_pbr_surface>
<surfacematerial name="M" type="material">
  <input name="surfaceshader" type="surfaceshader" nodename="S" />
</surfacematerial>
"""


def test_a_color4_image_converted_to_color3_is_no_type_mismatch_and_converts_to_loadable_outputs(tmp_path):
    from openpbr_tools.convert import convert_file
    from openpbr_tools.translate.common import Settings

    _png(tmp_path / "leaf.png", "RGBA")
    path = _mtlx(tmp_path, _CONVERTED)
    assert _validates_and_generates(path)  # the anchor: a valid, renderable graph
    assert _codes(path) == {}
    for output in ("out.mtlx", "out.usda"):
        convert_file(str(path), str(tmp_path / output), "open_pbr_surface", Settings())
        assert _codes(tmp_path / output) == {}, output
    written = tmp_path / "out.mtlx"
    assert _validates_and_generates(written)
    assert "<convert" in written.read_text(encoding="utf-8")


# -- "./textures/a.png" inside a USDZ: usd-core resolves it to the package member ---------------------------

def test_a_dot_relative_texture_in_a_usdz_is_found_in_the_package(tmp_path):
    from pxr import Sdf, Usd, UsdUtils

    _png(tmp_path / "textures" / "oak.png")
    layer = tmp_path / "panel.usda"
    layer.write_text(textwrap.dedent("""\
        #usda 1.0
        (
            defaultPrim = "Asset"
        )
        def Xform "Asset"
        {
            def Material "M"
            {
                token outputs:mtlx:surface.connect = </Asset/M/S.outputs:out>
                def Shader "S"
                {
                    uniform token info:id = "ND_open_pbr_surface_surfaceshader"
                    color3f inputs:base_color.connect = </Asset/M/T.outputs:out>
                    token outputs:out
                }
                def Shader "T"
                {
                    uniform token info:id = "ND_image_color3"
                    asset inputs:file = @./textures/oak.png@ (colorSpace = "srgb_texture")
                    color3f outputs:out
                }
            }
        }
        """), encoding="utf-8")
    package = tmp_path / "panel.usdz"
    assert UsdUtils.CreateNewUsdzPackage(Sdf.AssetPath(str(layer)), str(package))
    stage = Usd.Stage.Open(str(package))
    resolved = stage.GetPrimAtPath("/Asset/M/T").GetAttribute("inputs:file").Get().resolvedPath
    assert resolved.endswith("[textures/oak.png]")  # the anchor: usd-core finds the member
    assert "OPBR701" not in _codes(package)


# -- USD shading structure: UsdShade itself is the anchor -------------------------------------------------

_STAGE = """\
#usda 1.0
(
    defaultPrim = "World"
    metersPerUnit = 1
)
def Xform "World"
{{
    def Mesh "Plane" (
        prepend apiSchemas = ["MaterialBindingAPI"]
    )
    {{
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 1, 2]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 0, 1)]
        rel material:binding = <{target}>
    }}
    def Material "M" {active}
    {{
        token outputs:mtlx:surface.connect = </World/M/S.outputs:out>
        def Shader "S"
        {{
            uniform token info:id = "ND_open_pbr_surface_surfaceshader"
{inputs}            token outputs:out
        }}
        def Shader "albedo"
        {{
            uniform token info:id = "ND_image_color3"
            asset inputs:file = @albedo.png@
            color3f outputs:out
        }}
    }}
    def Shader "Outside"
    {{
        uniform token info:id = "ND_image_color3"
        asset inputs:file = @albedo.png@
        color3f outputs:out
    }}
}}
"""


def _stage(tmp_path, target="/World/M", inputs="", active=""):
    _png(tmp_path / "albedo.png")
    path = tmp_path / "stage.usda"
    path.write_text(_STAGE.format(target=target, inputs=inputs, active=active), encoding="utf-8")
    return path


@pytest.mark.parametrize("target, active, bound", [
    ("/World/M", "", True), ("/World/M/S", "", False), ("/World/Missing", "", False),
    ("/World/M", "(\n        active = false\n    )", False),
])
def test_a_binding_is_flagged_exactly_when_usd_resolves_it_to_no_material(tmp_path, target, active, bound):
    from pxr import Usd, UsdShade

    path = _stage(tmp_path, target=target, active=active)
    stage = Usd.Stage.Open(str(path))  # held: a prim of a released stage is invalid
    material, _ = UsdShade.MaterialBindingAPI(stage.GetPrimAtPath("/World/Plane")).ComputeBoundMaterial()
    # the anchor: usd-core resolves it to no material, or to an inactive one, which Hydra never populates
    assert (bool(material) and material.GetPrim().IsActive()) is bound
    assert ("OPBR1017" in _codes(path)) is not bound


def test_an_input_authored_as_a_relationship_is_no_input_to_usdshade(tmp_path):
    from pxr import Usd, UsdShade

    path = _stage(tmp_path, inputs="            rel inputs:base_color = </World/M/albedo.outputs:out>\n")
    stage = Usd.Stage.Open(str(path))
    shader = UsdShade.Shader(stage.GetPrimAtPath("/World/M/S"))
    assert not shader.GetInput("base_color")  # the anchor: UsdShade sees no such input
    assert _codes(path).get("OPBR1018") == 1


@pytest.mark.parametrize("inputs, refused, reported", [
    ('            color3f inputs:base_color (\n                connectability = "interfaceOnly"\n            )\n'
     "            color3f inputs:base_color.connect = </World/M/albedo.outputs:out>\n", True, True),
    # across the Material's boundary: UsdShade refuses it too, but Hydra follows it and OpenUSD's own
    # preview-surface test stages do it (testPreviewSurfaceOpacityThreshold.usda), so it is no finding
    ("            color3f inputs:base_color.connect = </World/Outside.outputs:out>\n", True, False),
    ("            color3f inputs:base_color.connect = </World/M/albedo.outputs:out>\n", False, False),
])
def test_a_connection_usdshade_refuses_is_reported_where_renderers_do_not_follow_usd(tmp_path, inputs, refused, reported):
    from pxr import Usd, UsdShade

    path = _stage(tmp_path, inputs=inputs)
    stage = Usd.Stage.Open(str(path))
    port = UsdShade.Shader(stage.GetPrimAtPath("/World/M/S")).GetInput("base_color")
    source = port.GetConnectedSources()[0][0]
    origin = source.source.GetOutput(source.sourceName).GetAttr()
    assert UsdShade.ConnectableAPI.CanConnect(port, origin) is not refused  # the anchor
    assert ("OPBR1019" in _codes(path)) is reported


def test_a_published_stage_feeding_shaders_across_material_boundaries_stays_clean():
    published = (Path(__file__).parent / "data" / "published" / "usd" / "openusd" / "pxr" / "usdImaging" / "usdImagingGL"
                 / "testenv" / "testUsdImagingGLPreviewSurface" / "testPreviewSurfaceOpacityThreshold.usda")
    assert "OPBR1019" not in _codes(published)


def test_a_source_asset_implementation_without_its_asset_has_no_definition(tmp_path):
    from pxr import Usd, UsdShade

    path = _stage(tmp_path, inputs='            uniform token info:implementationSource = "sourceAsset"\n')
    stage = Usd.Stage.Open(str(path))
    shader = UsdShade.Shader(stage.GetPrimAtPath("/World/M/S"))
    assert not shader.GetShaderId() and not shader.GetSourceAsset("mtlx")  # the anchor: nothing names the node
    report = _report(path)
    found = [d for d in report.diagnostics if d.code == "OPBR1001"]
    assert found and found[0].location.input == "info:implementationSource"
    # the material is still reported as left out of conversions, naming the implementation, not an empty id
    notes = [d.message for d in report.diagnostics if d.code == "OPBR805"]
    assert notes and "uses a sourceAsset" in notes[0] and "uses a  shader" not in notes[0]


def test_a_tga_texture_in_a_usdz_is_an_entry_the_package_may_not_hold(tmp_path):
    import zipfile

    layer = _STAGE.format(target="/World/M", inputs="", active="").replace("albedo.png", "albedo.tga")
    package = tmp_path / "asset.usdz"
    with zipfile.ZipFile(package, "w", zipfile.ZIP_STORED) as archive:
        archive.writestr("asset.usda", layer)
        archive.writestr("albedo.tga", bytes(18) + bytes(4 * 3))
    assert len([m for m in _messages(package, "OPBR1012") if not m.startswith("usd-core")]) == 1
    # usd-core's own finding of the same entry is not repeated (its misaligned entries are, as OPBR1012 since
    # session 19: usd-core's package validators call them errors)
    assert not [m for m in _messages(package, "OPBR1010") if "UnsupportedFileExtension" in m]


@pytest.mark.parametrize("opacity, code_expected", [("0.35", True), ("0.6", True), ("1", True), (None, False)])
def test_a_preview_threshold_over_a_constant_opacity_cuts_all_or_nothing(tmp_path, opacity, code_expected):
    _png(tmp_path / "mask.png", "LA", colour=(128, 128))  # (a mask in alpha: an "L" image's a reads 1, which cuts
    # nothing, OPBR1007 since session 26)
    value = (f"            float inputs:opacity = {opacity}\n" if opacity is not None else
             "            float inputs:opacity.connect = </M/mask.outputs:a>\n")
    path = tmp_path / "preview.usda"
    path.write_text(textwrap.dedent(f"""\
        #usda 1.0
        (
            defaultPrim = "M"
            metersPerUnit = 1
        )
        def Material "M"
        {{
            token outputs:surface.connect = </M/P.outputs:surface>
            def Shader "P"
            {{
                uniform token info:id = "UsdPreviewSurface"
        {value}            float inputs:opacityThreshold = 0.5
                token outputs:surface
            }}
            def Shader "mask"
            {{
                uniform token info:id = "UsdUVTexture"
                asset inputs:file = @mask.png@
                float outputs:a
            }}
        }}
        """), encoding="utf-8")
    messages = _messages(path, "OPBR1007")
    assert bool(messages) is code_expected
    if opacity == "0.35":
        assert "cuts the whole surface away" in messages[0]
    elif opacity is not None:
        assert "cuts nothing" in messages[0]


@pytest.mark.parametrize("tiling, flagged", [("0, 0", True), ("4, 0", True), ("4, 4", False), ("1, 1", False)])
def test_a_zero_tiling_collapses_the_texture(tmp_path, tiling, flagged):
    _png(tmp_path / "albedo.png")
    path = _mtlx(tmp_path, f"""
        <tiledimage name="albedo" type="color3">
          <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />
          <input name="uvtiling" type="vector2" value="{tiling}" />
        </tiledimage>
        <open_pbr_surface name="S" type="surfaceshader">
          <input name="base_color" type="color3" nodename="albedo" />
        </open_pbr_surface>
        <surfacematerial name="M" type="material">
          <input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>
    """)
    assert ("OPBR711" in _codes(path)) is flagged


# -- MaterialX texture use: the same image read as a colour and as data; a texture GPUs cannot load ----------

_TWO_READS = """
<image name="albedo" type="color3">
  <input name="file" type="filename" value="oak_basecolor.png" colorspace="srgb_texture" />
</image>
<image name="data" type="{type}">
  <input name="file" type="filename" value="{file}" />
</image>
{extract}
<open_pbr_surface name="S" type="surfaceshader">
  <input name="base_color" type="color3" nodename="albedo" />
  <input name="{input}" type="float" nodename="{node}" />
</open_pbr_surface>
<surfacematerial name="M" type="material">
  <input name="surfaceshader" type="surfaceshader" nodename="S" />
</surfacematerial>
"""
_ALPHA = ('<extract name="a" type="float">\n  <input name="in" type="color4" nodename="data" />\n'
          '  <input name="index" type="integer" value="3" />\n</extract>')


@pytest.mark.parametrize("file, input_name, kind, flagged", [
    ("oak_basecolor.png", "specular_roughness", "float", True),   # the auto-assign script's wrong pick
    ("oak_basecolor.png", "geometry_opacity", "float", True),     # a cut-out from the red channel
    ("oak_roughness.png", "specular_roughness", "float", False),  # its own map
    ("oak_basecolor.png", "specular_roughness", "alpha", False),  # data packed in the colour image's alpha
])
def test_a_colour_image_read_as_data_through_a_colour_channel(tmp_path, file, input_name, kind, flagged):
    _png(tmp_path / "oak_basecolor.png", "RGBA")
    _png(tmp_path / "oak_roughness.png", "L", colour=128)
    alpha = kind == "alpha"
    path = _mtlx(tmp_path, _TWO_READS.format(type="color4" if alpha else "float", file=file, input=input_name,
                                             extract=_ALPHA if alpha else "", node="a" if alpha else "data"))
    assert ("OPBR712" in _codes(path)) is flagged


@pytest.mark.parametrize("width, flagged", [(16384, False), (16385, True)])
def test_a_texture_wider_than_gpus_load_is_flagged_from_its_header(tmp_path, width, flagged):
    import struct
    import zlib

    # a PNG header and an empty image: the size is read from IHDR, nothing is decoded
    ihdr = struct.pack(">IIBBBBB", width, 4, 8, 0, 0, 0, 0)
    png = (b"\x89PNG\r\n\x1a\n" + struct.pack(">I", 13) + b"IHDR" + ihdr + struct.pack(">I", zlib.crc32(b"IHDR" + ihdr))
           + struct.pack(">I", 0) + b"IEND" + struct.pack(">I", zlib.crc32(b"IEND")))
    (tmp_path / "scan.png").write_bytes(png)
    path = _mtlx(tmp_path, """
        <image name="rough" type="float"><input name="file" type="filename" value="scan.png" /></image>
        <open_pbr_surface name="S" type="surfaceshader">
          <input name="specular_roughness" type="float" nodename="rough" />
        </open_pbr_surface>
    """)
    assert ("OPBR713" in _codes(path)) is flagged


@pytest.mark.parametrize("colour, weight, code", [
    ("0, 0, 0", "1", "OPBR909"), ("0.9, 0.9, 0.9", "0.01", "OPBR909"),   # black, or dimmed to black by base_weight
    ("0.1, 0.1, 0.1", "1", "OPBR901"),                                    # dark: the heuristic's info
    ("0.56, 0.57, 0.58", "1", None),                                       # a real metal (physicallybased.info's iron)
])
def test_a_black_metal_is_a_warning_and_a_dark_one_an_info(tmp_path, colour, weight, code):
    path = _mtlx(tmp_path, f"""
        <open_pbr_surface name="S" type="surfaceshader">
          <input name="base_metalness" type="float" value="1" />
          <input name="base_weight" type="float" value="{weight}" />
          <input name="base_color" type="color3" value="{colour}" />
        </open_pbr_surface>
    """)
    found = set(_codes(path, ("error", "warning", "info"))) & {"OPBR901", "OPBR909"}
    assert found == ({code} if code else set())


@pytest.mark.parametrize("layer_unit, length, flagged", [("1", True, True), ("0.01", True, False), ("1", False, False)])
def test_a_composed_layer_in_another_unit_is_read_in_the_stages(tmp_path, layer_unit, length, flagged):
    """A material length in a layer of another unit is read in the stage's; a layer of geometry only is the
    layout OpenUSD's linear-units guidance and NVIDIA's UN.004 recommend (a scale on the referencing prim)."""
    from pxr import Usd, UsdGeom

    body = 'over "M"\n{\n    over "S"\n    {\n        float inputs:transmission_depth = 2.5\n    }\n}\n' if length else \
        'def Xform "Geo"\n{\n}\n'
    (tmp_path / "looks.usda").write_text(f'#usda 1.0\n(\n    metersPerUnit = {layer_unit}\n)\n{body}', encoding="utf-8")
    path = tmp_path / "stage.usda"
    path.write_text('#usda 1.0\n(\n    metersPerUnit = 0.01\n    subLayers = [@looks.usda@]\n)\n', encoding="utf-8")
    stage = Usd.Stage.Open(str(path))
    assert UsdGeom.GetStageMetersPerUnit(stage) == 0.01  # the anchor: the root layer's unit is the stage's
    assert ("OPBR1020" in _codes(path)) is flagged


# -- a foreign glTF metal's KHR_materials_specular: glTF renders none of it, so neither does the OpenPBR ---------

def test_a_foreign_gltf_metal_reads_its_specular_colour_as_glTF_renders_it(tmp_path):
    """physicallybased.info's tungsten as kwokcb/materialxMaterials exports it to glTF: the F82 tint in the
    specular colour of a full metal, which glTF's metal (Schlick's, F0 = base colour) ignores."""
    import json

    from openpbr_tools.convert import convert_file
    from openpbr_tools.translate.common import Settings
    from openpbr_tools.verification import measure

    tungsten = {"name": "tungsten", "pbrMetallicRoughness": {"baseColorFactor": [0.504, 0.498, 0.478, 1.0],
                                                              "metallicFactor": 1.0, "roughnessFactor": 0.0},
                "extensions": {"KHR_materials_specular": {"specularColorFactor": [0.403, 0.418, 0.423]}}}
    path = tmp_path / "tungsten.gltf"
    path.write_text(json.dumps({"asset": {"version": "2.0", "generator": "materialxMaterials"},
                                "extensionsUsed": ["KHR_materials_specular"], "materials": [tungsten]}))
    conversion = convert_file(str(path), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings())
    (source, delta), = measure(conversion)
    assert delta.mean < 0.05 and delta.max < 0.5  # read as a tint: mean 2.10, max 14.7
    assert any(d.code == "OPBR1102" and "no effect on a fully metallic" in d.message and d.location.input == "specularColorFactor"
               for d in conversion.diagnostics)


def test_an_image_too_large_to_decode_is_refused_before_it_is_decoded(tmp_path):
    """A 20000 x 20000 scan: decoded whole (Pillow refuses it as a decompression bomb, OpenImageIO did not) it
    exhausted the machine's memory and the conversion was killed; now it is an undecodable texture with a note."""
    import struct
    import zlib

    from openpbr_tools.convert import convert_file
    from openpbr_tools.io.images import ImageUndecodable, load_pixels
    from openpbr_tools.translate.common import Settings

    ihdr = struct.pack(">IIBBBBB", 20000, 20000, 8, 0, 0, 0, 0)
    png = (b"\x89PNG\r\n\x1a\n" + struct.pack(">I", 13) + b"IHDR" + ihdr + struct.pack(">I", zlib.crc32(b"IHDR" + ihdr))
           + struct.pack(">I", 0) + b"IEND" + struct.pack(">I", zlib.crc32(b"IEND")))
    (tmp_path / "scan.png").write_bytes(png)
    with pytest.raises(ImageUndecodable, match="20000 x 20000"):
        load_pixels(str(tmp_path / "scan.png"))
    path = _mtlx(tmp_path, """
        <image name="rough" type="float"><input name="file" type="filename" value="scan.png" /></image>
        <open_pbr_surface name="S" type="surfaceshader">
          <input name="specular_roughness" type="float" nodename="rough" />
        </open_pbr_surface>
        <surfacematerial name="M" type="material">
          <input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>
    """)
    conversion = convert_file(str(path), str(tmp_path / "out.gltf"), None, Settings())
    assert any("20000 x 20000" in d.message for d in conversion.diagnostics)


def test_a_prototype_shared_by_many_instances_is_read_once(tmp_path):
    """Materials inside instanceable prims are read through the first instance's proxies; the other instances'
    subtrees are pruned (a traversal of every proxy grew with instances x prototype size)."""
    instances = "".join(
        f'    def Xform "Chair_{i}" (\n        instanceable = true\n        references = </Prototypes/Chair>\n    )\n    {{\n    }}\n'
        for i in range(40))
    path = tmp_path / "room.usda"
    path.write_text(textwrap.dedent('''\
        #usda 1.0
        (
            defaultPrim = "World"
            metersPerUnit = 1
            upAxis = "Y"
        )
        def Xform "World"
        {
        ''') + instances + textwrap.dedent('''\
        }
        class "Prototypes"
        {
            def Xform "Chair"
            {
                def Material "M"
                {
                    token outputs:mtlx:surface.connect = </Prototypes/Chair/M/S.outputs:out>
                    def Shader "S"
                    {
                        uniform token info:id = "ND_open_pbr_surface_surfaceshader"
                        color3f inputs:base_color = (0.25, 0.12, 0.06)
                        token outputs:out
                    }
                }
            }
        }
        '''), encoding="utf-8")
    report = _report(path)
    assert sum(f.materials for f in report.files) == 1
    assert not [d for d in report.diagnostics if str(d.severity) in ("error", "warning")]


def test_a_black_standard_surface_metal_is_flagged_and_a_black_gltf_default_metal_is_not(tmp_path):
    import json

    ss = _mtlx(tmp_path, """
        <standard_surface name="S" type="surfaceshader">
          <input name="metalness" type="float" value="1" />
          <input name="base_color" type="color3" value="0, 0, 0" />
        </standard_surface>
    """, name="ss.mtlx")
    assert "OPBR909" in _codes(ss)
    # glTF's metallicFactor defaults to 1: Khronos' samples label spheres with black text exported so
    text = tmp_path / "text.gltf"
    text.write_text(json.dumps({"asset": {"version": "2.0"}, "materials": [
        {"name": "text", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}}]}))
    assert "OPBR909" not in _codes(text)
