"""The sixth red-team round (session 19, set G: files written without reading this code), MaterialX and USD; the
glTF findings are tests/test_red_team_gltf_round_six.py. Each finding is proven against the anchor that decides
it: MaterialX's reader and GLSL generator, usd-core, the Khronos glTF-Validator, or the specification's text."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from PIL import Image

from openpbr_tools.validate import validate_file


def _codes(path: Path) -> dict[str, str]:
    return {d.code: str(d.severity) for d in validate_file(str(path)).diagnostics}


def _flagged(path: Path) -> set[str]:
    return {d.code for d in validate_file(str(path)).diagnostics if str(d.severity) in ("warning", "error")}


# -- false alarms -------------------------------------------------------------------------------------------------

_ALBEDO = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="{document}">
  <image name="bc" type="color3">
    <input name="file" type="filename" value="albedo.png" colorspace="{texture}" />
  </image>
  <open_pbr_surface name="SR" type="surfaceshader">
    <input name="base_color" type="color3" nodename="bc" />
    <input name="coat_color" type="color3" value="0.9, 0.5, 0.2" />
  </open_pbr_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR" />
  </surfacematerial>
</materialx>
"""


def _transforms(code: str) -> set[str]:
    return set(re.findall(r"NG_(\w+?)_to_lin_rec709", code))


def test_colour_space_names_materialx_remaps_itself_are_known(tmp_path):
    """mg07: a document in 'lin_ap1' was an unknown colour space (OPBR502 error). MaterialX 1.39.5's colour
    management (the anchor) maps it, the legacy gamma names and the ASWF colour-interop names to cmlib names
    itself: the generated GLSL calls the same transform as for the cmlib name. The table
    (schemas/colorspaces.json materialx_remapped) is checked name by name against that behaviour."""
    import MaterialX as mx
    import MaterialX.PyMaterialXGenShader as gs

    from glsupport import shader_generator
    from openpbr_tools.resources import load_json

    Image.new("RGB", (2, 2), (120, 80, 40)).save(tmp_path / "albedo.png")
    library, generator, context = shader_generator()
    colour_management = gs.DefaultColorManagementSystem.create(generator.getTarget())
    colour_management.loadLibrary(library)
    generator.setColorManagementSystem(colour_management)
    remapped = {k: v for k, v in load_json("colorspaces.json")["materialx_remapped"].items() if not k.startswith("_")}
    assert {"lin_ap1", "gamma22", "lin_p3d65_scene"} <= set(remapped)

    def generated(document_space, texture_space):
        path = tmp_path / "doc.mtlx"
        path.write_text(_ALBEDO.format(document=document_space, texture=texture_space))
        document = mx.createDocument()
        mx.readFromXmlFile(document, str(path))
        document.setDataLibrary(library)
        code = generator.generate("M", document.getMaterialNodes()[0], context).getSourceCode(gs.PIXEL_STAGE)
        return path, code

    for alias, name in remapped.items():
        path, code = generated(alias, alias)
        _, reference = generated(name, name)
        assert _transforms(code) == _transforms(reference), alias
        assert not {"OPBR502", "OPBR004"} & _flagged(path), alias


def test_a_scene_linear_exr_read_raw_as_a_colour_is_no_finding(tmp_path):
    """ug05: an OpenEXR base colour read with sourceColorSpace 'raw' is right (scene-linear values need no transform;
    UsdPreviewSurface spec: raw means none); an 8-bit PNG read raw as a colour is still OPBR503."""
    import OpenImageIO as oiio

    buffer = oiio.ImageBuf(oiio.ImageSpec(2, 2, 3, oiio.HALF))
    oiio.ImageBufAlgo.fill(buffer, (0.5, 0.25, 0.125))
    assert buffer.write(str(tmp_path / "albedo.exr"))
    Image.new("RGB", (2, 2), (120, 80, 40)).save(tmp_path / "albedo.png")
    stage = """#usda 1.0
(
    defaultPrim = "M"
    metersPerUnit = 1
    upAxis = "Y"
)
def Material "M"
{
    token outputs:surface.connect = </M/P.outputs:surface>
    def Shader "P"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor.connect = </M/T.outputs:rgb>
        token outputs:surface
    }
    def Shader "T"
    {
        uniform token info:id = "UsdUVTexture"
        asset inputs:file = @FILE@
        token inputs:sourceColorSpace = "raw"
        float2 inputs:st.connect = </M/uv.outputs:result>
        float3 outputs:rgb
    }
    def Shader "uv"
    {
        uniform token info:id = "UsdPrimvarReader_float2"
        string inputs:varname = "st"
        float2 outputs:result
    }
}
"""
    for file, expected in (("albedo.exr", None), ("albedo.png", "warning")):
        path = tmp_path / f"{file}.usda"
        path.write_text(stage.replace("FILE", file))
        assert _codes(path).get("OPBR503") == expected


@pytest.mark.parametrize("uri, expected", [("textures/v002/../albedo.png", None), ("../albedo.png", "warning")])
def test_a_dotdot_that_comes_back_inside_the_folder_is_no_path_outside(tmp_path, uri, expected):
    """gg06: 'textures/v002/../albedo.png' names textures/albedo.png, inside the asset's folder (the Khronos
    validator is silent); a '..' that leaves the folder is still OPBR704."""
    (tmp_path / "asset" / "textures" / "v002").mkdir(parents=True)
    Image.new("RGB", (2, 2), (120, 80, 40)).save(tmp_path / "asset" / "textures" / "albedo.png")
    Image.new("RGB", (2, 2), (120, 80, 40)).save(tmp_path / "albedo.png")
    uri = uri if expected is None else uri
    document = {"asset": {"version": "2.0"}, "images": [{"uri": uri}], "textures": [{"source": 0}],
                "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]}
    path = tmp_path / "asset" / "m.gltf"
    path.write_text(json.dumps(document))
    assert _codes(path).get("OPBR704") == expected
