"""Procedural graphs survive a translation whose mapping transforms them, and texture scale and bias
survive a .mtlx output.

* translate/expressed.py writes a mapping of a procedural input as MaterialX nodes after its graph:
  the fitted forms are checked against closed forms, and MaterialX itself (Document.validate(), GLSL
  shader generation, and, where GL is available, its GLSL renderer) checks the written nodes: a
  uniform procedural colour converted through the nodes renders as the same colour converted as a
  constant. Without the nodes (the graph dropped, as before) the same comparison fails.
* Kept graphs keep their images: MaterialX's examples put ``fileprefix="../../../Images/"`` on the
  document; a kept brick's images were looked up beside the output (25 mean ΔE in GLSL).
* A texture's scale and bias (a UsdUVTexture's) are written as multiply/add nodes and read back; a
  UsdPreviewSurface's normal map is written as its decode (MaterialX's UsdPreviewSurface re-encodes
  its ``normal`` and applies its own normalmap).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import MaterialX as mx
import numpy as np
import pytest

from openpbr_tools import colorspaces
from openpbr_tools.convert import convert_file
from openpbr_tools.evaluate import procedural
from openpbr_tools.io import read_asset
from openpbr_tools.model import Connection, Texture
from openpbr_tools.translate import expressed
from openpbr_tools.translate.common import Settings
from openpbr_tools.verification import measure

PUBLISHED = Path(__file__).resolve().parent / "data" / "published"
EXAMPLES = PUBLISHED / "materialx" / "resources"


# -- the fitted forms -------------------------------------------------------------------------------
def test_an_affine_colour_map_is_found_exactly():
    scale, offset = np.array([0.8, 0.5, 0.25]), np.array([0.1, 0.0, 0.02])
    found = expressed.fit(lambda x: x * scale + offset, "color3", "color3", 0.0, 1.0)
    assert found.kind == "affine" and found.error == 0.0
    np.testing.assert_allclose(found.matrix, np.diag(scale), atol=1e-12)
    np.testing.assert_allclose(found.offset, offset, atol=1e-12)


def test_a_per_channel_scale_seen_from_acescg_is_a_full_matrix():
    """A per-channel tint in linear Rec.709, for a colour authored in ACEScg: M^-1 D M, not diagonal."""
    tint = np.array([1.0, 0.6, 0.3])

    def g(x):
        return colorspaces.from_lin_rec709(colorspaces.to_lin_rec709(x, "acescg") * tint, "acescg")

    found = expressed.fit(g, "color3", "color3", 0.0, 1.0)
    assert found.kind == "affine"
    assert np.abs(found.matrix - np.diag(np.diag(found.matrix))).max() > 0.01  # off-diagonal terms
    x = expressed.samples(3, 0.0, 1.0)
    np.testing.assert_allclose(expressed.evaluate(found, x), g(x), atol=1e-9)


def test_a_square_is_a_cubic_and_a_product_of_channels_is_refused():
    square = expressed.fit(lambda x: x ** 2, "color3", "color3", 0.0, 1.0)
    assert square.kind == "polynomial" and square.error < 1e-9
    np.testing.assert_allclose(square.coefficients[:, 0], [0.0, 1.0, 0.0, 0.0], atol=1e-9)  # a cubic: 0 x^3 + x^2
    assert expressed.fit(lambda x: x * x[:, ::-1], "color3", "color3", 0.0, 1.0) is None  # r * b: not per channel
    assert expressed.fit(lambda x: np.sqrt(x), "float", "float", 0.0, 1.0) is None  # a quintic is still 0.07 off near 0


def test_a_float_to_colour_map_and_a_clamp():
    found = expressed.fit(lambda x: x * np.array([2.0, 1.0, 0.5]), "float", "color3", 0.0, 1.0, (0.0, 1.0))
    assert found.kind == "affine" and found.clamp == (0.0, 1.0)
    np.testing.assert_allclose(expressed.evaluate(found, np.array([[0.75]])), [[1.0, 0.75, 0.375]])


# -- the arithmetic the verifier evaluates ----------------------------------------------------------
def test_the_verifier_evaluates_a_graphs_closing_arithmetic_on_the_stand_in():
    graph = """<?xml version="1.0"?><materialx version="1.39">
      <noise3d name="n" type="color3" />
      <multiply name="m" type="color3"><input name="in1" type="color3" nodename="n" />
        <input name="in2" type="color3" value="0.5, 1, 2" /></multiply>
      <add name="a" type="color3"><input name="in1" type="color3" nodename="m" />
        <input name="in2" type="color3" value="0.1, 0.1, 0.1" /></add>
      <clamp name="c" type="color3"><input name="in" type="color3" nodename="a" /></clamp>
      <extract name="e" type="float"><input name="in" type="color3" nodename="a" />
        <input name="index" type="integer" value="2" /></extract>
    </materialx>"""
    s = procedural.STAND_IN
    np.testing.assert_allclose(procedural.value(graph, "c", "color3", None), np.minimum([s * 0.5 + 0.1, s + 0.1, s * 2 + 0.1], 1))
    np.testing.assert_allclose(procedural.value(graph, "e", "float", None), s * 2 + 0.1)
    np.testing.assert_allclose(procedural.value(graph, "n", "color3", None), [s, s, s])


# -- conversions ------------------------------------------------------------------------------------
UNIFORM = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="{space}">
  <mix name="colour" type="color3">
    <input name="fg" type="color3" value="{colour}" />
    <input name="bg" type="color3" value="0, 0, 0" />
    <input name="mix" type="float" value="1" />
  </mix>
  <{model} name="S" type="surfaceshader"{version}>
    <input name="{knob}" type="color3" {binding} />
{inputs}
  </{model}>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
</materialx>
"""

#: (model, target, colour space, other inputs): the mapping each case's nodes carry
CASES = {
    "standard surface base weight to the preview": ("standard_surface", "UsdPreviewSurface", "lin_rec709",
                                                    {"base": ("float", "0.6")}),
    "OpenPBR coat tint to the preview, acescg (a full matrix)": (
        "open_pbr_surface", "UsdPreviewSurface", "acescg",
        {"coat_weight": ("float", "1"), "coat_color": ("color3", "0.8, 0.7, 0.5"), "coat_darkening": ("float", "0")}),
    "OpenPBR metal to the preview (a cubic)": ("open_pbr_surface", "UsdPreviewSurface", "lin_rec709",
                                               {"base_metalness": ("float", "1"), "specular_weight": ("float", "0.7")}),
    "Standard Surface rough diffuse to OpenPBR, lin_displayp3 (a cubic in linear Rec.709)": (
        "standard_surface", "open_pbr_surface", "lin_displayp3", {"diffuse_roughness": ("float", "0.8")}),
}
COLOUR = "0.7, 0.35, 0.12"


def _document(folder: Path, name: str, model: str, space: str, inputs: dict, procedural_colour: bool) -> Path:
    knob = "base_color"
    binding = 'nodename="colour"' if procedural_colour else f'value="{COLOUR}"'
    text = UNIFORM.format(space=space, colour=COLOUR, model=model, knob=knob, binding=binding,
                          version=' version="1.1"' if model == "open_pbr_surface" else "",
                          inputs="\n".join(f'    <input name="{k}" type="{t}" value="{v}" />' for k, (t, v) in inputs.items()))
    path = folder / f"{name}.mtlx"
    path.write_text(text)
    return path


def _convert(tmp_path, case: str, procedural_colour: bool) -> tuple[Path, object]:
    model, target, space, inputs = CASES[case]
    tag = "graph" if procedural_colour else "constant"
    source = _document(tmp_path, f"source_{tag}", model, space, inputs, procedural_colour)
    out = tmp_path / f"out_{tag}.mtlx"
    # the mapping alone on both (the candidate search and appearance fit weigh constant materials only)
    conversion = convert_file(str(source), str(out), target, Settings(candidates=False))
    return out, conversion


def _loads_and_generates(path: Path) -> None:
    import MaterialX.PyMaterialXGenGlsl as gg
    import MaterialX.PyMaterialXGenShader as gs

    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    document.importLibrary(library)
    valid, message = document.validate()
    assert valid, message
    generator = gg.GlslShaderGenerator.create()
    context = gs.GenContext(generator)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    for element in gs.findRenderableElements(document):
        assert generator.generate("check", element, context).getSourceCode(gs.PIXEL_STAGE)


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_graph_is_kept_with_its_mapping_as_nodes(tmp_path, case):
    out, conversion = _convert(tmp_path, case, procedural_colour=True)
    result = read_asset(str(out)).materials[0]
    connected = [e for e in result.inputs.values() if isinstance(e.value, Connection)]
    assert connected, "the procedural colour was dropped"
    assert "mix" in connected[0].value.graph_xml  # the source's own graph, kept
    codes = {d.code for d in conversion.diagnostics}
    assert "OPBR1102" in codes or "OPBR1103" in codes
    assert not any(d.code == "OPBR1104" and "procedural" in d.message for d in conversion.diagnostics)
    _loads_and_generates(out)


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_verifier_judges_the_kept_graph_at_one_stand_in(tmp_path, case):
    """The source's procedural and the target's nodes after it are evaluated at the same stand-in, so a
    faithful conversion measures as its constant twin does, not as two unrelated defaults."""
    _, conversion = _convert(tmp_path, case, procedural_colour=True)
    [(_, delta)] = measure(conversion)
    assert delta.mean < 2.3


def test_kept_graphs_read_their_images_through_the_documents_fileprefix(tmp_path):
    shutil.copytree(EXAMPLES, tmp_path / "resources")
    source = tmp_path / "resources" / "Materials" / "Examples" / "StandardSurface" / "standard_surface_brick_procedural.mtlx"
    out = tmp_path / "elsewhere" / "brick.mtlx"
    out.parent.mkdir()
    convert_file(str(source), str(out), "open_pbr_surface", Settings(), allow_outside=(str(tmp_path),))
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(out))
    files = [port.getResolvedValueString() for scope in [document] + document.getNodeGraphs()
             for node in scope.getNodes() for port in node.getInputs() if port.getType() == "filename"]
    assert len(files) >= 4
    for file in files:
        assert (out.parent / file).resolve().is_file(), file


# -- scale, bias and the preview's normal ------------------------------------------------------------
NORMAL_MAPPED = PUBLISHED / "usd" / "openusd" / "pxr" / "usdImaging" / "usdImagingGL" / "testenv" / \
    "testUsdImagingGLPreviewSurface" / "testPreviewSurfaceNormalMap.usda"
SCALED = PUBLISHED / "usd" / "usd-wg" / "test_assets" / "AlphaBlendSortTest" / "AlphaBlendSortTest.usda"


def test_a_usduvtexture_scale_survives_a_mtlx_output(tmp_path):
    """The USD working group's alpha-sort asset scales its textures (0, 0, 0, 0.51): written to .mtlx
    without the scale it measured 9.7 mean ΔE against itself."""
    out = tmp_path / "scaled.mtlx"
    conversion = convert_file(str(SCALED), str(out), "UsdPreviewSurface", Settings())
    assert max(delta.mean for _, delta in measure(conversion)) < 0.05
    textures = [e.value for m in read_asset(str(out)).materials for e in m.inputs.values() if isinstance(e.value, Texture)]
    assert any(t.scale is not None for t in textures)


def test_the_previews_normal_map_is_its_decode_in_mtlx(tmp_path):
    out = tmp_path / "normal.mtlx"
    conversion = convert_file(str(NORMAL_MAPPED), str(out), "UsdPreviewSurface", Settings())
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(out))
    categories = {node.getCategory() for node in document.getNodes()}
    assert "normalmap" not in categories and {"multiply", "add"} <= categories
    normal = read_asset(str(out)).materials[0].inputs["normal"].value
    assert normal.decoded_by_scale_bias and normal.scale == (2.0, 2.0, 2.0) and normal.bias == (-1.0, -1.0, -1.0)
    assert max(delta.mean for _, delta in measure(conversion)) < 0.05
    _loads_and_generates(out)


def test_a_mapping_no_node_form_holds_is_reported_not_dropped_silently(tmp_path):
    """A Standard Surface metal with ``specular`` 0 divides its colour by its own largest channel going
    to OpenPBR (openpbr_specular_weight): neither affine nor a cubic per channel, so the graph is not
    written, and the report says so at the input."""
    source = _document(tmp_path, "metal", "standard_surface", "lin_rec709",
                       {"metalness": ("float", "1"), "specular": ("float", "0")}, True)
    conversion = convert_file(str(source), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings())
    dropped = [d for d in conversion.diagnostics if d.code == "OPBR1104" and "procedural" in d.message]
    assert dropped and all(d.location.input == "base_color" for d in dropped)


@pytest.mark.parametrize("case", sorted(CASES))
def test_materialx_renders_the_kept_graph_as_the_constant_conversion(tmp_path, case):
    """MaterialX's GLSL renderer evaluates the written nodes: the uniform procedural colour converted
    through them renders as the same colour converted as a constant (an affine map exactly; a
    polynomial within its error), while the graph wired straight to the target input, the mapping
    left out, renders visibly apart."""
    from glsupport import comparison_mask, materialx_renderer
    from openpbr_tools.evaluate.difference import delta_e_2000
    from openpbr_tools.evaluate.preview import Rig

    rig = Rig(size=48)
    renderer = materialx_renderer(rig)
    graph_out, conversion = _convert(tmp_path, case, procedural_colour=True)
    constant_out, _ = _convert(tmp_path, case, procedural_colour=False)
    mask = comparison_mask(rig)

    def delta(a, b):
        return float(delta_e_2000(a[mask], b[mask], rig.white()).mean())

    reference = renderer.render_document(constant_out)
    kept = renderer.render_document(graph_out)
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(graph_out))
    shader = [n for n in document.getNodes() if n.getType() == "surfaceshader"][0]
    port = [p for p in shader.getInputs() if p.getNodeName()][0]
    mixes = [n for n in document.getNodes() if n.getCategory() == "mix"]
    port.setNodeName(mixes[0].getName())  # the graph straight in, without the mapping's nodes
    bare = tmp_path / "bare.mtlx"
    mx.writeToXmlFile(document, str(bare))
    polynomial = any("polynomial" in d.message for d in conversion.diagnostics)
    assert delta(kept, reference) < (0.5 if polynomial else 0.05)
    assert delta(renderer.render_document(bare), reference) > 1.0


UDIM_DOCUMENT = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="albedo" type="color3">
    <input name="file" type="filename" value="albedo.&lt;UDIM&gt;.png" colorspace="srgb_texture" />
  </image>
  <standard_surface name="S" type="surfaceshader">
    <input name="base" type="float" value="0.6" />
    <input name="base_color" type="color3" nodename="albedo" />
  </standard_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
</materialx>
"""


def test_a_udim_set_a_mapping_scales_keeps_its_tiles_with_the_scale(tmp_path):
    """A UDIM set cannot be baked; Standard Surface's base weight 0.6 on it, going to UsdPreviewSurface's
    diffuseColor (base * base_color), is an affine map per channel, so the set is kept with scale 0.6 (it
    was reported lost, the diffuse colour left at its default), and renders as the source does."""
    from PIL import Image

    for tile, colour in ((1001, (200, 120, 40)), (1002, (30, 90, 220))):
        Image.new("RGB", (16, 16), colour).save(tmp_path / f"albedo.{tile}.png")
    source = tmp_path / "udim.mtlx"
    source.write_text(UDIM_DOCUMENT)
    out = tmp_path / "out" / "udim.mtlx"
    out.parent.mkdir()
    conversion = convert_file(str(source), str(out), "UsdPreviewSurface", Settings(candidates=False))
    texture = read_asset(str(out)).materials[0].inputs["diffuseColor"].value
    assert isinstance(texture, Texture) and texture.is_udim
    np.testing.assert_allclose(texture.scale, (0.6, 0.6, 0.6))
    assert not [d for d in conversion.diagnostics if d.code == "OPBR1104"]
    [(_, delta)] = measure(conversion)
    assert delta.mean < 2.3


def test_a_target_the_material_does_not_need_is_not_written_from_a_texture(tmp_path):
    """MaterialX's brass puts its colour texture on coat_color; without emission, glTF's emissive colour
    (OpenPBR's emission colour through the coat) is not needed whatever the texture holds, and was
    written from it anyway (gltf_pbr's emissive_strength defaults to 1 in MaterialX: the brass glowed,
    26 mean CIEDE2000 in GLSL)."""
    shutil.copytree(EXAMPLES, tmp_path / "resources")
    source = tmp_path / "resources" / "Materials" / "Examples" / "StandardSurface" / "standard_surface_brass_tiled.mtlx"
    out = source.parent / "brass_gltf_pbr.mtlx"
    convert_file(str(source), str(out), "gltf_pbr", Settings(), allow_outside=(str(tmp_path),))
    assert "emissive" not in read_asset(str(out)).materials[0].inputs
