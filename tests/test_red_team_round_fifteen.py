"""Session 27's red-team findings left open then (sets E and F), closed in session 28: a .mtlx output keeps the
source's node graphs whole (E#7), no false displacement loss (E#12), an 'over'-only layer said to be one (E#16),
UDIM and UVTILE sets packaged into a .usdz (F#18, F#19), an extracted image named by its bytes (F#20), a
texture-coordinate primvar of the wrong type (F#11) and sparse indices of no index type (F#15). Expected values
come from the formats' definitions (MaterialX's <UVTILE> and <UDIM> tokens, UsdPrimvarReader's fallback, the glTF
schema's sparse.indices.componentType list) and the anchors (MaterialX's validate() and GLSL generation,
usd-core's validators, the Khronos glTF-Validator)."""

from __future__ import annotations

import base64
import json
import struct
import zipfile
from pathlib import Path

import MaterialX as mx
import pytest
from PIL import Image

from openpbr_tools.convert import convert_file
from openpbr_tools.io import ReadError, read_asset
from openpbr_tools.model import Connection, Texture
from openpbr_tools.translate.common import Settings
from redteam_support import codes, khronos_warnings, messages, png

PUBLISHED = Path(__file__).resolve().parent / "data" / "published" / "materialx" / "resources"
EXAMPLES = PUBLISHED / "Materials" / "Examples" / "StandardSurface"


def _loads_and_generates(path: Path) -> mx.Document:
    """The document at ``path`` (without the library) once MaterialX has validated it and generated GLSL for every
    renderable element (test_procedural_graphs' check)."""
    from test_procedural_graphs import _loads_and_generates as check

    check(path)
    written = mx.createDocument()
    mx.readFromXmlFile(written, str(path))
    return written


# -- E#7: a .mtlx output keeps the source's node graphs -----------------------------------------------------------------

def _graph_interface(document, name: str) -> dict:
    graph = document.getNodeGraph(name)
    assert graph is not None, f"{name} was not kept"
    return {i.getName(): (i.getValueString(), i.getAttribute("uiname"), i.getAttribute("uifolder"))
            for i in graph.getInputs()}


@pytest.mark.parametrize("example, graph, inputs", [
    ("standard_surface_marble_solid.mtlx", "NG_marble1", {"base_color": "out", "subsurface_color": "out"}),
    ("standard_surface_brick_procedural.mtlx", "NG_BrickPattern",
     {"base_color": "base_color_output", "specular_roughness": "specular_roughness_output",
      "geometry_normal": "normal_output"}),
])
def test_a_node_graph_is_kept_with_its_interface(tmp_path, example, graph, inputs):
    """MaterialX's published marble and brick: Standard Surface -> OpenPBR, .mtlx to .mtlx. The graph's published
    interface (its inputs with uiname/uifolder: 'Color 1', 'UV Tiling'...) was inlined into copies of its nodes, the
    marble's output (read by base_color and subsurface_color) written twice and the brick's uvtiling hard-coded in
    three places. Now the graph is written once, as the source has it, and each input reads its output."""
    source = mx.createDocument()
    mx.readFromXmlFile(source, str(EXAMPLES / example))
    out = tmp_path / "out.mtlx"
    convert_file(str(EXAMPLES / example), str(out), "open_pbr_surface",
                 Settings(candidates=False),
                 allow_outside=(str(PUBLISHED / "Images"),))
    document = _loads_and_generates(out)
    assert _graph_interface(document, graph) == _graph_interface(source, graph)
    assert len(document.getNodeGraphs()) == 1
    assert sorted(n.getName() for n in document.getNodeGraph(graph).getNodes()) == \
        sorted(n.getName() for n in source.getNodeGraph(graph).getNodes())
    (shader,) = [n for n in document.getNodes() if n.getCategory() == "open_pbr_surface"]
    for name, output in inputs.items():
        port = shader.getInput(name)
        assert (port.getNodeGraphString(), port.getOutputString()) == (graph, output), name
    assert [n.getCategory() for n in document.getNodes()] == ["open_pbr_surface", "surfacematerial"]


def test_a_kept_graph_reads_as_the_source_did(tmp_path):
    """The kept graph reads back as the same procedural inputs (the evaluator's reading: the same images, the same
    constants), and its images still resolve from the output's folder (the document's fileprefix applied)."""
    example = EXAMPLES / "standard_surface_brick_procedural.mtlx"
    out = tmp_path / "sub" / "out.mtlx"
    out.parent.mkdir()
    convert_file(str(example), str(out), "open_pbr_surface",
                 Settings(candidates=False),
                 allow_outside=(str(PUBLISHED / "Images"),))
    (source,) = read_asset(str(example)).materials
    (written,) = read_asset(str(out)).materials
    assert isinstance(written.inputs["base_color"].value, Connection)
    texture = written.inputs["specular_roughness"].value
    assert isinstance(texture, Connection | Texture)
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(out))
    files = [port.getValueString() for node in document.getNodeGraph("NG_BrickPattern").getNodes()
             for port in node.getInputs() if port.getType() == "filename"]
    assert files and all((out.parent / f).resolve().is_file() for f in files), files
    assert source.inputs["base_color"].value.graph_xml.count("<tiledimage") == \
        written.inputs["base_color"].value.graph_xml.count("<tiledimage")


def test_a_mapping_that_changes_a_graph_writes_its_own_nodes(tmp_path):
    """To UsdPreviewSurface in a .mtlx, the brick's world-space normal takes a tangent-space form (normal_graphs) and
    its base colour an affine map (expressed): not the source's graph output, which would give world space and the
    unmapped colour; the roughness, mapped as it is, reads the graph kept whole."""
    out = tmp_path / "out.mtlx"
    convert_file(str(EXAMPLES / "standard_surface_brick_procedural.mtlx"), str(out), "UsdPreviewSurface",
                 Settings(candidates=False),
                 allow_outside=(str(PUBLISHED / "Images"),))
    document = _loads_and_generates(out)
    (shader,) = [n for n in document.getNodes() if n.getCategory() == "UsdPreviewSurface"]
    assert (shader.getInput("roughness").getNodeGraphString(), shader.getInput("roughness").getOutputString()) == \
        ("NG_BrickPattern", "specular_roughness_output")
    for name in ("diffuseColor", "normal"):
        assert shader.getInput(name).getNodeName() and not shader.getInput(name).getNodeGraphString(), name


def test_a_graph_reading_outside_itself_is_written_as_nodes(tmp_path):
    """A graph whose interface input is connected to a node outside it does not stand alone: the flat capture
    carries it (as before), and the output still loads and generates."""
    from redteam_support import mtlx

    path = mtlx(tmp_path, """
        <constant name="outside" type="color3"><input name="value" type="color3" value="0.2, 0.4, 0.6" /></constant>
        <nodegraph name="NG">
          <input name="tint" type="color3" nodename="outside" />
          <position name="p" type="vector3" />
          <noise3d name="n" type="color3"><input name="position" type="vector3" nodename="p" /></noise3d>
          <multiply name="m" type="color3">
            <input name="in1" type="color3" nodename="n" /><input name="in2" type="color3" interfacename="tint" />
          </multiply>
          <output name="out" type="color3" nodename="m" />
        </nodegraph>
        <standard_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodegraph="NG" output="out" /></standard_surface>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
    """)
    out = tmp_path / "out.mtlx"
    convert_file(str(path), str(out), "open_pbr_surface", Settings(candidates=False))
    document = _loads_and_generates(out)
    assert document.getNodeGraphs() == []
    assert any(n.getCategory() == "noise3d" for n in document.getNodes())


# -- E#12, E#16: no false loss, a clear reason ------------------------------------------------------------------------------

_PREVIEW_DISPLACED = """#usda 1.0
def Scope "Scene"
{
    def Material "M"
    {
        token outputs:surface.connect = </Scene/M/P.outputs:surface>
        token outputs:displacement.connect = </Scene/M/P.outputs:displacement>
        def Shader "P"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor = (0.2, 0.4, 0.6)
            DISPLACEMENT
            token outputs:surface
            token outputs:displacement
        }
    }
}
"""


@pytest.mark.parametrize("displacement, lost", [("", False), ("float inputs:displacement = 0.5", True)])
def test_a_preview_surfaces_own_displacement_output_is_lost_only_when_it_displaces(tmp_path, displacement, lost):
    """Pixar's testPreviewSurfacePrimvarFallback.usda connects the Material's outputs:displacement to the
    UsdPreviewSurface itself, whose displacement input is not authored (0: the specification's default, no
    displacement). Converting it said its displacement shader was not written; an authored displacement is."""
    path = tmp_path / "d.usda"
    path.write_text(_PREVIEW_DISPLACED.replace("DISPLACEMENT", displacement))
    conversion = convert_file(str(path), str(tmp_path / "o.mtlx"), "open_pbr_surface", Settings(candidates=False))
    said = [d for d in conversion.diagnostics if d.code == "OPBR1104" and "displacement" in d.message]
    assert bool(said) == lost, [d.message for d in said]


def test_materials_under_an_over_are_said_to_be_undefined(tmp_path):
    """usd-wg's StandardShaderBall example_materials.usda: Materials under an 'over' root prim are not defined until
    the layer is composed (UsdPrim.IsDefined is false; Usd.Stage.Traverse skips them), so there is nothing to
    convert; the message said there was no material of a convertible model."""
    path = tmp_path / "layer.usda"
    path.write_text('#usda 1.0\nover "Scene"\n{\n    def Material "M"\n    {\n'
                    '        token outputs:surface.connect = </Scene/M/P.outputs:surface>\n'
                    '        def Shader "P"\n        {\n            uniform token info:id = "UsdPreviewSurface"\n'
                    '            token outputs:surface\n        }\n    }\n}\n')
    with pytest.raises(ReadError) as raised:
        convert_file(str(path), str(tmp_path / "o.mtlx"), "open_pbr_surface", Settings(candidates=False))
    assert "under an 'over'" in raised.value.message and "/Scene/M" in raised.value.message


# -- F#18, F#19: tile sets into a .usdz ----------------------------------------------------------------------------------

def _tiled_material(tmp_path, token: str, tiles: list[str]) -> Path:
    from redteam_support import mtlx

    for name in tiles:
        png(tmp_path / "textures" / name)
    return mtlx(tmp_path, f"""
        <image name="img" type="color3"><input name="file" type="filename" value="textures/albedo.{token}.png" colorspace="srgb_texture" /></image>
        <open_pbr_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="img" /></open_pbr_surface>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
    """.replace("<UDIM>", "&lt;UDIM&gt;").replace("<UVTILE>", "&lt;UVTILE&gt;"))


@pytest.mark.parametrize("token, tiles, packaged", [
    ("<UDIM>", ["albedo.1001.png", "albedo.1002.png"], ["albedo.1001.png", "albedo.1002.png"]),
    # MaterialX's <UVTILE> is u<U>_v<V>, one-based (u1_v1 is UDIM 1001, u2_v1 1002, u1_v2 1011)
    ("<UVTILE>", ["albedo.u1_v1.png", "albedo.u2_v1.png", "albedo.u1_v2.png"],
     ["albedo.1001.png", "albedo.1002.png", "albedo.1011.png"]),
])
def test_a_tile_set_is_packaged_into_a_usdz(tmp_path, token, tiles, packaged):
    """A .usdz carries its textures: a <UDIM> set's tiles were left out (OPBR1104 and a package usd-core called
    unresolvable), a <UVTILE> set was called missing. Both are packaged, under their UDIM numbers (USD substitutes
    <UDIM> only), and the package validates: no finding of the toolkit's, no error of usd-core's validators."""
    from pxr import Usd, UsdValidation

    source = _tiled_material(tmp_path, token, tiles)
    out = tmp_path / "out" / "m.usdz"
    out.parent.mkdir()
    conversion = convert_file(str(source), str(out), "open_pbr_surface", Settings(candidates=False))
    assert not [d.message for d in conversion.diagnostics if d.code == "OPBR1104"]
    names = zipfile.ZipFile(out).namelist()
    assert sorted(n.rsplit("/", 1)[-1] for n in names if n.endswith(".png")) == packaged
    assert not codes(out)
    stage = Usd.Stage.Open(str(out))
    context = UsdValidation.ValidationContext(UsdValidation.ValidationRegistry().GetOrLoadAllValidators())
    errors = [e for e in context.Validate(stage) if e.GetType() == UsdValidation.ValidationErrorType.Error
              and "MissingShaderIdInRegistry" not in e.GetName()]
    assert not errors, [e.GetMessage() for e in errors]


def test_a_uvtile_set_in_a_layer_is_said_to_be_unreadable_by_usd(tmp_path):
    """A .usda only references its textures: a <UVTILE> path, which USD does not substitute, is reported."""
    source = _tiled_material(tmp_path, "<UVTILE>", ["albedo.u1_v1.png"])
    conversion = convert_file(str(source), str(tmp_path / "m.usda"), "open_pbr_surface", Settings(candidates=False))
    assert any(d.code == "OPBR1104" and "<UVTILE>" in d.message for d in conversion.diagnostics)


def test_a_tile_set_with_no_tile_is_said_to_be_missing(tmp_path):
    source = _tiled_material(tmp_path, "<UDIM>", [])
    conversion = convert_file(str(source), str(tmp_path / "m.usdz"), "open_pbr_surface", Settings(candidates=False))
    assert any(d.code == "OPBR1104" and "no tile" in d.message for d in conversion.diagnostics)


# -- F#20: an extracted image is named by its bytes -------------------------------------------------------------------------

def test_an_extracted_image_is_named_by_its_bytes_not_its_declared_type(tmp_path):
    """A data-URI PNG declared image/webp (OPBR1214): extracted beside a .usda, it was named image_0.webp."""
    from test_red_team_round_thirteen import _triangle

    png_path = png(tmp_path / "a.png")
    document = _triangle()
    document["images"] = [{"uri": "data:image/webp;base64," + base64.b64encode(png_path.read_bytes()).decode(),
                           "mimeType": "image/webp"}]
    document["textures"] = [{"source": 0}]
    document["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    path = tmp_path / "t.gltf"
    path.write_text(json.dumps(document))
    convert_file(str(path), str(tmp_path / "o.usda"), "open_pbr_surface", Settings(candidates=False))
    extracted = sorted(p.name for p in (tmp_path / "o_textures").iterdir())
    assert extracted == ["image_0.png"]
    assert Image.open(tmp_path / "o_textures" / "image_0.png").format == "PNG"


# -- F#11, F#15: what a reader cannot read -------------------------------------------------------------------------------

_ST_STAGE = """#usda 1.0
(
    metersPerUnit = 1
)
def Xform "Root"
{
    def Mesh "Quad" (
        prepend apiSchemas = ["MaterialBindingAPI"]
    )
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1)]
        PRIMVAR
        rel material:binding = </Root/Mat>
    }
    def Material "Mat"
    {
        token outputs:surface.connect = </Root/Mat/Preview.outputs:surface>
        def Shader "Preview"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor.connect = </Root/Mat/Tex.outputs:rgb>
            token outputs:surface
        }
        def Shader "Tex"
        {
            uniform token info:id = "UsdUVTexture"
            asset inputs:file = @./albedo.png@
            token inputs:sourceColorSpace = "sRGB"
            float2 inputs:st.connect = </Root/Mat/Reader.outputs:result>
            float3 outputs:rgb
        }
        def Shader "Reader"
        {
            uniform token info:id = "UsdPrimvarReader_float2"
            string inputs:varname = "st"
            float2 outputs:result
        }
    }
}
"""


@pytest.mark.parametrize("primvar, wrong", [
    ("color3f[] primvars:st = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)] (interpolation = \"vertex\")", True),
    ("float[] primvars:st = [0, 1, 1, 0] (interpolation = \"vertex\")", True),
    ("texCoord2f[] primvars:st = [(0, 0), (1, 0), (1, 1), (0, 1)] (interpolation = \"vertex\")", False),
    ("float2[] primvars:st = [(0, 0), (1, 0), (1, 1), (0, 1)] (interpolation = \"vertex\")", False),
])
def test_a_texture_coordinate_primvar_of_another_type_is_not_read(tmp_path, primvar, wrong):
    """UsdPrimvarReader_float2 returns its fallback when the primvar is not found or is not of its type (Pixar's
    OSL reader: getattribute into a float[2] fails on a colour), so a color3f st gives every texel (0, 0): OPBR1015,
    as for a missing st. A texCoord2f or float2 st is read."""
    image = Image.new("RGB", (8, 8), (255, 255, 255))
    image.paste((0, 0, 0), (0, 0, 4, 8))  # two halves: the coordinates matter
    image.save(tmp_path / "albedo.png")
    path = tmp_path / "s.usda"
    path.write_text(_ST_STAGE.replace("PRIMVAR", primvar))
    assert ("OPBR1015" in codes(path)) == wrong
    if wrong:
        assert any("not a two-component type" in m for m in messages(path, "OPBR1015"))


@pytest.mark.parametrize("component_type, wrong", [(5126, True), (5123, False)])
def test_sparse_indices_of_no_index_type_are_an_error(tmp_path, component_type, wrong):
    """glTF 2.0's accessor.sparse.indices.componentType: 5121, 5123 or 5125 (the Khronos glTF-Validator:
    VALUE_NOT_IN_LIST for a float's 5126); it was silent."""
    from test_red_team_round_thirteen import _triangle

    document = _triangle()
    extra = struct.pack("<2H", 0, 0) + struct.pack("<2f", 0.5, 0.5)
    data = base64.b64decode(document["buffers"][0]["uri"].split(",", 1)[1]) + extra
    start = len(data) - len(extra)
    document["buffers"][0] = {"byteLength": len(data),
                              "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}
    document["bufferViews"] += [{"buffer": 0, "byteOffset": start, "byteLength": 4},
                                {"buffer": 0, "byteOffset": start + 4, "byteLength": 8}]
    document["accessors"][1]["sparse"] = {"count": 1, "indices": {"bufferView": 3, "componentType": component_type},
                                          "values": {"bufferView": 4}}
    path = tmp_path / "s.gltf"
    path.write_text(json.dumps(document))
    assert ("OPBR1228" in codes(path)) == wrong
    khronos = khronos_warnings(path, tmp_path)
    if khronos is not None:
        assert ("VALUE_NOT_IN_LIST" in khronos) == wrong


# -- session 28's set H: what crashed, and what the anchors reject that was silent ---------------------------------------

def _gltf_file(tmp_path, document: dict, name: str = "t.gltf") -> Path:
    path = tmp_path / name
    path.write_text(json.dumps(document))
    return path


@pytest.mark.parametrize("where, value", [
    (("accessors", 1, "type"), ["VEC2"]),
    (("accessors", 1, "componentType"), "s"),
    (("meshes", 0, "primitives", 0, "attributes", "TEXCOORD_0"), "s"),
    (("bufferViews", 0, "buffer"), {"a": 1}),
    (("materials", 0, "pbrMetallicRoughness", "baseColorTexture", "extensions", "KHR_texture_transform"), "s"),
])
def test_a_property_of_the_wrong_json_type_anywhere_is_an_error(tmp_path, where, value):
    """Red team H's type sweep (945 files, each one JSON value of the wrong type): 320 files the Khronos
    glTF-Validator rejects were silent, and an accessor type or a variants mapping written as a list crashed the
    reader (exit 2, every other check lost). The glTF schema is now checked over the whole document (Khronos' own
    schema files, jsonschema): the file's other findings are still made (here metallicFactor 5)."""
    from test_red_team_round_thirteen import _triangle

    document = _triangle()
    png(tmp_path / "albedo.png")
    document["images"], document["textures"] = [{"uri": "albedo.png"}], [{"source": 0}]
    document["materials"][0]["pbrMetallicRoughness"].update(baseColorTexture={"index": 0}, metallicFactor=5)
    target = document
    for key in where[:-1]:
        target = target.setdefault(key, {}) if isinstance(key, str) else target[key]
    target[where[-1]] = value
    path = _gltf_file(tmp_path, document)
    found = codes(path)
    assert "OPBR011" not in found and "OPBR301" in found
    assert found.keys() & {"OPBR1253", "OPBR1210", "OPBR1228"}, found
    khronos = __import__("redteam_support").khronos_errors(path, tmp_path)
    if khronos is not None:
        assert khronos, "the anchor accepts it: not a defect"


def test_the_schema_is_said_once_where_a_rule_says_more(tmp_path):
    """A textureInfo index that is a string is OPBR1210 (with what it does: the texture is dropped); the schema's
    TYPE_MISMATCH at the same property is not said again."""
    from test_red_team_round_thirteen import _triangle

    document = _triangle()
    document["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": "0"}
    path = _gltf_file(tmp_path, document)
    assert codes(path).get("OPBR1210") == 1 and "OPBR1253" not in codes(path)


def test_the_published_gltf_samples_break_no_schema(tmp_path):
    """No false alarm: every glTF and GLB vendored from Khronos' sample assets passes the schema check."""
    published = sorted(p for p in (Path(__file__).resolve().parent / "data" / "published").rglob("*")
                       if p.suffix in (".gltf", ".glb"))
    assert len(published) > 20
    from openpbr_tools.validate import Options, validate_paths

    report = validate_paths([str(p) for p in published], options=Options(use_config=False))
    assert not [(d.location.file, d.message) for d in report.diagnostics if d.code == "OPBR1253"]


@pytest.mark.parametrize("stage, code", [
    ('int[] faceVertexCounts = </Nope>', None),  # (usd-core opens it; the topology is not judged)
    ('float4 inputs:scale = </Nope>', "OPBR1006"),
])
def test_a_path_where_a_usd_value_is_no_crash(tmp_path, stage, code):
    """A path authored where an array or a float4 is: the reader crashed (OPBR011, exit 2), hiding the file's
    base_metalness 3 (OPBR301)."""
    png(tmp_path / "albedo.png")
    normal = png(tmp_path / "normal.png", colour=(128, 128, 255))
    body = f'''#usda 1.0
def Xform "Root"
{{
    def Mesh "Quad" (prepend apiSchemas = ["MaterialBindingAPI"])
    {{
        {stage if "faceVertexCounts" in stage else "int[] faceVertexCounts = [4]"}
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1)]
        texCoord2f[] primvars:st = [(0, 0), (1, 0), (1, 1), (0, 1)] (interpolation = "vertex")
        rel material:binding = </Root/Mat>
    }}
    def Material "Mat"
    {{
        token outputs:surface.connect = </Root/Mat/Preview.outputs:surface>
        token outputs:mtlx:surface.connect = </Root/Mat/O.outputs:surface>
        def Shader "O"
        {{
            uniform token info:id = "ND_open_pbr_surface_surfaceshader"
            float inputs:base_metalness = 3
            token outputs:surface
        }}
        def Shader "Preview"
        {{
            uniform token info:id = "UsdPreviewSurface"
            normal3f inputs:normal.connect = </Root/Mat/N.outputs:rgb>
            token outputs:surface
        }}
        def Shader "N"
        {{
            uniform token info:id = "UsdUVTexture"
            asset inputs:file = @./{normal.name}@
            token inputs:sourceColorSpace = "raw"
            {stage if "scale" in stage else "float4 inputs:scale = (2, 2, 2, 2)"}
            float4 inputs:bias = (-1, -1, -1, -1)
            float2 inputs:st.connect = </Root/Mat/R.outputs:result>
            float3 outputs:rgb
        }}
        def Shader "R"
        {{
            uniform token info:id = "UsdPrimvarReader_float2"
            string inputs:varname = "st"
            float2 outputs:result
        }}
    }}
}}
'''
    path = tmp_path / "s.usda"
    path.write_text(body)
    found = codes(path)
    assert "OPBR011" not in found and "OPBR301" in found, found
    if code:
        assert code in found


def test_an_input_without_a_type_is_an_error(tmp_path):
    """<input name="coat_roughness" value="0.1"/>: MaterialX's validate() fails ("doesn't match declaration") and no
    code is generated for the shader; it was silent."""
    from redteam_support import mtlx

    path = mtlx(tmp_path, """
        <open_pbr_surface name="S" type="surfaceshader"><input name="coat_roughness" value="0.1" /></open_pbr_surface>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
    """)
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    document.importLibrary(library)
    assert not document.validate()[0]  # the anchor rejects it
    assert any("declares no type" in m for m in messages(path, "OPBR201"))


# -- session 28's set G: conversions of published assets -------------------------------------------------------------------

def test_a_texture_extension_the_toolkit_does_not_read_is_said(tmp_path):
    """glTF-MaterialX-Converter's checkerboard: baseColorTexture's KHR_texture_procedurals names a procedural graph;
    the texture's own image is a 1 x 1 magenta fallback. Converted, the fallback stood in with no word: now validate
    says the extension is not converted (OPBR1212) and convert that it is not carried (OPBR1104)."""
    from test_red_team_round_thirteen import _triangle

    document = _triangle()
    png(tmp_path / "fallback.png", size=(1, 1), colour=(255, 0, 255))
    document.update(images=[{"uri": "fallback.png"}], textures=[{"source": 0}],
                    extensionsUsed=["KHR_texture_procedurals"])
    document["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {
        "index": 0, "extensions": {"KHR_texture_procedurals": {"index": 0, "output": "out"}}}
    path = _gltf_file(tmp_path, document)
    from openpbr_tools.validate import Options, validate_paths

    said = [d for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics if d.code == "OPBR1212"]
    assert said and "KHR_texture_procedurals" in said[0].message
    conversion = convert_file(str(path), str(tmp_path / "o.mtlx"), "open_pbr_surface", Settings(candidates=False))
    assert any(d.code == "OPBR1104" and "KHR_texture_procedurals" in d.message for d in conversion.diagnostics)


@pytest.mark.parametrize("mode", ["CMYK", "I;16"])
def test_an_image_glTF_does_not_take_is_re_encoded(tmp_path, mode):
    """usd-wg's TextureFileFormatTests to glTF: a CMYK JPEG and a 16-bit PNG were copied as the base colour image,
    which glTF forbids (3.9.2: 8-bit sRGB; JFIF: one or three components; the toolkit's own OPBR1219 on the output,
    the Khronos glTF-Validator's IMAGE_DATA_INVALID). They are re-encoded as 8-bit PNG, and the output is clean."""
    import numpy as np

    from redteam_support import preview_stage, uv_texture

    if mode == "CMYK":
        name = "albedo.jpg"
        Image.new("CMYK", (4, 4), (0, 128, 255, 0)).save(tmp_path / name)
    else:  # a 16-bit PNG (greyscale: Pillow writes 16 bits per channel for mode I;16)
        name = "albedo.png"
        Image.fromarray(np.full((4, 4), 40000, dtype=np.uint16)).save(tmp_path / name)
        assert Image.open(tmp_path / name).mode.startswith("I")
    source = preview_stage(tmp_path, "color3f inputs:diffuseColor.connect = </M/T.outputs:rgb>",
                           extra=uv_texture("T", name))
    out = tmp_path / "out" / "o.gltf"
    out.parent.mkdir()
    convert_file(str(source), str(out), None, Settings(candidates=False))
    written = json.loads(out.read_text())["images"][0]["uri"]
    with Image.open(out.parent / written) as image:
        assert image.format == "PNG" and image.mode in ("RGB", "RGBA", "L", "LA")
    assert "OPBR1219" not in codes(out)


# -- session 28's set H: the command line's contract ----------------------------------------------------------------------

def _run_cli(*args, env=None, cwd=None):
    import os
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-m", "cli.main", *args], capture_output=True, cwd=cwd,
                          env={**os.environ, **(env or {})}, timeout=300)


def test_a_folder_that_cannot_be_listed_is_an_error(tmp_path, monkeypatch):
    """A subfolder the user cannot read was skipped in silence (exit 0, its broken file never checked): now OPBR001
    at the folder, and the run is not clean (root reads every folder, so the refusal is the operating system's,
    simulated here)."""
    import os

    from openpbr_tools import validate as validation
    from redteam_support import mtlx

    mtlx(tmp_path, "", name="a.mtlx")
    (tmp_path / "sub").mkdir()
    real = os.scandir

    def refusing(path="."):
        if os.path.basename(os.fspath(path)) == "sub":
            raise PermissionError(13, "Permission denied", os.fspath(path))
        return real(path)

    monkeypatch.setattr(os, "scandir", refusing)
    files, problems = validation.discover([str(tmp_path)])
    assert [p.code for p in problems] == ["OPBR001"] and "cannot list folder" in problems[0].message
    assert [os.path.basename(f) for f in files] == ["a.mtlx"]


def test_a_link_to_a_parent_folder_is_not_walked(tmp_path):
    """contract/loop/up -> ..: validating 'loop' walked its parent (19 files checked for a folder holding none)."""
    import os

    from openpbr_tools import validate as validation
    from redteam_support import mtlx

    mtlx(tmp_path, "", name="outside.mtlx")
    (tmp_path / "loop").mkdir()
    os.symlink("..", tmp_path / "loop" / "up")
    files, problems = validation.discover([str(tmp_path / "loop")])
    assert files == [] and [p.code for p in problems] == ["OPBR001"]  # (no supported file in the folder)


def test_a_file_named_twice_is_checked_once(tmp_path):
    import os

    from openpbr_tools import validate as validation
    from redteam_support import mtlx

    mtlx(tmp_path, "", name="a.mtlx")
    files, _ = validation.discover([str(tmp_path / "a.mtlx"), str(tmp_path), os.path.join(str(tmp_path), ".", "a.mtlx")])
    assert len(files) == 1


def test_a_json_report_of_a_file_name_that_is_not_utf8_is_utf8(tmp_path):
    """A file named with the bytes 0xFF 0xFE: the JSON report held them raw, which no JSON parser reads (RFC 8259:
    UTF-8). The name is written with \\udcXX escapes, as Python reads such a name."""
    import os

    from redteam_support import mtlx

    source = mtlx(tmp_path, "", name="a.mtlx")
    odd = os.path.join(os.fsencode(str(tmp_path)), b"odd_\xff\xfe.mtlx")
    os.rename(str(source), odd)
    completed = _run_cli("validate", "--no-config", "--format", "json", os.fsdecode(odd))
    report = json.loads(completed.stdout.decode("utf-8"))
    assert report["files"][0]["path"] == os.fsdecode(odd)


@pytest.mark.parametrize("args, env, said", [
    (("validate", "--no-config", "--scheduler", "localhost"), None, "not a scheduler address"),
    (("validate", "--no-config"), {"OPENPBR_MAX_FILE_MB": "-1"}, "positive number"),
    (("validate", "--no-config"), {"OPENPBR_MAX_FILE_MB": "abc"}, "positive number"),
])
def test_a_usage_error_is_exit_2_with_a_message(tmp_path, args, env, said):
    """--scheduler localhost (no port) printed Dask's traceback and exited 1 ("findings"); OPENPBR_MAX_FILE_MB=-1
    made every file "0 MiB above the -1 MiB limit", and "abc" was ignored."""
    from redteam_support import mtlx

    source = mtlx(tmp_path, "", name="a.mtlx")
    if "--scheduler" in args:
        pytest.importorskip("distributed")
    completed = _run_cli(*args, str(source), env=env)
    assert completed.returncode == 2, completed.stderr.decode()
    assert said in completed.stderr.decode() and b"Traceback" not in completed.stderr


# -- session 28's set G: no alarm where nothing is wrong -------------------------------------------------------------------

_SHADER_BALL = """#usda 1.0
def Material "M"
{
    token outputs:surface.connect = </M/P.outputs:surface>
    token outputs:mtlx:surface.connect = </M/O.outputs:surface>
    def Shader "O"
    {
        uniform token info:id = "ND_open_pbr_surface_surfaceshader"
        color3f inputs:base_color = (0.5, 0.5, 0.5)
        float inputs:specular_weight = WEIGHT
        float inputs:specular_roughness = 0.3
        token outputs:surface
    }
    def Shader "P"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0.5, 0.5, 0.5)
        float inputs:roughness = 1
        token outputs:surface
    }
}
"""


@pytest.mark.parametrize("weight, alarm", [("0", False), ("1", True)])
def test_a_roughness_that_renders_nothing_is_not_compared(tmp_path, weight, alarm):
    """usd-wg's StandardShaderBall: 20 OPBR1009 warnings ('roughness 1 is far from the OpenPBR specular_roughness
    0.3') on materials whose specular_weight is 0, where the roughness has nothing to roughen."""
    path = tmp_path / "ball.usda"
    path.write_text(_SHADER_BALL.replace("WEIGHT", weight))
    assert ("OPBR1009" in codes(path)) == alarm


def test_a_data_image_that_cannot_be_opened_is_not_judged_srgb(tmp_path):
    """The converter's own .usda read a 16-bit greyscale roughness map on auto (raw, by UsdUVTexture's rule) beside
    the folder; validated without --allow-outside, the suffix decided it was 8-bit RGB: a false OPBR504 error."""
    from redteam_support import preview_stage, uv_texture

    folder = tmp_path / "asset"
    folder.mkdir()
    Image.new("I;16", (4, 4)).save(tmp_path / "rough.png")
    path = preview_stage(folder, "float inputs:roughness.connect = </M/T.outputs:r>",
                         extra=uv_texture("T", "../rough.png", "r", "float"))
    assert "OPBR504" not in codes(path)


# -- session 28's set H: misses -------------------------------------------------------------------------------------------

def test_a_nan_time_sample_is_not_finite(tmp_path):
    """A static NaN is OPBR203 and an out-of-range time sample OPBR301 'at time 24'; a NaN time sample passed."""
    path = tmp_path / "s.usda"
    path.write_text('#usda 1.0\ndef Material "M"\n{\n    token outputs:mtlx:surface.connect = </M/O.outputs:surface>\n'
                    '    def Shader "O"\n    {\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n'
                    '        color3f inputs:base_color.timeSamples = {1: (0.8, 0.3, 0.2), 2: (nan, 0, 0)}\n'
                    '        token outputs:surface\n    }\n}\n')
    assert any("at time 2" in m for m in messages(path, "OPBR203"))


def test_an_empty_varname_reads_no_primvar(tmp_path):
    """UsdPrimvarReader_float2 with varname "": no primvar is read, the texture samples (0, 0) everywhere."""
    image = Image.new("RGB", (8, 8), (255, 255, 255))
    image.paste((0, 0, 0), (0, 0, 4, 8))
    image.save(tmp_path / "albedo.png")
    path = tmp_path / "s.usda"
    path.write_text(_ST_STAGE.replace("PRIMVAR", 'texCoord2f[] primvars:st = [(0, 0), (1, 0), (1, 1), (0, 1)] '
                                                 '(interpolation = "vertex")')
                    .replace('string inputs:varname = "st"', 'string inputs:varname = ""'))
    assert any("varname is empty" in m for m in messages(path, "OPBR1015"))


@pytest.mark.parametrize("coat, saturated", [(0.25, True), (1.0, False)])
def test_a_saturated_specular_weight_under_a_partial_coat(tmp_path, coat, saturated):
    """specular_weight 100: under a whole coat of IOR 1.6 the base's F0 relative to it is 0.001 (100 x 0.001 < 1),
    but a coat of 0.25 leaves three quarters of the base against air, F0 0.04: 4, clamped to a mirror (OPBR911)."""
    from redteam_support import mtlx

    path = mtlx(tmp_path, f"""
        <open_pbr_surface name="S" type="surfaceshader">
          <input name="specular_weight" type="float" value="100" />
          <input name="coat_weight" type="float" value="{coat}" />
          <input name="coat_ior" type="float" value="1.6" />
        </open_pbr_surface>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
    """)
    assert ("OPBR911" in codes(path)) == saturated


def test_a_buffer_view_past_its_buffer_is_an_error(tmp_path):
    """bufferView 160 + 4000 bytes of a 204-byte buffer: the Khronos glTF-Validator's BUFFER_VIEW_TOO_LONG; silent."""
    from test_red_team_round_thirteen import _triangle

    document = _triangle()
    document["bufferViews"].append({"buffer": 0, "byteOffset": 8, "byteLength": 4000})
    path = _gltf_file(tmp_path, document)
    assert messages(path, "OPBR1209") == ["bufferView 3 lies outside its buffer"]
    khronos = __import__("redteam_support").khronos_errors(path, tmp_path)
    if khronos is not None:
        assert "BUFFER_VIEW_TOO_LONG" in khronos


# -- session 28's set G and session 27's E#14: what a conversion writes ------------------------------------------------------

def test_an_extension_of_weight_0_is_not_written(tmp_path):
    """Every glTF output carried KHR_materials_clearcoat {clearcoatRoughnessFactor} with no clearcoatFactor (0): an
    extension that does nothing, which the toolkit's own OPBR1211 reports. Omitted, with a note."""
    from redteam_support import mtlx

    source = mtlx(tmp_path, """
        <open_pbr_surface name="S" type="surfaceshader"><input name="coat_roughness" type="float" value="0.3" /></open_pbr_surface>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
    """)
    out = tmp_path / "o.gltf"
    conversion = convert_file(str(source), str(out), None, Settings(candidates=False))
    material = json.loads(out.read_text())["materials"][0]
    assert "KHR_materials_clearcoat" not in (material.get("extensions") or {})
    assert any("KHR_materials_clearcoat omitted" in d.message for d in conversion.diagnostics)
    assert "OPBR1211" not in codes(out)


def test_a_formula_that_leaves_a_texture_as_it_is_keeps_its_reference(tmp_path):
    """Standard Surface with a metalness map (specular 1): base_color was 'baked per texel' into a PNG byte-identical
    to the source's, so a later repaint of the artist's texture no longer reached the material. The reference is
    kept where every texel comes out at its own 8-bit level."""
    import numpy as np

    from redteam_support import mtlx

    rng = np.random.default_rng(7)
    Image.fromarray(rng.integers(0, 256, (8, 8, 3), dtype=np.uint8), "RGB").save(tmp_path / "bc.png")
    Image.fromarray(np.where(rng.random((8, 8)) > 0.5, 255, 0).astype(np.uint8), "L").save(tmp_path / "metal.png")
    source = mtlx(tmp_path, """
        <image name="bc" type="color3"><input name="file" type="filename" value="bc.png" colorspace="srgb_texture" /></image>
        <image name="mt" type="float"><input name="file" type="filename" value="metal.png" /></image>
        <standard_surface name="S" type="surfaceshader">
          <input name="base_color" type="color3" nodename="bc" /><input name="metalness" type="float" nodename="mt" />
        </standard_surface>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
    """)
    out = tmp_path / "out" / "o.mtlx"
    out.parent.mkdir()
    convert_file(str(source), str(out), "open_pbr_surface", Settings(candidates=False))
    (material,) = read_asset(str(out)).materials
    texture = material.inputs["base_color"].value
    assert isinstance(texture, Texture) and Path(texture.file).name == "bc.png"


@pytest.mark.parametrize("geomprop, texcoord", [("st", None), ("UV0", None), ("uv2", "uv2")])
def test_an_image_on_a_geompropvalue_uv_set_is_a_texture(tmp_path, geomprop, texcoord):
    """The Digital Production Example Library's OpenPBR Shader Playground reads every image through
    <geompropvalue geomprop="st"> (UsdMtlx's, Houdini's and Omniverse's way to the UV primvar): the image was a
    procedural input, dropped from glTF ('which glTF cannot hold') and from the preview fallback. It is a texture on
    the UV set the primvar names: st (USD's default) and UV0 (MaterialX's) are set 0."""
    from redteam_support import mtlx

    png(tmp_path / "mask.png", mode="L", colour=128)
    source = mtlx(tmp_path, f"""
        <geompropvalue name="uv" type="vector2"><input name="geomprop" type="string" value="{geomprop}" /></geompropvalue>
        <image name="mask" type="float">
          <input name="file" type="filename" value="mask.png" /><input name="texcoord" type="vector2" nodename="uv" />
        </image>
        <open_pbr_surface name="S" type="surfaceshader"><input name="geometry_opacity" type="float" nodename="mask" /></open_pbr_surface>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
    """)
    (material,) = read_asset(str(source)).materials
    texture = material.inputs["geometry_opacity"].value
    assert isinstance(texture, Texture) and texture.texcoord == texcoord
    if texcoord is None:
        out = tmp_path / "o.gltf"
        convert_file(str(source), str(out), None, Settings(candidates=False))
        written = json.loads(out.read_text())["materials"][0]
        assert written.get("alphaMode") == "BLEND" and "baseColorTexture" in written["pbrMetallicRoughness"]


# -- session 27's E#15: a procedural colour in an output that holds no graph -------------------------------------------------

@pytest.mark.parametrize("suffix", [".gltf", ".usda"])
def test_a_procedural_colour_is_written_as_its_midpoint_where_no_graph_goes(tmp_path, suffix):
    """MaterialX's marble to glTF or to a USD output's UsdPreviewSurface fallback: its base colour, a mix of
    (0.8, 0.8, 0.8) and (0.1, 0.1, 0.3) by a noise, was left to the output's default (glTF's white, the preview's
    0.18 grey: 17.5 mean CIEDE2000 for the preview, by the red team). It is written as the mix at the noise's
    midpoint, 0.5: (0.45, 0.45, 0.55), with a note; --verify says its figure measures the stand-in, nothing more."""
    from openpbr_tools.verification import verify

    example = EXAMPLES / "standard_surface_marble_solid.mtlx"
    out = tmp_path / f"o{suffix}"
    conversion = convert_file(str(example), str(out), None, Settings(candidates=False),
                              allow_outside=(str(PUBLISHED / "Images"),))
    expected = (0.45, 0.45, 0.55)  # 0.5 x (0.8, 0.8, 0.8) + 0.5 x (0.1, 0.1, 0.3): MaterialX's mix
    if suffix == ".gltf":
        assert json.loads(out.read_text())["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][:3] == \
            pytest.approx(expected, abs=1e-6)
    else:
        preview = next(m for m in read_asset(str(out)).materials if m.model == "UsdPreviewSurface")
        assert preview.inputs["diffuseColor"].value.value == pytest.approx(expected, abs=1e-6)
    said = "base_color" if suffix == ".gltf" else "diffuseColor"
    assert any(d.code == "OPBR1103" and "midpoint" in d.message and said in d.message for d in conversion.diagnostics)
    figures = [d for d in verify(conversion, threshold=0.5) if d.code in ("OPBR1108", "OPBR1109")]
    assert all(d.code == "OPBR1108" for d in figures if "not a measure" in d.message)
    assert any("not a measure" in d.message for d in figures)
