"""Session 23's red team, set U: one realistic defect in a real published asset (and the unmodified assets as
controls). Four misses and one false alarm, each against its authority:

* m03: a GPUOpen material's normal map swapped for its one-channel height map, read through a node graph whose
  texture coordinates are tiled by a multiply (so no input reads it as a texture): OPBR709 never saw it. The
  image's channel count is Pillow's; MaterialX's normalmap decodes three channels.
* u12: a UsdPreviewSurface diffuseColor authored float3: usd-core's ShaderSdrCompliance reports
  MismatchedPropertyType (an error there); it was dropped as covered by OPBR1002, which allows a preview's role.
* u18: a UsdTransform2d rotation of 0.3927 (22.5 degrees in radians, where the node takes degrees): OPBR719 knew
  only multiples of 15 degrees.
* uc12 (false alarm): usd-wg's intent-vfx teapot authors specularColor (1, 1, 1) in the metalness workflow, which
  renders nothing: OPBR1035 (info) now, OPBR1008's warning kept for a metallic the specular workflow ignores
  (tests/test_usd_rules.py).
"""

from __future__ import annotations

from PIL import Image

from redteam_support import findings, messages, mtlx, report

_GRAPH = '''
    <nodegraph name="NG">
      <texcoord name="uv" type="vector2" />
      <multiply name="tiled" type="vector2">
        <input name="in1" type="vector2" nodename="uv" />
        <input name="in2" type="float" value="2" />
      </multiply>
      <image name="normal_image" type="vector3">
        <input name="file" type="filename" value="{file}" />
        <input name="texcoord" type="vector2" nodename="tiled" />
      </image>
      <normalmap name="decode" type="vector3">
        <input name="in" type="vector3" nodename="normal_image" />
      </normalmap>
      <output name="normal_output" type="vector3" nodename="decode" />
    </nodegraph>
    <standard_surface name="S" type="surfaceshader">
      <input name="normal" type="vector3" nodegraph="NG" output="normal_output" />
    </standard_surface>
    <surfacematerial name="M" type="material">
      <input name="surfaceshader" type="surfaceshader" nodename="S" />
    </surfacematerial>
'''


def test_a_height_map_decoded_as_normals_inside_a_graph_is_found(tmp_path):
    Image.new("L", (8, 8), 128).save(tmp_path / "height.png")
    Image.new("RGB", (8, 8), (128, 128, 255)).save(tmp_path / "normal.png")
    assert Image.open(tmp_path / "height.png").getbands() == ("L",)  # one channel: x = y = z for every texel
    broken = mtlx(tmp_path, _GRAPH.format(file="height.png"), name="broken.mtlx")
    (code, severity, path, input_name), = [f for f in findings(broken) if f[0] == "OPBR709"]
    assert severity == "warning" and path == "NG/normal_image" and input_name == "file"
    assert "NG/decode decodes 'height.png'" in messages(broken, "OPBR709")[0]
    good = mtlx(tmp_path, _GRAPH.format(file="normal.png"), name="good.mtlx")
    assert not [f for f in findings(good) if f[0] == "OPBR709"]


_PREVIEW = '''#usda 1.0
(
    defaultPrim = "M"
    metersPerUnit = 1
    upAxis = "Y"
)
def Material "M"
{{
    token outputs:surface.connect = </M/S.outputs:surface>
    def Shader "S"
    {{
        uniform token info:id = "UsdPreviewSurface"
        {diffuse}
        token outputs:surface
    }}
}}
'''


def test_a_float3_preview_colour_keeps_usd_cores_finding(tmp_path):
    from pxr import Usd, UsdValidation

    path = tmp_path / "float3.usda"
    path.write_text(_PREVIEW.format(diffuse="float3 inputs:diffuseColor = (0.8, 0.2, 0.1)"), encoding="utf-8")
    passed = [d for d in report(path).diagnostics if d.code == "OPBR1010"]
    assert len(passed) == 1 and "MismatchedPropertyType" in passed[0].message
    assert str(passed[0].severity) == "warning" and passed[0].location.input == "diffuseColor"
    stage = Usd.Stage.Open(str(path))  # the anchor: usd-core's own validator on the same stage
    validator = UsdValidation.ValidationRegistry().GetOrLoadValidatorByName("usdShadeValidators:ShaderSdrCompliance")
    errors = [e for prim in stage.Traverse() for e in validator.Validate(prim)]
    assert any(e.GetName() == "MismatchedPropertyType" for e in errors)
    good = tmp_path / "color3f.usda"
    good.write_text(_PREVIEW.format(diffuse="color3f inputs:diffuseColor = (0.8, 0.2, 0.1)"), encoding="utf-8")
    assert not [d for d in report(good).diagnostics if d.code == "OPBR1010"]


_ROTATED = '''#usda 1.0
(
    metersPerUnit = 1
    upAxis = "Y"
)
def Material "M"
{{
    token outputs:surface.connect = </M/S.outputs:surface>
    def Shader "S"
    {{
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor.connect = </M/T.outputs:rgb>
        token outputs:surface
    }}
    def Shader "T"
    {{
        uniform token info:id = "UsdUVTexture"
        asset inputs:file = @albedo.png@
        float2 inputs:st.connect = </M/R.outputs:result>
        float3 outputs:rgb
    }}
    def Shader "R"
    {{
        uniform token info:id = "UsdTransform2d"
        float inputs:rotation = {rotation}
        float2 outputs:result
    }}
}}
'''


def test_a_transform2d_rotation_of_22_5_degrees_in_radians_is_found(tmp_path):
    import math

    Image.new("RGB", (4, 4), (200, 120, 40)).save(tmp_path / "albedo.png")
    for rotation, expected in ((round(math.pi / 8, 4), True), (22.5, False), (0.5, False)):
        path = tmp_path / f"rotated_{rotation}.usda"
        path.write_text(_ROTATED.format(rotation=rotation), encoding="utf-8")
        found = messages(path, "OPBR719")
        assert bool(found) is expected, rotation
        if expected:
            assert "22.5 degrees written in radians" in found[0]
