"""Session 29: what session 28's red team G left open, and this session's red teams I and J. Expected values
come from closed forms (a cosine-weighted integral), MaterialX's GLSL renderer and the anchors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from glsupport import (comparison_mask, irradiance_environment, materialx_renderer, shader_generator,
                       studio_environment, uniforms, validated)
from openpbr_tools.convert import convert_file
from openpbr_tools.io import read_asset
from openpbr_tools.rules import Context
from openpbr_tools.translate import anchor
from openpbr_tools.translate.common import Settings
from openpbr_tools.translate.convert import convert
from openpbr_tools.translate.judging import as_written


# -- the studio environment's irradiance (the GLSL judge of sharpness below) ----------------------------------------

def test_the_irradiance_of_a_uniform_environment_is_its_radiance():
    """E(n) / pi of a uniform radiance L is L (MaterialX's irradiance map of the rig's uniform environment)."""
    radiance = np.full((64, 128, 3), 0.37)
    assert np.allclose(irradiance_environment(radiance), 0.37, atol=1e-3)


def test_the_irradiance_of_a_linear_sky_is_its_closed_form():
    """L(w) = a + b w_z: the integral of L max(0, n.w) over the sphere is a pi + b (2 pi / 3) n_z, so E / pi is
    a + 2 b n_z / 3 (n_z = cos of the row's polar angle), which nine spherical harmonics hold exactly."""
    height, width, a, b = 64, 128, 0.5, 0.3
    theta = np.pi * (np.arange(height) + 0.5) / height
    radiance = np.broadcast_to((a + b * np.cos(theta))[:, None, None], (height, width, 3)).copy()
    expected = a + 2.0 * b * np.cos(theta) / 3.0
    assert np.allclose(irradiance_environment(radiance)[:, 7, 1], expected, atol=2e-3)


# -- G/F2: a graphs' result that wins keeps the mapping's roughnesses ------------------------------------------------

#: the OpenPBR Shader Playground's bubbles (DigitalProductionExampleLibrary, materials/bubbles.mtlx): its values
BUBBLES = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <open_pbr_surface name="bubbles_shader" type="surfaceshader">
    <input name="fuzz_weight" type="float" value="0.5" />
    <input name="fuzz_roughness" type="float" value="0.28205" />
    <input name="coat_weight" type="float" value="1" />
    <input name="coat_ior" type="float" value="1.34375" />
    <input name="base_color" type="color3" value="1, 1, 1" />
    <input name="specular_ior" type="float" value="1.2" />
    <input name="specular_roughness" type="float" value="0.5" />
    <input name="specular_roughness_anisotropy" type="float" value="0.5" />
    <input name="subsurface_weight" type="float" value="1" />
    <input name="thin_film_ior" type="float" value="1.4" />
    <input name="thin_film_thickness" type="float" value="2000" />
    <input name="transmission_depth" type="float" value="0.3" />
    <input name="transmission_weight" type="float" value="0.8141" />
  </open_pbr_surface>
  <surfacematerial name="bubbles" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="bubbles_shader" />
  </surfacematerial>
</materialx>
"""


def _bubbles(tmp_path: Path):
    path = tmp_path / "bubbles.mtlx"
    path.write_text(BUBBLES)
    return path, read_asset(str(path)).materials[0]


def test_a_graphs_result_that_wins_keeps_the_mappings_roughness(tmp_path):
    """MaterialX's open_pbr_to_standard_surface gives a coated base its coat's roughness (its specRoughness is
    mix(specular_roughness, coat_roughness, coat_weight)): the bubbles' 0.5 became a mirror's 0, and the
    evaluator's uniform surroundings cannot see it. The kept result has the mapping's roughness, and says so."""
    path, material = _bubbles(tmp_path)
    chain = anchor.graph_candidate(material, "standard_surface")
    assert as_written(chain)["specular_roughness"] == pytest.approx(0.0, abs=1e-6)  # the premise
    mapped = convert(material, "standard_surface", Settings(context=Context(), candidates=False)).material
    report = convert_file(str(path), str(tmp_path / "out.mtlx"), "standard_surface")
    written = read_asset(str(tmp_path / "out.mtlx")).materials[0]
    assert as_written(written)["specular_roughness"] == pytest.approx(
        as_written(mapped)["specular_roughness"], abs=1e-6)
    assert as_written(written)["specular_roughness"] > 0.4
    notes = [d for d in report.diagnostics if "sharply" in d.message]
    assert notes and "specular_roughness" in notes[0].message


def test_the_kept_roughness_renders_closer_under_a_structured_environment(tmp_path):
    """Judged by MaterialX's GLSL renderer under the studio environment (a striped sky, a dark ground, two
    windows), where a clear and a frosted transmission differ: the kept result is closer to the source than the
    graphs' result whole, and than the toolkit's mapping alone."""
    from openpbr_tools.evaluate.difference import compare_images
    from openpbr_tools.evaluate.preview import Rig

    path, material = _bubbles(tmp_path)
    convert_file(str(path), str(tmp_path / "out.mtlx"), "standard_surface")
    kept = read_asset(str(tmp_path / "out.mtlx")).materials[0]
    chain = anchor.graph_candidate(material, "standard_surface")
    mapped = convert(material, "standard_surface", Settings(context=Context(), candidates=False)).material
    rig = Rig(size=64)
    renderer = materialx_renderer(rig)
    renderer.use_environment(studio_environment())
    try:
        reference = renderer.render("open_pbr_surface", uniforms(as_written(material)))
        mask = comparison_mask(rig) & np.isfinite(reference).all(axis=-1)
        delta = {name: compare_images(reference, renderer.render("standard_surface", uniforms(as_written(m))), mask,
                                      rig.white()).mean for name, m in (("kept", kept), ("chain", chain),
                                                                        ("mapped", mapped))}
    finally:
        renderer.use_environment(None)
    assert delta["kept"] < delta["chain"] - 2.0, delta
    assert delta["kept"] < delta["mapped"], delta


# -- G/F10: a mix of two constants by an image is the image's scale and bias -----------------------------------------

MIX_GRAPH = """<?xml version="1.0"?>
<materialx version="1.39">
  <nodegraph name="NG_wood">
    <constant name="low" type="float"><input name="value" type="float" value="{low}" /></constant>
    <constant name="high" type="float"><input name="value" type="float" value="{high}" /></constant>
    <image name="mask" type="vector3">
      <input name="file" type="filename" value="mask.png" />
    </image>
    <extract name="red" type="float">
      <input name="in" type="vector3" nodename="mask" />
      <input name="index" type="integer" value="0" />
    </extract>
    <mix name="range" type="float">
      <input name="fg" type="float" nodename="high" />
      <input name="bg" type="float" nodename="low" />
      <input name="mix" type="float" nodename="red" />
    </mix>
    <output name="roughness_out" type="float" nodename="range" />
  </nodegraph>
  <open_pbr_surface name="wood" type="surfaceshader">
    <input name="specular_roughness" type="float" nodegraph="NG_wood" output="roughness_out" />
  </open_pbr_surface>
  <surfacematerial name="Wood" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="wood" />
  </surfacematerial>
</materialx>
"""


@pytest.mark.parametrize("low, high", [(0.0, 0.915), (0.2, 0.8), (0.9, 0.1)])
def test_a_mix_of_two_constants_by_an_image_is_its_scale_and_bias(tmp_path, low, high):
    """GPUOpen's Oliana Blue Painted Wood: specular_roughness = mix(RoughnessMin, RoughnessMax, mask.r). MaterialX's
    mix is bg + (fg - bg) * mix (stdlib's ND_mix_float), so the texture is mask.r scaled by high - low plus low;
    it was a 'procedural graph glTF cannot hold', its roughness written as one value."""
    from openpbr_tools.model import Texture

    from redteam_support import png

    png(tmp_path / "mask.png", colour=(180, 0, 0))
    path = tmp_path / "wood.mtlx"
    path.write_text(MIX_GRAPH.format(low=low, high=high))
    texture = read_asset(str(path)).materials[0].inputs["specular_roughness"].value
    assert isinstance(texture, Texture) and texture.channels == (0,)
    assert texture.scale == pytest.approx(high - low) and (texture.bias or 0.0) == pytest.approx(low)
    convert_file(str(path), str(tmp_path / "wood.gltf"))
    document = json.loads((tmp_path / "wood.gltf").read_text())
    pbr = document["materials"][0]["pbrMetallicRoughness"]
    image = document["images"][document["textures"][pbr["metallicRoughnessTexture"]["index"]]["source"]]
    green = np.asarray(Image.open(tmp_path / image["uri"]).convert("RGB"), dtype=float)[..., 1] / 255.0
    # glTF's roughness is the factor times the texture's green channel
    assert np.allclose(pbr.get("roughnessFactor", 1.0) * green, low + (high - low) * 180.0 / 255.0, atol=1.5 / 255.0)


# -- G/F17: a normal map's strength in a UsdUVTexture's scale, which usd-core's validator warns on --------------------

def _gltf_with_normal_strength(tmp_path: Path, strength: float) -> Path:
    from redteam_support import png

    png(tmp_path / "normal.png", colour=(128, 128, 255))
    document = {"asset": {"version": "2.0"}, "images": [{"uri": "normal.png"}], "textures": [{"source": 0}],
                "materials": [{"name": "Sofa", "normalTexture": {"index": 0, "scale": strength}}]}
    path = tmp_path / "sofa.gltf"
    path.write_text(json.dumps(document))
    return path


@pytest.mark.parametrize("strength, warned", [(1.5, True), (1.0, False)])
def test_a_normal_strength_usd_core_warns_on_is_said(tmp_path, strength, warned):
    """GlamVelvetSofa's normalTexture.scale 1.5 becomes a UsdUVTexture scale (3, 3, 2) / bias (-1.5, -1.5, -1): Storm
    renders the strength, and usd-core's NormalMapTextureValidator warns (NonCompliantScaleValues: an 8-bit normal
    map takes (2, 2, 2) and (-1, -1, -1) only). The validator dropped usd-core's warning as one OPBR1006 says better,
    though OPBR1006 accepts a strength; the converter wrote it without a word."""
    from pxr import Usd, UsdValidation

    from redteam_support import findings

    report = convert_file(str(_gltf_with_normal_strength(tmp_path, strength)), str(tmp_path / "sofa.usda"))
    stage = Usd.Stage.Open(str(tmp_path / "sofa.usda"))
    validator = UsdValidation.ValidationRegistry().GetOrLoadValidatorByName(
        "usdShadeValidators:NormalMapTextureValidator")
    anchor_warns = any("NonCompliant" in str(e.GetName()) for prim in stage.Traverse() for e in validator.Validate(prim))
    assert anchor_warns is warned  # the anchor
    ours = [f for f in findings(tmp_path / "sofa.usda") if f[0] == "OPBR1010"]
    assert bool(ours) is warned
    said = [d for d in report.diagnostics if "NormalMapTextureValidator" in d.message]
    assert bool(said) is warned and all(d.location.input == "normal" or "normal" in (d.location.input or "")
                                        for d in said)


# -- session 27's E#13: a displacement shader kept in a .usda output ------------------------------------------------

DISPLACED = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="height" type="float">
    <input name="file" type="filename" value="tex/height.png" />
  </image>
  <displacement name="DS" type="displacementshader">
    <input name="displacement" type="float" nodename="height" />
    <input name="scale" type="float" value="0.05" />
  </displacement>
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" value="0.6, 0.5, 0.4" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
    <input name="displacementshader" type="displacementshader" nodename="DS" />
  </surfacematerial>
</materialx>
"""


def test_a_displacement_shader_is_written_to_usd(tmp_path):
    """A .usda output holds the OpenPBR shader as MaterialX nodes on outputs:mtlx:surface; UsdMtlx gives a
    MaterialX material's displacement shader the outputs:mtlx:displacement terminal the same way. It was dropped
    ('only a .mtlx output carries one'), with an error-level note."""
    from pxr import Usd, UsdShade

    from redteam_support import png

    png(tmp_path / "tex" / "height.png", mode="L", colour=90)
    (tmp_path / "m.mtlx").write_text(DISPLACED)
    (tmp_path / "out").mkdir()
    report = convert_file(str(tmp_path / "m.mtlx"), str(tmp_path / "out" / "m.usda"))
    assert not [d for d in report.diagnostics if "displacement" in d.message and d.code == "OPBR1104"]
    stage = Usd.Stage.Open(str(tmp_path / "out" / "m.usda"))
    material = UsdShade.Material(stage.GetPrimAtPath("/Looks/M"))
    source = material.GetDisplacementOutput("mtlx").GetConnectedSources()[0][0]
    shader = UsdShade.Shader(source.source.GetPrim())
    library = shader_generator()[0]  # MaterialX's standard libraries
    assert library.getNodeDef(shader.GetShaderId()).getNodeString() == "displacement"
    assert shader.GetInput("scale").Get() == pytest.approx(0.05)
    image = UsdShade.Shader(shader.GetInput("displacement").GetConnectedSources()[0][0].source.GetPrim())
    assert library.getNodeDef(image.GetShaderId()).getNodeString() == "image"
    file = image.GetInput("file").Get()
    assert (tmp_path / "out" / file.path).resolve() == (tmp_path / "tex" / "height.png").resolve()


# -- red team I (session 29): published assets from new sources --------------------------------------------------------

PUBLISHED = Path(__file__).resolve().parent / "data" / "published"


def test_a_thin_wall_is_a_flag_not_a_texture(tmp_path):
    """I/F1 (glTF-Blender-IO's 15_transmission): KHR_materials_transmission with a transmissionTexture and no volume.
    glTF's transmission without KHR_materials_volume is thin-walled everywhere; the thin-wall flag was baked per texel
    into an image and connected to geometry_thin_walled, a uniform boolean MaterialX's validate() rejects ('Mismatched
    types in port connection')."""
    Image.frombytes("L", (4, 1), bytes([0, 0, 255, 255])).save(tmp_path / "tx.png")  # transmissive on one half
    document = {"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_transmission"],
                "images": [{"uri": "tx.png"}], "textures": [{"source": 0}],
                "materials": [{"name": "T", "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.2},
                               "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0,
                                                                              "transmissionTexture": {"index": 0}}}}]}
    (tmp_path / "t.gltf").write_text(json.dumps(document))
    for target, flag in (("open_pbr_surface", "geometry_thin_walled"), ("standard_surface", "thin_walled")):
        out = tmp_path / f"{target}.mtlx"
        convert_file(str(tmp_path / "t.gltf"), str(out), target)
        written = validated(out)  # the anchor
        shader = next(n for n in written.getNodes() if n.getCategory() == target)
        assert shader.getInput(flag).getConnectedNode() is None and shader.getInputValue(flag) is True


def test_a_material_that_emits_nothing_writes_no_white_emissive(tmp_path):
    """I/F7 (OpenPBR's pearl; MaterialX's TestSuite utf8.mtlx): where MaterialX's graphs' result is kept, a
    non-emissive material came out as emissiveFactor (1, 1, 1) with KHR_materials_emissive_strength 0, an extension
    not required: a viewer without it renders a white glow (glTF 2.0: a client may ignore an extension only in
    extensionsUsed). Emission is emissiveFactor times emissiveStrength: 0, which core glTF says by its default."""
    convert_file(str(PUBLISHED / "openpbr" / "open_pbr_pearl.mtlx"), str(tmp_path / "pearl.gltf"))
    document = json.loads((tmp_path / "pearl.gltf").read_text())
    for material in document["materials"]:
        strength = material.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
        emitted = np.asarray(material.get("emissiveFactor", [0.0, 0.0, 0.0])) * strength
        assert np.allclose(emitted, 0.0) and np.allclose(material.get("emissiveFactor", [0.0, 0.0, 0.0]), 0.0)
    assert "KHR_materials_emissive_strength" not in document.get("extensionsUsed", [])


SKIN = """<?xml version="1.0"?>
<materialx version="1.39">
  <open_pbr_surface name="skin" type="surfaceshader">
    <input name="subsurface_weight" type="float" value="1" />
    <input name="subsurface_color" type="color3" value="0.8, 0.5, 0.4" />
    {radius}
  </open_pbr_surface>
  <surfacematerial name="Skin" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="skin" />
  </surfacematerial>
</materialx>
"""


def test_a_default_length_is_converted_as_an_authored_one(tmp_path):
    """I/F3 (OpenPBR's skin examples leave subsurface_radius at its default 1): to a .usda stage in centimetres, an
    authored 1 (taken as metres) became 100 and the default stayed unwritten, read as 1 cm: the same material 100x
    apart. Both are now 100 (1 m in a stage of metersPerUnit 0.01)."""
    from pxr import Usd, UsdGeom, UsdShade

    radii = []
    for name, radius in (("explicit", '<input name="subsurface_radius" type="float" value="1.0" />'), ("implicit", "")):
        (tmp_path / f"{name}.mtlx").write_text(SKIN.format(radius=radius))
        convert_file(str(tmp_path / f"{name}.mtlx"), str(tmp_path / f"{name}.usda"))
        stage = Usd.Stage.Open(str(tmp_path / f"{name}.usda"))
        shader = next(UsdShade.Shader(p) for p in stage.Traverse()
                      if p.IsA(UsdShade.Shader) and "open_pbr" in str(UsdShade.Shader(p).GetShaderId()))
        radii.append(shader.GetInput("subsurface_radius").Get() * UsdGeom.GetStageMetersPerUnit(stage))
    assert radii == pytest.approx([1.0, 1.0])  # metres, both


CUTOUT = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <nodegraph name="G">
    <texcoord name="tc" type="vector2" />
    <transformmatrix name="xf" type="vector2">
      <input name="mat" type="matrix33" value="4, 0, 0, 0, 4, 0, 0, 0, 1" />
      <input name="in" type="vector2" nodename="tc" />
    </transformmatrix>
    <image name="mask" type="color3">
      <input name="file" type="filename" value="mask.png" colorspace="lin_rec709" />
      <input name="texcoord" type="vector2" nodename="xf" />
    </image>
    <output name="cut" type="color3" nodename="mask" />
  </nodegraph>
  <standard_surface name="SS" type="surfaceshader">
    <input name="opacity" type="color3" nodegraph="G" output="cut" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SS" />
  </surfacematerial>
</materialx>
"""


def test_a_graph_a_mapping_changes_is_written_as_nodes_to_usd_too(tmp_path):
    """I/F6 (MaterialX's TestSuite brass_wire_mesh): Standard Surface's colour opacity from a graph becomes OpenPBR's
    float geometry_opacity by an affine map a .mtlx output writes after the kept graph as MaterialX nodes; a .usda
    output, whose OpenPBR shader is MaterialX nodes too (outputs:mtlx:surface), dropped the cut-out (OPBR1104). Its
    network's every shader is a MaterialX node definition, and the opacity input is connected."""
    from pxr import Usd, UsdShade

    from redteam_support import png

    png(tmp_path / "mask.png", colour=(255, 255, 255))
    (tmp_path / "m.mtlx").write_text(CUTOUT)
    report = convert_file(str(tmp_path / "m.mtlx"), str(tmp_path / "m.usda"))
    assert not [d for d in report.diagnostics if d.code == "OPBR1104" and d.location.input == "opacity"]
    stage = Usd.Stage.Open(str(tmp_path / "m.usda"))
    shader = next(UsdShade.Shader(p) for p in stage.Traverse() if p.IsA(UsdShade.Shader)
                  and str(UsdShade.Shader(p).GetShaderId()).startswith("ND_open_pbr_surface"))
    assert shader.GetInput("geometry_opacity").HasConnectedSource()
    library = shader_generator()[0]  # MaterialX's standard libraries
    preview = {"UsdPreviewSurface", "UsdUVTexture", "UsdPrimvarReader_float2", "UsdTransform2d"}  # (the fallback's)
    ids = {str(UsdShade.Shader(p).GetShaderId()) for p in stage.Traverse() if p.IsA(UsdShade.Shader)} - preview
    assert ids and all(library.getNodeDef(i) is not None for i in ids), ids
    assert any(library.getNodeDef(i).getNodeString() == "transformmatrix" for i in ids)


WRAPPED = """#usda 1.0
(
    defaultPrim = "M"
    metersPerUnit = 1
)

def Material "M"
{
    token outputs:mtlx:surface.connect = </M/S.outputs:out>

    def Shader "S"
    {
        uniform token info:id = "ND_open_pbr_surface_surfaceshader"
        float inputs:specular_roughness.connect = </M/tex.outputs:r>
        token outputs:out
    }

    def Shader "tex"
    {
        uniform token info:id = "ND_UsdUVTexture_23"
        asset inputs:file = @grid.png@
        string inputs:wrapS = "WRAP"
        string inputs:wrapT = "periodic"
        float outputs:r
    }
}
"""


@pytest.mark.parametrize("wrap, wrong", [("constant", True), ("mirror", False)])
def test_an_enum_of_a_materialx_node_in_usd_is_checked(tmp_path, wrap, wrong):
    """I/F2 (Adobe's USD-Fileformat-plugins baseline_writeOpenPBR.usda): an ND_UsdUVTexture_23 node with wrapS
    'constant' validated clean in USD, though the same node in a .mtlx is OPBR303; MaterialX's definition lists black,
    clamp, periodic, mirror, and its shader generation refuses another ('not a valid enum value')."""
    from redteam_support import findings, png

    png(tmp_path / "grid.png")
    (tmp_path / "m.usda").write_text(WRAPPED.replace("WRAP", wrap))
    library = shader_generator()[0]  # MaterialX's standard libraries
    allowed = library.getNodeDef("ND_UsdUVTexture_23").getActiveInput("wrapS").getAttribute("enum").split(",")
    assert (wrap not in allowed) is wrong  # the anchor's list
    found = [f for f in findings(tmp_path / "m.usda") if f[0] == "OPBR303"]
    assert [(f[2], f[3]) for f in found] == ([("/M/tex", "wrapS")] if wrong else [])


#: Adobe's USD-Fileformat-plugins gltf/tests/ExtFuzz.gltf, its material: a grey base, KHR_materials_fuzz 0.8 orange
EXT_FUZZ = {"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_fuzz"],
            "materials": [{"name": "FuzzMaterial",
                           "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0,
                                                    "roughnessFactor": 0.8},
                           "extensions": {"KHR_materials_fuzz": {"fuzzFactor": 0.8, "fuzzColorFactor": [0.9, 0.5, 0.2],
                                                                 "fuzzRoughnessFactor": 0.6}}}]}


def test_a_draft_fuzz_is_judged_as_its_openpbr_reading(tmp_path):
    """I/F4 (Adobe's USD-Fileformat-plugins gltf/tests/ExtFuzz.gltf: a grey base, KHR_materials_fuzz 0.8 orange): to
    Standard Surface, the candidate search judged against the glTF material, whose shading model has no fuzz, and the
    appearance fit turned the grey base blue to cancel the orange sheen (MaterialX's GLSL: 1.74 against the source,
    0.26 through the OpenPBR document the toolkit writes from the same glTF). The two paths now agree."""
    import MaterialX as mx

    (tmp_path / "fuzz.gltf").write_text(json.dumps(EXT_FUZZ))
    convert_file(str(tmp_path / "fuzz.gltf"), str(tmp_path / "direct.mtlx"), "standard_surface")
    convert_file(str(tmp_path / "fuzz.gltf"), str(tmp_path / "openpbr.mtlx"))
    convert_file(str(tmp_path / "openpbr.mtlx"), str(tmp_path / "through.mtlx"), "standard_surface")

    def shader(path):
        written = mx.createDocument()
        mx.readFromXmlFile(written, str(path))
        node = next(n for n in written.getNodes() if n.getCategory() == "standard_surface")
        return {i.getName(): i.getValueString() for i in node.getInputs()}

    direct, through = shader(tmp_path / "direct.mtlx"), shader(tmp_path / "through.mtlx")
    assert direct.get("base_color") == "0.5, 0.5, 0.5"
    for name in ("base_color", "sheen", "sheen_color", "sheen_roughness"):
        assert np.allclose([float(v) for v in direct[name].split(",")], [float(v) for v in through[name].split(",")],
                           atol=1e-4), name


# -- red team J (session 29): realistic ACEScg materials judged by MaterialX's GLSL ------------------------------------

def test_a_conductor_of_negative_n_reflects_as_materialx_computes_it():
    """Gulbrandsen's artistic IOR extrapolates n below 0 for an edge colour above 1 (a measured metal's F82 tint in
    ACEScg): n = mix(n_max, n_min, g). MaterialX's mx_fresnel_conductor depends on n^2 and k^2 only, so at normal
    incidence it gives ((|n| - 1)^2 + k^2) / ((|n| + 1)^2 + k^2) (Born & Wolf); the evaluator's complex form gave 1.22
    for such a copper's red, and scored MaterialX's graphs' Standard Surface copper 1.68 where GLSL measured 11.98."""
    from openpbr_tools.evaluate.fresnel import artistic_ior, fresnel_conductor, fresnel_conductor_real

    n, k = artistic_ior(np.array([1.25, 0.617, 0.444]), np.array([1.05, 0.92, 0.89]))
    assert n[0] < 0  # the premise: an extrapolated n
    normal = ((np.abs(n) - 1.0) ** 2 + k ** 2) / ((np.abs(n) + 1.0) ** 2 + k ** 2)
    assert np.allclose(fresnel_conductor(1.0, n, k), normal, atol=1e-9)
    for cosine in (0.9, 0.5, 0.1):
        assert np.allclose(fresnel_conductor(cosine, n, k), fresnel_conductor_real(cosine, n, k), atol=1e-9)
    assert np.all(fresnel_conductor(np.linspace(0.0, 1.0, 11)[:, None], n, k) <= 1.0)


COPPER = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="acescg">
  <open_pbr_surface name="SR_copper" type="surfaceshader">
    <input name="base_metalness" type="float" value="1" />
    <input name="base_color" type="color3" value="1.01, 0.66, 0.48" />
    <input name="specular_color" type="color3" value="1, 0.93, 0.9" />
    <input name="specular_roughness" type="float" value="0.3" />
  </open_pbr_surface>
  <surfacematerial name="copper" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_copper" />
  </surfacematerial>
</materialx>
"""


def test_an_acescg_copper_is_not_given_the_graphs_extrapolated_edge(tmp_path):
    """J/F1: a copper with an ACEScg base colour slightly above 1, to Standard Surface. The graphs pass the edge colour
    through (1.05 in Rec.709's red): MaterialX's GLSL renders it 11.98 off, the toolkit's mapping 5.98; the evaluator
    chose the graphs' (1.68 against 6.13). Judged by MaterialX's GLSL on the rig's sphere, the kept result is closer
    than the graphs' by far."""
    from openpbr_tools.evaluate.difference import compare_images
    from openpbr_tools.evaluate.preview import Rig

    (tmp_path / "copper.mtlx").write_text(COPPER)
    material = read_asset(str(tmp_path / "copper.mtlx")).materials[0]
    convert_file(str(tmp_path / "copper.mtlx"), str(tmp_path / "out.mtlx"), "standard_surface")
    kept = read_asset(str(tmp_path / "out.mtlx")).materials[0]
    chain = anchor.graph_candidate(material, "standard_surface")
    rig = Rig(size=64)
    renderer = materialx_renderer(rig)
    reference = renderer.render("open_pbr_surface", uniforms(as_written(material)))
    mask = comparison_mask(rig) & np.isfinite(reference).all(axis=-1)
    kept_delta, chain_delta = (compare_images(reference, renderer.render("standard_surface", uniforms(as_written(m))),
                                              mask, rig.white()).mean for m in (kept, chain))
    assert kept_delta < chain_delta - 3.0, (kept_delta, chain_delta)


def test_a_gold_to_usd_preview_is_the_same_from_any_document_space(tmp_path):
    """J/F2: physicallybased.info's gold (linear Rec.709 (1.059, 0.773, 0.307), F82 (0.99, 0.93, 0.77)) re-expressed
    in an ACEScg document: the graphs pass its base colour to diffuseColor, 1.059 in red, which MaterialX's
    UsdPreviewSurface renders as an artistic-IOR conductor clamped at 0.99 and extrapolated (GLSL 4.70 against 1.64
    from the lin_rec709 document). The results agree now: within 0.5 (#13's invariance), both held to 1."""
    rec709 = {"base_color": (1.059, 0.773, 0.307), "specular_color": (0.99, 0.93, 0.77)}
    from openpbr_tools import colorspaces

    written = {}
    for space in ("lin_rec709", "acescg"):
        values = {k: colorspaces.from_lin_rec709(v, space) for k, v in rec709.items()}
        text = COPPER.replace("acescg", space).replace("SR_copper", "SR_gold").replace("copper", "gold")
        text = text.replace("1.01, 0.66, 0.48", ", ".join(f"{v:.6f}" for v in values["base_color"]))
        text = text.replace("1, 0.93, 0.9", ", ".join(f"{v:.6f}" for v in values["specular_color"]))
        text = text.replace('"0.3"', '"0.2"')
        (tmp_path / f"{space}.mtlx").write_text(text)
        convert_file(str(tmp_path / f"{space}.mtlx"), str(tmp_path / f"{space}_out.mtlx"), "UsdPreviewSurface")
        out = read_asset(str(tmp_path / f"{space}_out.mtlx")).materials[0]
        written[space] = np.asarray(colorspaces.to_lin_rec709(as_written(out)["diffuseColor"], None))
    assert np.all(written["acescg"] <= 1.0 + 1e-6)
    assert np.allclose(written["acescg"], written["lin_rec709"], atol=0.01), written


def test_a_missing_texture_is_said_to_be_rebased_as_it_is(tmp_path):
    """I/F9 (MaterialX's TestSuite reads resources/Images/... through the application's search path): a missing
    texture's reference is rebased against the output's folder, so it names the same file; the note said 'written as
    authored', which the output contradicted."""
    (tmp_path / "m.mtlx").write_text(
        '<?xml version="1.0"?>\n<materialx version="1.39">\n  <image name="i" type="color3">\n'
        '    <input name="file" type="filename" value="resources/Images/grid.png" />\n  </image>\n'
        '  <open_pbr_surface name="S" type="surfaceshader">\n'
        '    <input name="base_color" type="color3" nodename="i" />\n  </open_pbr_surface>\n</materialx>\n')
    (tmp_path / "out").mkdir()
    report = convert_file(str(tmp_path / "m.mtlx"), str(tmp_path / "out" / "m.mtlx"))
    notes = [d.message for d in report.diagnostics if "does not exist" in d.message]
    assert notes and "rebased" in notes[0] and "written as authored" not in notes[0]
    assert "../resources/Images/grid.png" in (tmp_path / "out" / "m.mtlx").read_text()


TWO_TONE = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <nodegraph name="NG">
    <image name="mask" type="float">
      <input name="file" type="filename" value="mask.png" />
    </image>
    <mix name="two_tone" type="color3">
      <input name="fg" type="color3" value="0.8, 0.1, 0.1" />
      <input name="bg" type="color3" value="0.1, 0.1, 0.8" />
      <input name="mix" type="float" nodename="mask" />
    </mix>
    <output name="out" type="color3" nodename="two_tone" />
  </nodegraph>
  <open_pbr_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" nodegraph="NG" output="out" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
"""


def test_a_colour_mix_by_a_float_mask_is_not_read_as_the_mask(tmp_path):
    """The control of the float mix above: a two-tone colour, mix(blue, red, mask) with a float mask, is a colour the
    image alone cannot be (a Texture is one image's channels); read as the mask with a colour scale, validate called
    the valid document a type mismatch (OPBR702) and the .mtlx and USD outputs wired the float image to base_color.
    MaterialX validates the document and the outputs."""
    from redteam_support import findings, png

    png(tmp_path / "mask.png", mode="L", colour=128)
    (tmp_path / "m.mtlx").write_text(TWO_TONE)
    assert not [f for f in findings(tmp_path / "m.mtlx") if f[1] == "error"]
    for output in ("out.mtlx", "out.usda"):
        convert_file(str(tmp_path / "m.mtlx"), str(tmp_path / output))
        assert not [f for f in findings(tmp_path / output) if f[1] == "error"], output
    validated(tmp_path / "out.mtlx")


def test_a_materialx_image_address_mode_in_usd_is_said_once(tmp_path):
    """A MaterialX image node in USD (ND_image_color3) with uaddressmode 'repeat' (USD's UsdUVTexture word; MaterialX's
    list is constant, clamp, periodic, mirror): the enum check of every MaterialX node and the texture's own check said
    it twice."""
    from redteam_support import findings, png

    png(tmp_path / "grid.png")
    stage = WRAPPED.replace('"ND_UsdUVTexture_23"', '"ND_image_float"').replace(
        '        string inputs:wrapS = "WRAP"\n        string inputs:wrapT = "periodic"\n',
        '        string inputs:uaddressmode = "repeat"\n').replace("outputs:r", "outputs:out")
    (tmp_path / "m.usda").write_text(stage)
    found = [(f[2], f[3]) for f in findings(tmp_path / "m.usda") if f[0] == "OPBR303"]
    assert found == [("/M/tex", "uaddressmode")]


def test_verify_judges_a_draft_fuzz_as_its_openpbr_reading(tmp_path):
    """I/F5's figure: --verify compared the Standard Surface result with the glTF material, whose shading model has no
    fuzz, and said 4.59 mean CIEDE2000; MaterialX's GLSL, against the OpenPBR reading of the same glTF, measures the
    result about 1. Both judges agree now (within 1)."""
    from openpbr_tools.evaluate.difference import compare_images
    from openpbr_tools.evaluate.preview import Rig
    from openpbr_tools.verification import measure

    (tmp_path / "fuzz.gltf").write_text(json.dumps(EXT_FUZZ))
    conversion = convert_file(str(tmp_path / "fuzz.gltf"), str(tmp_path / "out.mtlx"), "standard_surface")
    (_, statistics), = measure(conversion)
    convert_file(str(tmp_path / "fuzz.gltf"), str(tmp_path / "reading.mtlx"))
    reading = read_asset(str(tmp_path / "reading.mtlx")).materials[0]
    written = read_asset(str(tmp_path / "out.mtlx")).materials[0]
    rig = Rig(size=64)
    renderer = materialx_renderer(rig)
    reference = renderer.render("open_pbr_surface", uniforms(as_written(reading)))
    mask = comparison_mask(rig) & np.isfinite(reference).all(axis=-1)
    glsl = compare_images(reference, renderer.render("standard_surface", uniforms(as_written(written))), mask,
                          rig.white()).mean
    assert statistics.mean < 2.3 and abs(statistics.mean - glsl) < 1.0, (statistics.mean, glsl)
