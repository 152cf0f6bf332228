"""Ambient occlusion between glTF and UsdPreviewSurface (translate/past_hub.py): both models hold it (glTF 2.0
3.9.4 occlusionTexture, read from red as 1 + strength (r - 1); UsdPreviewSurface's occlusion, 1 = none),
OpenPBR does not, and a conversion through the OpenPBR hub used to drop it with an OPBR1104 error although
the output could hold it. Expected values are the two specifications' formulas, read back with usd-core,
the JSON and MaterialX's own reader; glTF outputs are also checked by the Khronos glTF-Validator."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from pxr import Usd, UsdShade

from gltf_support import validate_with_khronos
from openpbr_tools.convert import convert_file

PUBLISHED = Path(__file__).parent / "data" / "published" / "gltf_samples" / "CompareAmbientOcclusion"

_USD = """#usda 1.0
(
    defaultPrim = "Asset"
    metersPerUnit = 1
)
def Xform "Asset"
{
    def Scope "Looks"
    {
        def Material "M"
        {
            token outputs:surface.connect = </Asset/Looks/M/P.outputs:surface>
            def Shader "P"
            {
                uniform token info:id = "UsdPreviewSurface"
                color3f inputs:diffuseColor = (0.6, 0.5, 0.4)
                float inputs:occlusion.connect = </Asset/Looks/M/AO.outputs:r>
                token outputs:surface
            }
            def Shader "AO"
            {
                uniform token info:id = "UsdUVTexture"
                asset inputs:file = @ao.jpg@
                token inputs:sourceColorSpace = "raw"
                float4 inputs:scale = (SCALE, SCALE, SCALE, 1)
                float4 inputs:bias = (BIAS, BIAS, BIAS, 0)
                float2 inputs:st.connect = </Asset/Looks/M/uv.outputs:result>
                float outputs:r
            }
            def Shader "uv"
            {
                uniform token info:id = "UsdPrimvarReader_float2"
                string inputs:varname = "st"
                float2 outputs:result
            }
        }
    }
}
"""


def _notes(conversion, code):
    return [d for d in conversion.diagnostics if d.code == code and "occlusion" in d.message]


def _copy_published(tmp_path: Path, strength: float | None = None) -> Path:
    for name in ("CompareAmbientOcclusion.gltf", "CompareAmbientOcclusion.bin", "BasketORM.jpg", "BasketBaseColor.jpg",
                 "BasketNormal.png", "FruitORM.jpg", "FruitBaseColor.jpg", "FruitNormal.png"):
        if (PUBLISHED / name).exists():
            shutil.copy(PUBLISHED / name, tmp_path / name)
    path = tmp_path / "CompareAmbientOcclusion.gltf"
    if strength is not None:
        document = json.loads(path.read_text())
        document["materials"][0]["occlusionTexture"]["strength"] = strength
        path.write_text(json.dumps(document))
    return path


def _preview_occlusion(usda: Path, material: str):
    stage = Usd.Stage.Open(str(usda))
    preview = next(UsdShade.Shader(p) for p in stage.Traverse()
                   if p.GetName() == f"{material}_preview" and p.IsA(UsdShade.Shader))
    source, output, _ = preview.GetInput("occlusion").GetConnectedSource()
    return UsdShade.Shader(source.GetPrim()), output, stage  # the stage must outlive its prims


def test_gltf_occlusion_texture_reaches_the_usd_preview_fallback(tmp_path):
    """Khronos' CompareAmbientOcclusion (strength 1): the preview reads BasketORM.jpg's red channel with the
    identity scale and bias (1 + 1 (r - 1) = r); the OpenPBR shader cannot, which the note says."""
    conversion = convert_file(str(_copy_published(tmp_path)), str(tmp_path / "out" / "out.usda"))
    texture, output, _stage = _preview_occlusion(tmp_path / "out" / "out.usda", "Basket_with_Occlusion")
    assert output == "r"
    assert texture.GetInput("file").Get().path.endswith("BasketORM.jpg")
    assert texture.GetInput("sourceColorSpace").Get() == "raw"
    for name, expected in (("scale", 1.0), ("bias", 0.0)):
        value = texture.GetInput(name).Get() if texture.GetInput(name) else None
        assert value is None or abs(value[0] - expected) < 1e-6, (name, value)
    assert not _notes(conversion, "OPBR1104")
    fallback_only = _notes(conversion, "OPBR1103")
    assert {d.location.path for d in fallback_only} == {"/materials/0", "/materials/1"}
    assert all("fallback only" in d.message for d in fallback_only)


def test_gltf_occlusion_strength_becomes_the_preview_scale_and_bias(tmp_path):
    """strength 0.25: glTF's 1 + 0.25 (r - 1) = 0.25 r + 0.75, i.e. UsdUVTexture scale 0.25 and bias 0.75."""
    convert_file(str(_copy_published(tmp_path, strength=0.25)), str(tmp_path / "out" / "out.usda"))
    texture, _, _stage = _preview_occlusion(tmp_path / "out" / "out.usda", "Basket_with_Occlusion")
    assert abs(texture.GetInput("scale").Get()[0] - 0.25) < 1e-6
    assert abs(texture.GetInput("bias").Get()[0] - 0.75) < 1e-6


def test_gltf_occlusion_is_still_reported_lost_on_an_openpbr_output(tmp_path):
    conversion = convert_file(str(_copy_published(tmp_path)), str(tmp_path / "out" / "out.mtlx"))
    assert {d.location.path for d in _notes(conversion, "OPBR1104")} == {"/materials/0", "/materials/1"}
    assert "occlusion" not in (tmp_path / "out" / "out.mtlx").read_text()


def _usd_source(tmp_path: Path, scale: float, bias: float) -> Path:
    shutil.copy(PUBLISHED / "BasketORM.jpg", tmp_path / "ao.jpg")
    path = tmp_path / "preview.usda"
    path.write_text(_USD.replace("SCALE", repr(scale)).replace("BIAS", repr(bias)))
    return path


def test_usd_preview_occlusion_becomes_a_gltf_occlusion_texture(tmp_path):
    """The identity scale and bias is glTF's strength 1 (the default, not written); the Khronos validator
    accepts the file; no loss is reported for occlusion."""
    conversion = convert_file(str(_usd_source(tmp_path, 1.0, 0.0)), str(tmp_path / "out" / "out.gltf"))
    document = json.loads((tmp_path / "out" / "out.gltf").read_text())
    occlusion = document["materials"][0]["occlusionTexture"]
    assert occlusion.get("strength", 1.0) == 1.0
    image = document["images"][document["textures"][occlusion["index"]]["source"]]
    assert image["uri"].endswith("ao.jpg")
    assert not _notes(conversion, "OPBR1104") and not _notes(conversion, "OPBR1103")
    report = validate_with_khronos(tmp_path / "out" / "out.gltf", tmp_path)
    assert report["issues"]["numErrors"] == 0


def test_usd_preview_occlusion_in_gltf_strength_form_keeps_its_strength(tmp_path):
    """scale 0.5, bias 0.5 is 1 + 0.5 (r - 1): glTF strength 0.5, exactly."""
    conversion = convert_file(str(_usd_source(tmp_path, 0.5, 0.5)), str(tmp_path / "out" / "out.gltf"))
    occlusion = json.loads((tmp_path / "out" / "out.gltf").read_text())["materials"][0]["occlusionTexture"]
    assert abs(occlusion["strength"] - 0.5) < 1e-6
    assert not _notes(conversion, "OPBR1104")


def test_usd_preview_occlusion_into_materialx_gltf_pbr_loads_in_materialx(tmp_path):
    import MaterialX as mx

    conversion = convert_file(str(_usd_source(tmp_path, 1.0, 0.0)), str(tmp_path / "out" / "out.mtlx"), "gltf_pbr")
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(tmp_path / "out" / "out.mtlx"))
    assert document.validate()[0]
    shader = next(n for n in document.getNodes() if n.getCategory() == "gltf_pbr")
    assert shader.getInput("occlusion").getConnectedNode() is not None
    assert not _notes(conversion, "OPBR1104")
