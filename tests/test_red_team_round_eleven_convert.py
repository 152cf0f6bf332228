"""Session 24's red team, set Z: the converter on published files nobody here had converted (bevy's glTF, kwokcb's
glTF_MaterialX documents, bhouston's materialx.js examples), judged by MaterialX's GLSL renderer. Three conversions
changed the look without a warning, each against its authority:

* F1: a glTF metal with KHR_materials_specular's specular 0 became a black OpenPBR metal (33-40 mean CIEDE2000):
  glTF's specular scales "the specular reflection of the dielectric" only, OpenPBR's specular_weight dims its metal
  too (open_pbr_surface.mtlx multiplies the metal's F82 Fresnel by it).
* F13: a gltf_pbr fed by MaterialX's own standard_surface_to_gltf_pbr node (a multi-output node) was written with
  connections that name no output: MaterialX validates the document and its GLSL does not compile.
* F12: an untagged colour texture in a document without a colour space (MaterialX reads its texels as they are,
  linear) was copied into glTF's baseColorTexture, which every viewer decodes as sRGB.
"""

from __future__ import annotations

import json

import numpy as np
from PIL import Image

from openpbr_tools.convert import convert_file
from openpbr_tools.translate.common import Settings
from openpbr_tools.verification import measure
from redteam_support import mtlx

_GLTF_METAL = '''
    <gltf_pbr name="SR_gold" type="surfaceshader">
      <input name="base_color" type="color3" value="0.9, 0.6, 0.3" />
      <input name="metallic" type="float" value="{metallic}" />
      <input name="roughness" type="float" value="0.3" />
      <input name="specular" type="float" value="0" />
    </gltf_pbr>
    <surfacematerial name="M_gold" type="material">
      <input name="surfaceshader" type="surfaceshader" nodename="SR_gold" />
    </surfacematerial>
'''


def _converted(source, out, model):
    conversion = convert_file(str(source), str(out), model, Settings())
    return conversion, [delta.mean for _, delta in measure(conversion)]


def test_a_gltf_metal_at_specular_zero_stays_a_metal(tmp_path):
    source = mtlx(tmp_path, _GLTF_METAL.format(metallic=1))
    for model in ("open_pbr_surface", "standard_surface", "UsdPreviewSurface"):
        conversion, (mean,) = _converted(source, tmp_path / f"{model}.mtlx", model)
        assert mean < 1.0, (model, mean)  # it was 33-40: a black sphere
    written = (tmp_path / "open_pbr_surface.mtlx").read_text(encoding="utf-8")
    assert 'name="base_metalness" type="float" value="1"' in written and "specular_weight" not in written
    conversion, _ = _converted(source, tmp_path / "again.mtlx", "open_pbr_surface")
    notes = [d for d in conversion.diagnostics if d.location.input == "specular"]
    assert notes and "dielectric only" in notes[0].message  # the value not carried has its note


def test_a_dielectric_at_specular_zero_keeps_its_weight(tmp_path):
    source = mtlx(tmp_path, _GLTF_METAL.format(metallic=0))
    _converted(source, tmp_path / "out.mtlx", "open_pbr_surface")
    assert 'name="specular_weight" type="float" value="0"' in (tmp_path / "out.mtlx").read_text(encoding="utf-8")


_TRANSLATED = '''
    <nodegraph name="NG">
      <standard_surface_to_gltf_pbr name="translate" type="multioutput" nodedef="ND_standard_surface_to_gltf_pbr">
        <input name="base_color" type="color3" value="0.1, 0.6, 0.85" />
        <input name="coat" type="float" value="1" />
      </standard_surface_to_gltf_pbr>
      <output name="base_color_out" type="color3" nodename="translate" output="base_color_out" />
      <output name="clearcoat_out" type="float" nodename="translate" output="clearcoat_out" />
    </nodegraph>
    <gltf_pbr name="S" type="surfaceshader">
      <input name="base_color" type="color3" nodegraph="NG" output="base_color_out" />
      <input name="clearcoat" type="float" nodegraph="NG" output="clearcoat_out" />
    </gltf_pbr>
    <surfacematerial name="M" type="material">
      <input name="surfaceshader" type="surfaceshader" nodename="S" />
    </surfacematerial>
'''


def test_a_kept_graph_reads_the_output_of_a_multi_output_node(tmp_path):
    import MaterialX as mx

    source = mtlx(tmp_path, _TRANSLATED)
    convert_file(str(source), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings())
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(tmp_path / "out.mtlx"))
    multi = {n.getName() for n in document.getNodes() if n.getType() == "multioutput"}
    reads = [p for n in document.getNodes() for p in n.getInputs() if p.getNodeName() in multi]
    assert multi and reads
    # every connection to the translation node names its output, as the source's graph outputs did
    assert sorted({p.getOutputString() for p in reads}) == ["base_color_out", "clearcoat_out"]
    assert {document.getNode("S").getInput(n).getNodeName() for n in ("base_color", "coat_weight")}.isdisjoint(multi)
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    document.importLibrary(library)
    assert document.validate()[0]


def test_an_untagged_colour_texture_is_encoded_for_gltfs_srgb_slot(tmp_path):
    Image.new("RGB", (4, 4), (64, 128, 192)).save(tmp_path / "albedo.png")
    source = tmp_path / "m.mtlx"  # no colorspace on the document or the image: MaterialX reads the texels linear
    source.write_text('''<?xml version="1.0"?>
<materialx version="1.39">
  <image name="albedo" type="color3"><input name="file" type="filename" value="albedo.png" /></image>
  <open_pbr_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="albedo" /></open_pbr_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
</materialx>
''', encoding="utf-8")
    out = tmp_path / "out" / "m.gltf"
    convert_file(str(source), str(out), None, Settings())
    document = json.loads(out.read_text(encoding="utf-8"))
    texture = document["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"]
    image = document["images"][document["textures"][texture]["source"]]["uri"]
    written = np.asarray(Image.open(out.parent / image).convert("RGB"), dtype=float)[0, 0] / 255.0
    linear = np.array([64, 128, 192]) / 255.0
    # glTF decodes baseColorTexture as sRGB (3.9.2): the written texel must decode to the linear value MaterialX reads
    decoded = np.where(written <= 0.04045, written / 12.92, ((written + 0.055) / 1.055) ** 2.4)
    assert np.allclose(decoded, linear, atol=1.5 / 255)


_COMPILE = """
import sys, MaterialX as mx, MaterialX.PyMaterialXGenGlsl as glsl, MaterialX.PyMaterialXGenShader as gen
import MaterialX.PyMaterialXRender as render, MaterialX.PyMaterialXRenderGlsl as rglsl
document = mx.createDocument(); mx.readFromXmlFile(document, sys.argv[1])
library = mx.createDocument(); mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
document.importLibrary(library)
generator = glsl.GlslShaderGenerator.create(); context = gen.GenContext(generator)
context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
renderer = rglsl.GlslRenderer.create(16, 16, render.BaseType.UINT8); renderer.initialize()
for material in document.getMaterialNodes():
    renderer.createProgram(generator.generate(material.getName(), material, context))
print("compiled")
"""


def test_the_kept_translation_graph_compiles_in_materialxs_glsl(tmp_path):
    """MaterialX validated the earlier output; its GLSL compiler refused it ("no matching function for call to
    NG_open_pbr_surface_surfaceshader"): the connections to the multi-output node named no output."""
    import os
    import subprocess
    import sys

    from glsupport import require_gl

    require_gl()
    source = mtlx(tmp_path, _TRANSLATED)
    convert_file(str(source), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings())
    run = subprocess.run([sys.executable, "-c", _COMPILE, str(tmp_path / "out.mtlx")], capture_output=True, text=True,
                         timeout=300, env=os.environ.copy())
    assert run.returncode == 0 and "compiled" in run.stdout, (run.stdout + run.stderr)[-2000:]


def test_a_constant_occlusion_is_no_glTF_property(tmp_path):
    """F8: glTF has no occlusion constant (only occlusionTexture); a gltf_pbr's occlusion 1 (its default, no
    occlusion) was written as a material property named "null", which the Khronos validator flags."""
    body = '''
        <gltf_pbr name="S" type="surfaceshader">
          <input name="base_color" type="color3" value="0.8, 0.8, 0.8" />
          <input name="occlusion" type="float" value="{occlusion}" />
        </gltf_pbr>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>'''
    for occlusion in (1, 0.5):
        source = mtlx(tmp_path, body.format(occlusion=occlusion), name=f"o{occlusion}.mtlx")
        out = tmp_path / f"o{occlusion}.gltf"
        conversion = convert_file(str(source), str(out), None, Settings())
        material = json.loads(out.read_text(encoding="utf-8"))["materials"][0]
        assert "null" not in material and None not in material
        said = [d for d in conversion.diagnostics if d.location.input == "occlusion"]
        assert bool(said) == (occlusion != 1), occlusion  # 0.5 is lost, and said so


_TILED = '''
    <texcoord name="uv" type="vector2" />
    <constant name="tiles" type="float"><input name="value" type="float" value="2" /></constant>
    <multiply name="tiled" type="vector2">
      <input name="in1" type="vector2" nodename="uv" />
      <input name="in2" type="float" nodename="tiles" />
    </multiply>
    <image name="albedo" type="color3">
      <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />
      <input name="texcoord" type="vector2" nodename="tiled" />
    </image>
    <open_pbr_surface name="S" type="surfaceshader">
      <input name="base_color" type="color3" nodename="albedo" />
    </open_pbr_surface>
    <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" />
    </surfacematerial>
'''


def test_uvs_multiplied_by_a_constant_are_a_texture_transform(tmp_path):
    """F3: a texture read at texcoord * 2 (kwokcb's TH_Cathedral_Floor_Tiles) was a procedural graph, so glTF and USD
    outputs dropped it. MaterialX's place2d divides by its scale (NG_place2d_vector2), so uv * 2 is scale 1/2 there
    and KHR_texture_transform's scale 2 (glTF multiplies the UVs by it)."""
    from openpbr_tools.io import read_asset
    from openpbr_tools.model import Texture

    Image.new("RGB", (4, 4), (200, 120, 40)).save(tmp_path / "albedo.png")
    source = mtlx(tmp_path, _TILED)
    entry = read_asset(str(source)).materials[0].inputs["base_color"]
    assert isinstance(entry.value, Texture) and entry.value.uv is not None and entry.value.uv.scale == (0.5, 0.5)
    out = tmp_path / "out" / "m.gltf"
    convert_file(str(source), str(out), None, Settings())
    info = json.loads(out.read_text(encoding="utf-8"))["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]
    assert info["extensions"]["KHR_texture_transform"]["scale"] == [2.0, 2.0]


def test_a_height_map_in_a_kept_graph_is_still_found(tmp_path):
    """Session 23's m03 (a height map decoded by a normalmap inside a graph) now reads as a texture when the UVs are
    only tiled (tests/test_red_team_round_ten.py); where the coordinates are computed (uv * uv) the graph is kept,
    and OPBR709 judges the image the normalmap decodes (document_checks)."""
    from redteam_support import findings, messages
    from test_red_team_round_ten import _GRAPH

    Image.new("L", (8, 8), 128).save(tmp_path / "height.png")
    computed = _GRAPH.replace('<input name="in2" type="float" value="2" />', '<input name="in2" type="vector2" nodename="uv" />')
    assert computed != _GRAPH
    broken = mtlx(tmp_path, computed.format(file="height.png"), name="broken.mtlx")
    assert [f[:2] for f in findings(broken) if f[0] == "OPBR709"] == [("OPBR709", "warning")]
    assert "NG/decode decodes 'height.png'" in messages(broken, "OPBR709")[0]


# -- the review of the diff (/tmp/review24/REVIEW.md) ----------------------------------------------------------------

def test_a_nearly_whole_metal_at_specular_zero_is_not_black(tmp_path):
    """Review 2: the fix held at metallic 1 exactly; a texel of 254/255 metal (0.996) was as black as before."""
    for metallic in (0.999, 0.95):
        source = mtlx(tmp_path, _GLTF_METAL.format(metallic=metallic), name=f"m{metallic}.mtlx")
        _, (mean,) = _converted(source, tmp_path / f"out{metallic}.mtlx", "open_pbr_surface")
        assert mean < 1.0, (metallic, mean)


def test_a_tiling_multiply_under_a_gltf_images_own_transform_is_not_dropped(tmp_path):
    """Review 1: a gltf_colorimage with its own offset, read at texcoord * 4, came out with the offset alone (the
    tiling silently lost). One transform cannot compose both, so the graph is kept, as before."""
    from openpbr_tools.io import read_asset
    from openpbr_tools.model import Connection

    Image.new("RGB", (4, 4), (200, 120, 40)).save(tmp_path / "albedo.png")
    source = mtlx(tmp_path, '''
        <texcoord name="uv" type="vector2" />
        <multiply name="tiled" type="vector2">
          <input name="in1" type="vector2" nodename="uv" /><input name="in2" type="float" value="4" />
        </multiply>
        <gltf_colorimage name="albedo" type="multioutput">
          <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />
          <input name="texcoord" type="vector2" nodename="tiled" />
          <input name="offset" type="vector2" value="0.25, 0" />
        </gltf_colorimage>
        <gltf_pbr name="S" type="surfaceshader">
          <input name="base_color" type="color3" nodename="albedo" output="outcolor" />
        </gltf_pbr>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>''')
    assert isinstance(read_asset(str(source)).materials[0].inputs["base_color"].value, Connection)


def test_a_uniform_input_fed_through_a_definitions_geometric_default_varies(tmp_path):
    """Review 4: a custom node whose definition defaults an input to the object position (defaultgeomprop Pobject),
    left unset on the instance, read that input as the inner node's (no default) and was judged constant."""
    from redteam_support import findings

    source = mtlx(tmp_path, '''
        <nodedef name="ND_side" node="side">
          <input name="pos" type="vector3" defaultgeomprop="Pobject" />
          <output name="out" type="boolean" />
        </nodedef>
        <nodegraph name="NG_side" nodedef="ND_side">
          <extract name="x" type="float"><input name="in" type="vector3" interfacename="pos" /></extract>
          <ifgreater name="g" type="boolean">
            <input name="value1" type="float" nodename="x" /><input name="value2" type="float" value="0" />
          </ifgreater>
          <output name="out" type="boolean" nodename="g" />
        </nodegraph>
        <side name="m" type="boolean" />
        <open_pbr_surface name="S" type="surfaceshader">
          <input name="geometry_thin_walled" type="boolean" nodename="m" />
        </open_pbr_surface>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>''')
    assert ("OPBR204", "error") in [f[:2] for f in findings(source)]


def test_a_metalness_mask_is_judged_on_its_texels_not_their_mean(tmp_path):
    """Review 3: a 0/1 metalness mask under a constant gold at specular 0 solves cleanly texel by texel, but the
    "base colour clipped" warning was judged at the mask's mean (0.5, a partial metal that clipped under glTF's
    specular 0): a false warning. With the weight solved for partial metals too (review 2), the mean clips no more."""
    mask = np.zeros((4, 4), dtype=np.uint8)
    mask[:, 2:] = 255
    Image.fromarray(mask, "L").save(tmp_path / "metal.png")
    source = mtlx(tmp_path, '''
        <image name="mi" type="float"><input name="file" type="filename" value="metal.png" /></image>
        <gltf_pbr name="S" type="surfaceshader">
          <input name="metallic" type="float" nodename="mi" />
          <input name="base_color" type="color3" value="0.9, 0.6, 0.3" />
          <input name="specular" type="float" value="0" />
        </gltf_pbr>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>''')
    conversion = convert_file(str(source), str(tmp_path / "out.mtlx"), "open_pbr_surface", Settings())
    assert not [d for d in conversion.diagnostics if "clipped" in d.message and d.location.input == "base_color"]


def test_a_place2d_under_a_tiledimage_composes_with_its_tiling(tmp_path):
    """Review 5 (older than the session): NG_tiledimage tiles its texcoord input, so a place2d's scale s there and a
    tiling t give uv / s * t, a transform of scale s / t; the place2d's scale replaced the tiling. A place2d that also
    rotates or offsets is kept as a graph (one transform cannot hold both)."""
    from openpbr_tools.io import read_asset
    from openpbr_tools.model import Connection, Texture

    Image.new("RGB", (4, 4), (200, 120, 40)).save(tmp_path / "c.png")
    body = '''
        <texcoord name="uv" type="vector2" />
        <place2d name="p" type="vector2">
          <input name="scale" type="vector2" value="0.5, 0.5" />{extra}
          <input name="texcoord" type="vector2" nodename="uv" />
        </place2d>
        <tiledimage name="img" type="color3">
          <input name="file" type="filename" value="c.png" colorspace="srgb_texture" />
          <input name="texcoord" type="vector2" nodename="p" />
          <input name="uvtiling" type="vector2" value="4, 4" />
        </tiledimage>
        <open_pbr_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="img" />
        </open_pbr_surface>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>'''
    scaled = read_asset(str(mtlx(tmp_path, body.format(extra=""), name="s.mtlx"))).materials[0].inputs["base_color"]
    assert isinstance(scaled.value, Texture) and scaled.value.uv.scale == (0.125, 0.125)
    rotated = mtlx(tmp_path, body.format(extra='\n          <input name="rotate" type="float" value="30" />'), name="r.mtlx")
    assert isinstance(read_asset(str(rotated)).materials[0].inputs["base_color"].value, Connection)
