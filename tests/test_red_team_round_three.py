"""The third red-team round (session 17: files written without reading this code), each finding proven
against the anchor that decides it: MaterialX's string resolver and GLSL generator, usd-core's asset
resolution inside a USDZ, the OpenUSD and glTF specifications."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest
from PIL import Image

from openpbr_tools.validate import Options, validate_paths


def _codes(path, severities=("error", "warning")) -> dict[str, int]:
    report = validate_paths([str(path)], options=Options(use_config=False))
    found: dict[str, int] = {}
    for d in report.diagnostics:
        if str(d.severity) in severities:
            found[d.code] = found.get(d.code, 0) + 1
    return found


def _messages(path, code: str) -> list[str]:
    report = validate_paths([str(path)], options=Options(use_config=False))
    return [d.message for d in report.diagnostics if d.code == code]


def _mtlx(tmp_path, body: str, name: str = "m.mtlx") -> Path:
    path = tmp_path / name
    path.write_text('<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
                    + textwrap.indent(textwrap.dedent(body).strip("\n"), "  ") + "\n</materialx>\n", encoding="utf-8")
    return path


def _png(path: Path, mode: str = "RGB", size=(4, 4), colour=(200, 120, 40)) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    Image.new(mode, size, colour if mode != "RGBA" else colour + (128,)).save(path)
    return path


def _materialx_document(path):
    import MaterialX as mx

    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    document.importLibrary(library)
    return document


def _generates(path) -> bool:
    import MaterialX.PyMaterialXGenGlsl as glsl
    import MaterialX.PyMaterialXGenShader as gen
    import MaterialX as mx

    document = _materialx_document(path)
    generator = glsl.GlslShaderGenerator.create()
    context = gen.GenContext(generator)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    generator.generate("s", gen.findRenderableElements(document)[0], context)
    return True


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
    assert _materialx_document(path).validate()[0] and _generates(path)  # the anchor: a valid, renderable graph
    assert _codes(path) == {}
    for output in ("out.mtlx", "out.usda"):
        convert_file(str(path), str(tmp_path / output), "open_pbr_surface", Settings())
        assert _codes(tmp_path / output) == {}, output
    written = tmp_path / "out.mtlx"
    assert _materialx_document(written).validate()[0] and _generates(written)
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
