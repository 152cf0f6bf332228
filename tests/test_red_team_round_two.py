"""The second round of the session-15 red-team set (files written without reading this code), each finding
proven against the anchor that decides it: MaterialX's GLSL generator and renderer (enums, colour spaces,
defaultgeomprop), OpenUSD's and MaterialX's UDIM token, the OpenPBR 1.1.1 specification, the glTF extension
texts and the Khronos glTF-Validator."""

from __future__ import annotations

import json
import shutil
import textwrap
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.validate import Options, validate_paths
from redteam_support import codes as _codes, mtlx as _mtlx

BROKEN = Path(__file__).parent / "data" / "broken"
PUBLISHED = Path(__file__).parent / "data" / "published"




def _glsl(path, colour_managed: bool = False) -> tuple[str | None, str | None]:
    """MaterialX's GLSL generator on the document's first renderable element: ``(pixel source, None)``, or
    ``(None, its error)``; ``colour_managed``: with MaterialX's default colour management, to lin_rec709."""
    import MaterialX as mx
    import MaterialX.PyMaterialXGenGlsl as glsl
    import MaterialX.PyMaterialXGenShader as gen

    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    document.importLibrary(library)
    generator = glsl.GlslShaderGenerator.create()
    context = gen.GenContext(generator)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    if colour_managed:
        cms = gen.DefaultColorManagementSystem.create(generator.getTarget())
        cms.loadLibrary(library)
        generator.setColorManagementSystem(cms)
        context.getOptions().targetColorSpaceOverride = "lin_rec709"
    try:
        shader = generator.generate("s", gen.findRenderableElements(document)[0], context)
    except Exception as error:  # noqa: BLE001 - MaterialX's own exception types
        return None, str(error)
    return shader.getSourceCode("pixel"), None


# -- graph nodes' enums: MaterialX's generator is the anchor ------------------------------------------

_IMAGE = """
<image name="albedo" type="color3">
  <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />
  <input name="{input}" type="string" value="{value}" />
</image>
<open_pbr_surface name="S" type="surfaceshader">
  <input name="base_color" type="color3" nodename="albedo" />
</open_pbr_surface>
<surfacematerial name="M" type="material">
  <input name="surfaceshader" type="surfaceshader" nodename="S" />
</surfacematerial>
"""


@pytest.mark.parametrize("input_name, value, allowed", [
    ("uaddressmode", "repeat", False), ("vaddressmode", "wrap", False), ("filtertype", "bilinear", False),
    ("uaddressmode", "periodic", True), ("vaddressmode", "mirror", True), ("filtertype", "cubic", True),
])
def test_an_enum_outside_the_nodedefs_list_is_flagged_exactly_when_materialx_cannot_generate_it(
        tmp_path, input_name, value, allowed):
    path = _mtlx(tmp_path, _IMAGE.format(input=input_name, value=value))
    shutil.copy(BROKEN / "textures" / "albedo.png", tmp_path / "albedo.png")
    _, failure = _glsl(path)
    assert (failure is None) == allowed, failure
    assert ("OPBR303" in _codes(path)) == (not allowed)


# -- colour spaces and UDIM tokens --------------------------------------------------------------------

def test_usd_raw_on_a_float_image_is_no_finding_and_on_a_colour_image_an_error(tmp_path):
    """MaterialX converts colour outputs only (ShaderGraph::populateColorTransformMap returns for other
    types), so USD's 'raw' on ND_image_float asks for what happens; on a colour image MaterialX 1.39.5
    skips the unknown transform with a warning and its main branch refuses to generate (#2954)."""
    stage = (BROKEN / "OPBR1004_usd_raw_in_materialx_image.usda").read_text(encoding="utf-8")
    (tmp_path / "textures").mkdir()
    shutil.copy(BROKEN / "textures" / "albedo.png", tmp_path / "textures" / "albedo.png")
    colour = tmp_path / "colour.usda"
    colour.write_text(stage, encoding="utf-8")
    assert "OPBR1004" in _codes(colour)
    scalar = tmp_path / "scalar.usda"
    scalar.write_text(stage.replace("color3f inputs:emission_color.connect", "float inputs:specular_roughness.connect")
                      .replace("ND_image_color3", "ND_image_float").replace("color3f outputs:out", "float outputs:out"),
                      encoding="utf-8")
    assert _codes(scalar) == {}


def test_a_lower_case_udim_token_names_a_file_that_does_not_exist_with_a_hint(tmp_path):
    """MaterialX (UDIM_TOKEN = "<UDIM>") and OpenUSD (UsdShadeUdimUtils) substitute the token
    case-sensitively: '<udim>' is part of a file name, so the tiles on disk are never found."""
    for tile in ("1001", "1002"):
        shutil.copy(BROKEN / "textures" / "albedo.png", tmp_path / f"albedo.{tile}.png")
    upper = _mtlx(tmp_path, _IMAGE.replace('value="albedo.png"', 'value="albedo.&lt;UDIM&gt;.png"').format(
        input="filtertype", value="linear"), "upper.mtlx")
    lower = _mtlx(tmp_path, _IMAGE.replace('value="albedo.png"', 'value="albedo.&lt;udim&gt;.png"').format(
        input="filtertype", value="linear"), "lower.mtlx")
    assert "OPBR701" not in _codes(upper)
    report = validate_paths([str(lower)], options=Options(use_config=False))
    [missing] = [d for d in report.diagnostics if d.code == "OPBR701"]
    assert "case-sensitive" in missing.hint and "<UDIM>" in missing.hint


# -- defaultgeomprop inputs: MaterialX's renderer is the anchor ----------------------------------------

@pytest.mark.gl
def test_materialx_renders_a_constant_world_normal_as_if_it_were_not_there(tmp_path):
    """Why OPBR205 is an info: ShaderGraph connects the geometric normal to every unconnected input with
    a defaultgeomprop, value or not. MaterialX's own gltf_pbr_default example (normal = (0, 0, 1)) renders
    the same with the value, without it, and with (1, 0, 0)."""
    from glsupport import materialx_renderer

    from openpbr_tools.evaluate.preview import Rig

    renderer = materialx_renderer(Rig())
    source = (PUBLISHED / "materialx/resources/Materials/Examples/GltfPbr/gltf_pbr_default.mtlx").read_text()
    variants = {"as published": source,
                "without": "\n".join(line for line in source.splitlines() if '_normal"' not in line
                                     and 'name="normal"' not in line),
                "(1, 0, 0)": source.replace('name="normal" type="vector3" value="0, 0, 1"',
                                            'name="normal" type="vector3" value="1, 0, 0"')}
    images = {}
    for label, text in variants.items():
        path = tmp_path / f"{len(images)}.mtlx"
        path.write_text(text, encoding="utf-8")
        images[label] = renderer.render_document(path)
    reference = images.pop("as published")
    assert reference.std() > 0.05  # shaded (a constant normal honoured would light the sphere as one flat facet)
    for label, image in images.items():
        assert abs(image - reference).max() < 1e-4, label
    found = validate_paths([str(PUBLISHED / "materialx/resources/Materials/Examples/GltfPbr/gltf_pbr_default.mtlx")],
                           options=Options(use_config=False)).diagnostics
    assert {(d.code, str(d.severity)) for d in found if d.code == "OPBR205"} == {("OPBR205", "info")}


def test_a_custom_nodes_interface_default_with_a_defaultgeomprop_is_not_read_as_a_constant():
    """MaterialX's definition_using_definitions: the nodedef input surface_normal has value (1, 1, 1) and
    defaultgeomprop Nworld; an instance that leaves it unset gets the geometric normal, not (1, 1, 1)."""
    path = PUBLISHED / "materialx/resources/Materials/TestSuite/stdlib/definition/definition_using_definitions.mtlx"
    assert "OPBR205" not in _codes(path, ("error", "warning", "info"))


# -- OpenPBR 1.1.1 --------------------------------------------------------------------------------------

def test_an_hdr_emission_colour_is_legal_in_openpbr_1_1_1_only(tmp_path):
    """v1.1.1's table gives emission_color [0, inf)^3 with no typical range (CHANGELOG #260); v1.1 [0, 1]^3."""
    body = """
    <open_pbr_surface name="S" type="surfaceshader" version="{version}">
      <input name="emission_luminance" type="float" value="500" />
      <input name="emission_color" type="color3" value="2, 0.6, 0.1" />
    </open_pbr_surface>
    """
    assert _codes(_mtlx(tmp_path, body.format(version="1.1.1"), "new.mtlx")) == {}
    assert "OPBR301" in _codes(_mtlx(tmp_path, body.format(version="1.1"), "old.mtlx"))


@pytest.mark.parametrize("thickness, meant", [("4.5e-07", "0.45"), ("0.00045", "0.45"), ("3e-09", None)])
def test_a_film_thinner_than_a_nanometre_is_read_as_metres_or_millimetres(tmp_path, thickness, meant):
    path = _mtlx(tmp_path, f"""
    <open_pbr_surface name="S" type="surfaceshader">
      <input name="thin_film_weight" type="float" value="1" />
      <input name="thin_film_thickness" type="float" value="{thickness}" />
    </open_pbr_surface>
    """)
    [finding] = [d for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics
                 if d.code == "OPBR606"]
    assert (f"did you mean {meant}?" == finding.hint) if meant else "micrometres" in finding.hint
    assert "OPBR606" not in _codes(_mtlx(tmp_path, """
    <open_pbr_surface name="S" type="surfaceshader">
      <input name="thin_film_weight" type="float" value="1" />
      <input name="thin_film_thickness" type="float" value="0.005" />
    </open_pbr_surface>
    """, "five_nm.mtlx"))


def test_a_stale_version_header_is_an_info_and_a_document_the_upgrade_rewrites_a_warning(tmp_path):
    """MaterialX reads OPBR012's file back unchanged but for version; OPBR005's swizzle becomes a constant."""
    assert _codes(BROKEN / "OPBR012_stale_version_header.mtlx", ("error", "warning", "info")).get("OPBR012") == 1
    assert "OPBR005" not in _codes(BROKEN / "OPBR012_stale_version_header.mtlx")
    assert _codes(BROKEN / "OPBR005_materialx_138.mtlx").get("OPBR005") == 1


# -- USD stages that compose MaterialX documents ----------------------------------------------------------

_STAGE = """#usda 1.0
(
    defaultPrim = "Asset"
    metersPerUnit = 1
    upAxis = "Y"
)

def Xform "Asset"
{
    def Mesh "geo" (
        prepend apiSchemas = ["MaterialBindingAPI"]
    )
    {
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 1, 2]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
        rel material:binding = </Asset/M>
    }

    def Material "M" (
        prepend references = @./look.mtlx@</MaterialX/Materials/M>
    )
    {
    }
}
"""


def _look(roughness: str) -> str:
    return ('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
            '  <open_pbr_surface name="S" type="surfaceshader">\n'
            f'    <input name="specular_roughness" type="float" value="{roughness}" />\n  </open_pbr_surface>\n'
            '  <surfacematerial name="M" type="material">\n'
            '    <input name="surfaceshader" type="surfaceshader" nodename="S" />\n  </surfacematerial>\n</materialx>\n')


def test_a_stage_reports_the_findings_of_the_materialx_document_it_references_once(tmp_path):
    (tmp_path / "stage.usda").write_text(_STAGE, encoding="utf-8")
    (tmp_path / "look.mtlx").write_text(_look("0,4"), encoding="utf-8")  # a decimal comma: OPBR202
    alone = validate_paths([str(tmp_path / "stage.usda")], options=Options(use_config=False))
    assert [(Path(d.location.file).name, d.code) for d in alone.diagnostics if str(d.severity) != "info"] == \
        [("look.mtlx", "OPBR202")]  # no OPBR1010 about the binding to the prim whose arc was set aside
    assert alone.exit_code() == 1 and alone.files[0].materials == 1
    assert "OPBR003" not in {d.code for d in alone.diagnostics}
    folder = validate_paths([str(tmp_path)], options=Options(use_config=False))
    assert [d.code for d in folder.diagnostics].count("OPBR202") == 1  # under the document, not twice
    (tmp_path / "look.mtlx").write_text(_look("0.4"), encoding="utf-8")
    assert _codes(tmp_path / "stage.usda") == {}


def test_a_stage_whose_materialx_document_is_missing_cannot_be_opened(tmp_path):
    """As a missing .usda layer: usd-core with the usdMtlx plug-in could not compose it either."""
    (tmp_path / "stage.usda").write_text(_STAGE, encoding="utf-8")
    outcome = CliRunner().invoke(cli, ["validate", str(tmp_path / "stage.usda"), "--no-config"])
    assert outcome.exit_code == 2, outcome.output
    assert "OPBR002" in outcome.output and "look.mtlx" in outcome.output and "Traceback" not in outcome.output


# -- glTF: the Khronos validator and the extension texts -------------------------------------------------

@pytest.mark.parametrize("name, code", [
    ("OPBR1217_texcoord_ubyte_not_normalized.gltf", "MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT"),
    ("OPBR1218_clearcoat_normal_without_tangents.gltf", "MESH_PRIMITIVE_NO_TANGENT_SPACE"),
])
def test_mesh_errors_agree_with_the_khronos_validator(tmp_path, name, code):
    from gltf_support import validate_with_khronos

    messages = validate_with_khronos(BROKEN / name, tmp_path)["issues"]["messages"]
    assert code in {m["code"] for m in messages if m["severity"] == 0}
    document = json.loads((BROKEN / name).read_text(encoding="utf-8"))
    if "1217" in name:
        document["accessors"][1]["normalized"] = True
    else:
        document["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = len(document["accessors"])
        document["accessors"].append({"componentType": 5126, "count": 3, "type": "VEC4"})
    (tmp_path / "textures").mkdir(exist_ok=True)
    for texture in ("albedo.png", "normal.png"):
        shutil.copy(BROKEN / "textures" / texture, tmp_path / "textures" / texture)
    fixed = tmp_path / "fixed.gltf"
    fixed.write_text(json.dumps(document), encoding="utf-8")
    assert code not in {m["code"] for m in validate_with_khronos(fixed, tmp_path)["issues"]["messages"]}
    assert not {"OPBR1217", "OPBR1218"} & set(_codes(fixed))


def test_untextured_anisotropy_needs_a_tangent_space_too_and_strength_zero_does_not(tmp_path):
    """KHR_materials_anisotropy: "A mesh primitive using an anisotropy material MUST have a defined tangent
    space" (the Khronos validator checks only the textured case)."""
    document = json.loads((BROKEN / "OPBR1218_clearcoat_normal_without_tangents.gltf").read_text(encoding="utf-8"))
    document["extensionsUsed"] = ["KHR_materials_anisotropy"]
    for strength, expected in ((0.6, True), (0.0, False)):
        document["materials"] = [{"name": "M", "extensions": {"KHR_materials_anisotropy": {"anisotropyStrength": strength}}}]
        path = tmp_path / f"a{strength}.gltf"
        path.write_text(json.dumps(document), encoding="utf-8")
        assert ("OPBR1218" in _codes(path)) == expected


def test_a_misspelt_extension_name_is_a_warning_and_a_known_one_is_not(tmp_path):
    found = validate_paths([str(BROKEN / "OPBR1216_extension_name_typo.gltf")], options=Options(use_config=False))
    [warning] = [d for d in found.diagnostics if d.code == "OPBR1216"]
    assert "KHR_materials_clearcoat" in warning.message
    document = json.loads((BROKEN / "OPBR1216_extension_name_typo.gltf").read_text(encoding="utf-8"))
    for name in ("KHR_materials_clearcoat", "EXT_texture_webp", "VENDOR_materials_magic", "KHR_materials_coat"):
        document["extensionsUsed"] = [name]
        document["materials"][0]["extensions"] = {name: {}}
        path = tmp_path / "known.gltf"
        path.write_text(json.dumps(document), encoding="utf-8")
        assert "OPBR1216" not in _codes(path), name


def test_bindings_into_a_referenced_materialx_document_are_no_false_alarm():
    """The USD working group's stages bind meshes to materials a referenced .mtlx defines (below the prim
    that holds the arc); usd-core, without usdMtlx, calls every such binding invalid (six OPBR1010 warnings
    on these two published, working stages before)."""
    for stage in ("MaterialXTest/basic.usda", "TextureCoordinateTest/TextureCoordinateTestMaterialX.usda"):
        path = PUBLISHED / "usd/usd-wg/test_assets" / stage
        assert _codes(path) == {}, stage
        assert validate_paths([str(path)], options=Options(use_config=False)).files[0].materials > 0


def test_a_colour_space_only_on_the_interface_input_is_what_materialx_does_not_apply(tmp_path):
    """MaterialX's GLSL generator decodes the sRGB texture when the image's own file input is tagged, and
    not when only the node graph's interface input is: OPBR508 fires exactly then."""
    from openpbr_tools.rules.colorspace import INTERFACE_COLORSPACE

    shutil.copy(BROKEN / "textures" / "albedo.png", tmp_path / "albedo.png")
    for label, text in (("passing", INTERFACE_COLORSPACE.passing), ("failing", INTERFACE_COLORSPACE.failing)):
        path = _mtlx(tmp_path, text + '\n<surfacematerial name="M" type="material">\n'
                     '  <input name="surfaceshader" type="surfaceshader" nodename="S" />\n</surfacematerial>',
                     f"{label}.mtlx")
        assert ("OPBR508" in _codes(path)) == (label == "failing")
        assert _decodes_srgb(path) == (label == "passing")


def _decodes_srgb(path) -> bool:
    source, failure = _glsl(path, colour_managed=True)
    assert failure is None, failure
    return "srgb_texture_to_lin_rec709" in source


def _material_gltf(tmp_path, name: str, material: dict, used=()) -> Path:
    path = tmp_path / f"{name}.gltf"
    document = {"asset": {"version": "2.0"}, "materials": [{"name": "M", **material}]}
    if used:
        document["extensionsUsed"] = list(used)
    path.write_text(json.dumps(document), encoding="utf-8")
    return path


@pytest.mark.parametrize("name, material, used, code", [
    ("alpha_cutoff", {"alphaCutoff": 0.3}, (), "MATERIAL_ALPHA_CUTOFF_INVALID_MODE"),
    ("dispersion", {"extensions": {"KHR_materials_dispersion": {"dispersion": 0.5}}}, ("KHR_materials_dispersion",),
     "KHR_MATERIALS_DISPERSION_NO_VOLUME"),
    ("volume", {"extensions": {"KHR_materials_volume": {"thicknessFactor": 1.0}}}, ("KHR_materials_volume",),
     "KHR_MATERIALS_VOLUME_NO_TRANSMISSION"),
    ("double_sided", {"doubleSided": True, "pbrMetallicRoughness": {"metallicFactor": 0.0}, "extensions": {
        "KHR_materials_volume": {"thicknessFactor": 1.0}, "KHR_materials_transmission": {"transmissionFactor": 1.0}}},
     ("KHR_materials_volume", "KHR_materials_transmission"), "KHR_MATERIALS_VOLUME_DOUBLE_SIDED"),
])
def test_every_material_warning_of_the_khronos_validator_is_a_finding_here(tmp_path, name, material, used, code):
    """Never weaker than the anchor on materials: each of the validator's material-level warnings (ISSUES.md)
    is OPBR1211 here (a material without them: the rule's passing examples, tests/test_rule_examples.py)."""
    from gltf_support import validate_with_khronos

    path = _material_gltf(tmp_path, name, material, used)
    assert code in {m["code"] for m in validate_with_khronos(path, tmp_path)["issues"]["messages"]}
    assert "OPBR1211" in _codes(path)


@pytest.mark.parametrize("value", ["nan", "inf", "-inf"])
def test_a_non_finite_value_is_verified_at_its_default_not_a_crash(tmp_path, value):
    """convert --verify of a NaN roughness (OPBR203) raised IndexError in the evaluator's albedo tables (a NaN
    cast to an integer index): the evaluator takes the default, as the conversion writes none."""
    codes, output = _verify(tmp_path, f"""
      <input name="specular_roughness" type="float" value="{value}" />
      <input name="base_color" type="color3" value="0.6, 0.5, 0.4" />""", "out.gltf")
    assert "OPBR011" not in codes and {"OPBR1108", "OPBR1109"} & set(codes), output  # verified


def _verify(tmp_path, inputs: str, output: str) -> tuple[list[str], str]:
    """``convert --verify`` of one OpenPBR material with ``inputs``: its diagnostics' codes and its output."""
    path = _mtlx(tmp_path, f"""
    <open_pbr_surface name="S" type="surfaceshader">{inputs}
    </open_pbr_surface>
    <surfacematerial name="M" type="material">
      <input name="surfaceshader" type="surfaceshader" nodename="S" />
    </surfacematerial>
    """)
    outcome = CliRunner().invoke(cli, ["convert", str(path), "-o", str(tmp_path / output), "--verify", "--format", "json"])
    return [d["code"] for d in json.loads(outcome.stdout)["diagnostics"]], outcome.output


# -- review of the above: composition corners, hostile sizes --------------------------------------------

_HEAD = '#usda 1.0\n(\n    defaultPrim = "World"\n    metersPerUnit = 1\n    upAxis = "Y"\n)\n'
_BALL = 'def Sphere "Ball" (\n    prepend apiSchemas = ["MaterialBindingAPI"]\n)\n{\n    rel material:binding = <TARGET>\n}\n'


def test_materials_composed_from_a_document_inside_a_variant_or_a_referenced_layer_are_no_false_alarm(tmp_path):
    (tmp_path / "look.mtlx").write_text(_look("0.4"), encoding="utf-8")
    variant = (_HEAD + 'def Xform "World" (\n    variants = {\n        string look = "a"\n    }\n'
               '    prepend variantSets = "look"\n)\n{\n' + textwrap.indent(_BALL.replace("TARGET", "/World/M"), "    ")
               + '    variantSet "look" = {\n        "a" {\n            def Material "M" (\n'
               '                prepend references = @./look.mtlx@</MaterialX/Materials/M>\n            )\n'
               '            {\n            }\n        }\n    }\n}\n')
    (tmp_path / "variant.usda").write_text(variant, encoding="utf-8")
    (tmp_path / "looks.usda").write_text('#usda 1.0\n(\n    defaultPrim = "Looks"\n)\ndef Scope "Looks"\n{\n'
                                         '    def Material "M" (\n        prepend references = @./look.mtlx@'
                                         '</MaterialX/Materials/M>\n    )\n    {\n    }\n}\n', encoding="utf-8")
    (tmp_path / "top.usda").write_text(_HEAD + 'def Xform "World"\n{\n' + textwrap.indent(_BALL.replace("TARGET", "/World/Looks/M"), "    ")
                                       + '    def Scope "Looks" (\n        prepend references = @./looks.usda@\n    )\n'
                                       '    {\n    }\n}\n', encoding="utf-8")
    for stage in ("variant.usda", "top.usda"):
        assert _codes(tmp_path / stage) == {}, stage


def test_a_missing_document_in_a_variant_the_stage_does_not_select_does_not_fail_it(tmp_path):
    """usd-core composes only the selected variant; a missing .usda in another is not fatal either."""
    (tmp_path / "v.usda").write_text(
        _HEAD + 'def Xform "World" (\n    variants = {\n        string look = "a"\n    }\n    prepend variantSets = "look"\n)\n'
        '{\n    variantSet "look" = {\n        "a" {\n            def Scope "Looks" {}\n        }\n        "b" {\n'
        '            def Scope "Looks" (\n                prepend references = @./missing_b.mtlx@</MaterialX>\n'
        '            )\n            {\n            }\n        }\n    }\n}\n', encoding="utf-8")
    report = validate_paths([str(tmp_path / "v.usda")], options=Options(use_config=False))
    assert not report.unreadable and "OPBR002" not in {d.code for d in report.diagnostics}


def test_a_sublayered_document_does_not_hide_a_binding_to_nowhere(tmp_path):
    (tmp_path / "look.mtlx").write_text(_look("0.4"), encoding="utf-8")
    (tmp_path / "typo.usda").write_text(_HEAD.replace('defaultPrim = "World"', 'defaultPrim = "Ball"').replace(
        ')\n', '    subLayers = [@./look.mtlx@]\n)\n', 1) + _BALL.replace("TARGET", "/Nowhere/Typo"), encoding="utf-8")
    assert _codes(tmp_path / "typo.usda") == {"OPBR1017": 1}  # (usd-core's own InvalidResourcePath, OPBR1010, before OPBR1017)


def test_a_document_two_listed_stages_compose_is_reported_once_with_its_materials_counted_once(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "look.mtlx").write_text(_look("0,4"), encoding="utf-8")
    for name in ("a.usda", "b.usda"):
        (tmp_path / name).write_text(_STAGE.replace("./look.mtlx", "./sub/look.mtlx"), encoding="utf-8")
    report = validate_paths([str(tmp_path / "a.usda"), str(tmp_path / "b.usda")], options=Options(use_config=False))
    assert [d.code for d in report.diagnostics].count("OPBR202") == 1
    assert sum(r.materials for r in report.files) == 1  # the one material, in the document both compose
    folder = validate_paths([str(tmp_path)], options=Options(use_config=False))
    assert [d.code for d in folder.diagnostics].count("OPBR202") == 1
    assert sum(r.materials for r in folder.files) == 1


def test_a_stale_header_with_a_udim_path_is_still_recognised_as_unchanged_by_the_upgrade(tmp_path):
    body = _IMAGE.replace('value="albedo.png"', 'value="albedo.<UDIM>.png"').format(input="filtertype", value="linear")
    path = _mtlx(tmp_path, body, version="1.38")
    assert "OPBR012" in _codes(path, ("info",)) and "OPBR005" not in _codes(path)


def test_an_xml_declaration_with_an_unknown_encoding_is_malformed_not_a_crash(tmp_path):
    path = tmp_path / "enc.mtlx"
    path.write_text('<?xml version="1.0" encoding="foo"?>\n<materialx version="1.39"/>\n', encoding="utf-8")
    outcome = CliRunner().invoke(cli, ["validate", str(path), "--no-config"])
    assert outcome.exit_code == 2 and "OPBR002" in outcome.output and "OPBR011" not in outcome.output


def test_thousands_of_unknown_extension_names_are_compared_with_the_registry_a_bounded_number_of_times(tmp_path):
    """Each comparison costs ~2 ms: 20,000 near-misses took 40 s before the cap."""
    from openpbr_tools.rules.gltf import MISSPELLING_CHECKS

    names = [f"KHR_materials_clearcoat{i:05d}"[:-3] + "x" * (i % 2) for i in range(2000)]
    path = tmp_path / "many.gltf"
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "extensionsUsed": names,
                                "materials": [{"name": "M"}]}), encoding="utf-8")
    found = validate_paths([str(path)], options=Options(use_config=False)).diagnostics
    assert 0 < sum(d.code == "OPBR1216" for d in found) <= MISSPELLING_CHECKS


def test_a_colour_where_the_definition_wants_a_float_is_verified_at_the_default_not_a_crash(tmp_path):
    """geometry_opacity written as the color3 of OpenPBR 0.2 on a 1.1.1 shader (OPBR201) made the evaluator
    broadcast a (3,) value against the sphere's points."""
    codes, output = _verify(tmp_path, """
      <input name="transmission_weight" type="float" value="1" />
      <input name="geometry_opacity" type="color3" value="1, 1, 1" />""", "out.mtlx")
    assert "OPBR011" not in codes and {"OPBR1108", "OPBR1109"} & set(codes), output


def test_a_composed_document_is_judged_by_its_own_configuration_overrides(tmp_path):
    """The reviewer's case: an override for **/*.mtlx that ignores OPBR301 applied when the document was
    listed, not when the stage composing it was (it took the stage's settings)."""
    for folder, configured in (("plain", False), ("configured", True)):
        (tmp_path / folder / "sub").mkdir(parents=True)
        (tmp_path / folder / "sub" / "look.mtlx").write_text(_look("1.5"), encoding="utf-8")  # roughness 1.5: OPBR301
        (tmp_path / folder / "stage.usda").write_text(_STAGE.replace("./look.mtlx", "./sub/look.mtlx"), encoding="utf-8")
        if configured:
            (tmp_path / folder / ".openpbr.toml").write_text(
                '[[overrides]]\npaths = ["**/*.mtlx"]\nignore = ["OPBR301"]\n', encoding="utf-8")
        for listed in ("stage.usda", "sub/look.mtlx"):
            found = {d.code for d in validate_paths([str(tmp_path / folder / listed)]).diagnostics}
            assert ("OPBR301" in found) != configured, (folder, listed)


def test_under_shards_a_listed_document_is_reported_by_its_own_shard_only(tmp_path):
    """A stage and the .mtlx it composes, both in the folder: whichever shards they land in, the document's
    finding is reported once over all the shards (by the document's own)."""
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "look.mtlx").write_text(_look("0,4"), encoding="utf-8")
    for index in range(6):  # enough stages that some land in the other shard than the document
        (tmp_path / f"stage{index}.usda").write_text(_STAGE.replace("./look.mtlx", "./sub/look.mtlx"), encoding="utf-8")
    found = []
    for shard_index in (1, 2):
        report = validate_paths([str(tmp_path)], options=Options(use_config=False, shard=(shard_index, 2)))
        found += [d.code for d in report.diagnostics]
    assert found.count("OPBR202") == 1
