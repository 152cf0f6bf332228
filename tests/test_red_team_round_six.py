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


# -- USD -----------------------------------------------------------------------------------------------------------

_STAGE = """#usda 1.0
(
    defaultPrim = "Asset"
    metersPerUnit = 1
    upAxis = "Y"
)
def Xform "Asset" VARIANTS
{
    LOOKS
    def Mesh "Board" (
        prepend apiSchemas = ["MaterialBindingAPI"]
    )
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-0.5, 0, -0.5), (0.5, 0, -0.5), (0.5, 0, 0.5), (-0.5, 0, 0.5)]
        texCoord2f[] primvars:st = ST
        BINDING
    }
}
"""
_MATERIAL = """def Material "M"
        {
            token outputs:surface.connect = </Asset/Looks/M/P.outputs:surface>
            def Shader "P"
            {
                uniform token info:id = "UsdPreviewSurface"
                color3f inputs:diffuseColor.connect = </Asset/Looks/M/tex.outputs:rgb>
                token outputs:surface
            }
            def Shader "tex"
            {
                uniform token info:id = "UsdUVTexture"
                asset inputs:file = @albedo.png@
                token inputs:sourceColorSpace = "sRGB"
                TEXTURE
                float2 inputs:st.connect = </Asset/Looks/M/uv.outputs:result>
                float3 outputs:rgb
            }
            def Shader "uv"
            {
                uniform token info:id = "UsdPrimvarReader_float2"
                string inputs:varname = "st"
                float2 outputs:result
            }
        }"""
_VERTEX_ST = '[(0, 0), (1, 0), (1, 1), (0, 1)] (interpolation = "vertex")'


def _usd(tmp_path: Path, looks=None, st=_VERTEX_ST, binding="rel material:binding = </Asset/Looks/M>", variants="",
         texture="", name="stage.usda") -> Path:
    Image.frombytes("RGB", (2, 2), bytes([200, 10, 10, 10, 200, 10, 10, 10, 200, 200, 200, 10])).save(tmp_path / "albedo.png")
    looks = looks if looks is not None else 'def Scope "Looks"\n    {\n        ' + _MATERIAL.replace("TEXTURE", texture) + "\n    }"
    path = tmp_path / name
    path.write_text(_STAGE.replace("VARIANTS", variants).replace("LOOKS", looks).replace("ST", st)
                    .replace("BINDING", binding))
    return path


def test_a_binding_to_a_material_under_a_class_is_an_invalid_target(tmp_path):
    """ub12: the Material sits under a 'class' scope: abstract (usd-core's IsAbstract), so stage traversal and the
    renderers never visit it, though ComputeBoundMaterial resolves the binding."""
    from pxr import Usd, UsdShade

    looks = 'class Scope "Looks"\n    {\n        ' + _MATERIAL.replace("TEXTURE", "") + "\n    }"
    path = _usd(tmp_path, looks=looks)
    stage = Usd.Stage.Open(str(path))
    assert stage.GetPrimAtPath("/Asset/Looks/M").IsAbstract()
    assert "/Asset/Looks/M" not in {str(p.GetPath()) for p in stage.Traverse()}
    assert UsdShade.MaterialBindingAPI(stage.GetPrimAtPath("/Asset/Board")).ComputeBoundMaterial()[0]
    assert _codes(path).get("OPBR1017") == "error"
    assert "OPBR1017" not in _codes(_usd(tmp_path, name="defined.usda"))


@pytest.mark.parametrize("selection, expected", [("Oiled", "error"), ("oiled", None)])
def test_a_variant_selection_that_names_no_variant(tmp_path, selection, expected):
    """ub08: the selection 'Oiled' against the variant 'oiled' (names are case-sensitive): usd-core composes none
    of the set's variants, so the binding the variant holds is never made."""
    from pxr import Usd, UsdShade

    variants = ('(\n    variants = {\n        string finish = "' + selection + '"\n    }\n    prepend variantSets = "finish"\n)')
    looks = ('def Scope "Looks"\n    {\n        ' + _MATERIAL.replace("TEXTURE", "") + '\n    }\n    variantSet "finish" = {\n'
             '        "oiled" {\n            over "Board" (\n                prepend apiSchemas = ["MaterialBindingAPI"]\n'
             '            )\n            {\n                rel material:binding = </Asset/Looks/M>\n            }\n        }\n'
             '        "painted" {\n        }\n    }')
    path = _usd(tmp_path, looks=looks, binding="", variants=variants)
    stage = Usd.Stage.Open(str(path))
    bound = UsdShade.MaterialBindingAPI(stage.GetPrimAtPath("/Asset/Board")).ComputeBoundMaterial()[0]
    assert bool(bound) == (expected is None)
    assert _codes(path).get("OPBR802") == expected


def test_a_missing_value_clip_layer(tmp_path):
    """ub09: the clip layer a value clip names was not published; usd-core's MissingReferenceValidator reports it."""
    (tmp_path / "clips").mkdir()
    (tmp_path / "clips" / "manifest.usda").write_text('#usda 1.0\nover "Asset"\n{\n    double size\n}\n')
    clips = ('(\n    clips = {\n        dictionary default = {\n            double2[] active = [(0, 0)]\n'
             '            asset[] assetPaths = [@./clips/wet.0001.usda@]\n'
             '            asset manifestAssetPath = @./clips/manifest.usda@\n            string primPath = "/Asset"\n'
             '            double2[] times = [(0, 0)]\n        }\n    }\n)')
    path = _usd(tmp_path, variants=clips)
    assert _codes(path).get("OPBR802") == "error"
    (tmp_path / "clips" / "wet.0001.usda").write_text('#usda 1.0\nover "Asset"\n{\n    double size = 1\n}\n')
    assert "OPBR802" not in _codes(path)


def test_a_specializes_cycle_is_a_composition_error(tmp_path):
    """ub15: two materials specialize each other; usd-core's composition (the anchor) reports 'Cycle detected', an
    error of its CompositionErrorTest validator, which is an error here too (it was an OPBR1010 warning)."""
    from pxr import Usd

    looks = ('def Scope "Looks"\n    {\n        def Material "A" (\n            specializes = </Asset/Looks/B>\n        )\n'
             '        {\n        }\n        def Material "B" (\n            specializes = </Asset/Looks/A>\n        )\n        {\n'
             '        }\n        ' + _MATERIAL.replace("TEXTURE", "") + "\n    }")
    path = _usd(tmp_path, looks=looks)
    assert any("Cycle" in str(e) for e in Usd.Stage.Open(str(path)).GetCompositionErrors())
    assert _codes(path).get("OPBR002") == "error"


def test_a_uniform_uv_primvar_gives_one_texel_per_face(tmp_path):
    """ub11: st authored with uniform interpolation holds one UV per face (UsdGeomPrimvar), so a texture shows one
    flat texel on each face."""
    uniform = '[(0.5, 0.5)] (interpolation = "uniform")'
    assert _codes(_usd(tmp_path, st=uniform)).get("OPBR1015") == "error"
    assert "OPBR1015" not in _codes(_usd(tmp_path, name="vertex.usda"))


@pytest.mark.parametrize("texture, expected", [("float4 inputs:scale = (4, 4, 4, 1)", "warning"),
                                                ("float4 inputs:scale = (0.8, 0.8, 0.8, 1)", None)])
def test_a_uv_tiling_written_into_a_colour_textures_scale(tmp_path, texture, expected):
    """ub01: UsdUVTexture's scale multiplies texel values (UsdPreviewSurface spec), so (4, 4, 4, 1) meant as a
    tiling makes the albedo four times as bright."""
    assert _codes(_usd(tmp_path, texture=texture)).get("OPBR1028") == expected


def test_usdz_entries_not_aligned_to_64_bytes(tmp_path):
    """ub07: usd-core's package validators (the anchor) call an entry whose data does not start at a multiple of 64
    bytes an error (ByteMisalignment): now OPBR1012, an error too. The rule's own example package is aligned."""
    import zipfile

    from openpbr_tools.io.usd.validators import usd_core_findings
    from openpbr_tools.rules.usd import PACKAGE_ENTRY
    from pxr import Usd

    layer = _usd(tmp_path).read_text()
    path = tmp_path / "unaligned.usdz"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_STORED) as package:
        package.writestr("a.usda", layer)
        package.writestr("albedo.png", (tmp_path / "albedo.png").read_bytes())
    assert any(f["name"] == "ByteMisalignment" and f["severity"] == "error"
               for f in usd_core_findings(Usd.Stage.Open(str(path))))
    assert _codes(path).get("OPBR1012") == "error"
    aligned = tmp_path / "aligned.usdz"
    aligned.write_bytes(PACKAGE_ENTRY.passing)
    assert not any(f["name"] == "ByteMisalignment" for f in usd_core_findings(Usd.Stage.Open(str(aligned))))


# -- MaterialX -----------------------------------------------------------------------------------------------------

_DOC = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="{space}">
{body}
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
"""


def _mtlx(tmp_path: Path, body: str, name: str = "doc.mtlx", space: str = "lin_rec709") -> Path:
    for file in ("albedo.png", "oak_MaskMap.png", "normal.png"):
        if not (tmp_path / file).exists():
            Image.new("RGBA" if "Mask" in file else "RGB", (2, 2), (200, 120, 40, 200)[:4 if "Mask" in file else 3]).save(tmp_path / file)
    path = tmp_path / name
    path.write_text(_DOC.format(space=space, body=body))
    return path


def _glsl(path: Path) -> str:
    import MaterialX as mx
    import MaterialX.PyMaterialXGenGlsl as gg
    import MaterialX.PyMaterialXGenShader as gs

    from glsupport import shader_generator

    library, _, _ = shader_generator()  # (its library; a generator of this test's own: the shared one is left as it is)
    generator = gg.GlslShaderGenerator.create()
    context = gs.GenContext(generator)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    colour_management = gs.DefaultColorManagementSystem.create(generator.getTarget())
    colour_management.loadLibrary(library)
    generator.setColorManagementSystem(colour_management)
    context.registerSourceCodeSearchPath(mx.FileSearchPath(str(path.parent)))
    context.getOptions().targetColorSpaceOverride = "lin_rec709"  # the renderer's working space
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    document.setDataLibrary(library)
    return generator.generate("M", document.getMaterialNodes()[0], context).getSourceCode(gs.PIXEL_STAGE)


def _shader(input_name: str, input_type: str, node: str, extra: str = "") -> str:
    return (f'  <open_pbr_surface name="S" type="surfaceshader">\n    <input name="{input_name}" type="{input_type}" '
            f'nodename="{node}"{extra} />\n  </open_pbr_surface>')


@pytest.mark.parametrize("image_type, expected", [("color3", "error"), ("color4", None)])
def test_an_extract_past_its_inputs_channels(tmp_path, image_type, expected):
    """mb03: extract index 3 of a color3 (a mask map's alpha read as three channels). MaterialX's validate() accepts
    it (so the anchor cannot be relied on here); ND_extract_color3 defines index 0 to 2."""
    import MaterialX as mx

    body = (f'  <image name="mask" type="{image_type}">\n    <input name="file" type="filename" value="oak_MaskMap.png" />\n'
            f'  </image>\n  <extract name="smooth" type="float">\n    <input name="in" type="{image_type}" nodename="mask" />\n'
            '    <input name="index" type="integer" value="3" />\n  </extract>\n' + _shader("specular_roughness", "float", "smooth"))
    path = _mtlx(tmp_path, body)
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    assert library.getNodeDef("ND_extract_color3").getInput("index").getAttribute("uimax") == "2"
    assert _codes(path).get("OPBR807") == expected


def test_a_custom_nodes_missing_glsl_source(tmp_path):
    """mb04: MaterialX's shader generation (the anchor) fails on a custom node whose genglsl source is not there,
    and generates once it is."""
    body = ('  <nodedef name="ND_grime_color3" node="grime">\n    <input name="base" type="color3" value="0.5, 0.5, 0.5" />\n'
            '    <output name="out" type="color3" />\n  </nodedef>\n  <implementation name="IM_grime_color3_genglsl" '
            'nodedef="ND_grime_color3" file="grime.glsl" function="grime_color3" target="genglsl" />\n'
            '  <grime name="g" type="color3" />\n' + _shader("base_color", "color3", "g"))
    path = _mtlx(tmp_path, body)
    with pytest.raises(Exception, match="(?i)source code|grime"):
        _glsl(path)
    assert _codes(path).get("OPBR808") == "error"
    (tmp_path / "grime.glsl").write_text("void grime_color3(vec3 base, out vec3 result) { result = base * 0.5; }\n")
    assert _glsl(path)
    assert "OPBR808" not in _codes(path)


def test_two_default_versions_of_one_node(tmp_path):
    body = ''.join(
        f'  <nodedef name="ND_grime_v{v}_color3" node="grime" version="{v}.0"{flag}>\n'
        '    <input name="base" type="color3" value="0.5, 0.5, 0.5" />\n    <output name="out" type="color3" />\n'
        f'  </nodedef>\n  <nodegraph name="NG_grime_v{v}_color3" nodedef="ND_grime_v{v}_color3">\n'
        '    <output name="out" type="color3" interfacename="base" />\n  </nodegraph>\n'
        for v, flag in ((1, ' isdefaultversion="true"'), (2, "FLAG"))) + '  <grime name="g" type="color3" />\n' + \
        _shader("base_color", "color3", "g")
    assert _codes(_mtlx(tmp_path, body.replace("FLAG", ' isdefaultversion="true"'))).get("OPBR809") == "warning"
    assert "OPBR809" not in _codes(_mtlx(tmp_path, body.replace("FLAG", ""), name="one.mtlx"))


@pytest.mark.parametrize("geom, expected", [("|table_GRP|top_GEO", "warning"), ("/table_GRP/top_GEO", None)])
def test_a_look_assignment_with_a_maya_dag_path(tmp_path, geom, expected):
    body = ('  <constant name="c" type="color3">\n    <input name="value" type="color3" value="0.5, 0.3, 0.2" />\n'
            '  </constant>\n' + _shader("base_color", "color3", "c") +
            f'\n  <look name="L">\n    <materialassign name="MA" material="M" geom="{geom}" />\n  </look>')
    assert _codes(_mtlx(tmp_path, body)).get("OPBR810") == expected


def test_a_colour_space_on_a_connected_input_converts_nothing(tmp_path):
    """mb13: MaterialX's GLSL (the anchor) has no sRGB decode when srgb_texture sits on the shader's connected
    base_color, and has it when it sits on the image's file input."""
    image = '  <image name="bc" type="color3">\n    <input name="file" type="filename" value="albedo.png"{space} />\n  </image>\n'
    on_input = _mtlx(tmp_path, image.format(space="") + _shader("base_color", "color3", "bc", ' colorspace="srgb_texture"'))
    on_file = _mtlx(tmp_path, image.format(space=' colorspace="srgb_texture"') + _shader("base_color", "color3", "bc"),
                    name="file.mtlx")
    assert "srgb_texture_to_lin_rec709" not in _glsl(on_input)
    assert "srgb_texture_to_lin_rec709" in _glsl(on_file)
    assert _codes(on_input).get("OPBR509") == "warning"
    assert "OPBR509" not in _codes(on_file)


@pytest.mark.parametrize("scale, expected", [('type="float" value="-1"', "warning"), ('type="vector2" value="1, -1"', None)])
def test_a_normalmap_flipped_by_a_negative_strength(tmp_path, scale, expected):
    body = ('  <image name="n" type="vector3">\n    <input name="file" type="filename" value="normal.png" />\n  </image>\n'
            f'  <normalmap name="nm" type="vector3">\n    <input name="in" type="vector3" nodename="n" />\n'
            f'    <input name="scale" {scale} />\n  </normalmap>\n' + _shader("geometry_normal", "vector3", "nm"))
    assert _codes(_mtlx(tmp_path, body)).get("OPBR720") == expected


def test_a_normal_map_fed_to_the_tangent(tmp_path):
    body = ('  <image name="n" type="vector3">\n    <input name="file" type="filename" value="normal.png" />\n  </image>\n'
            '  <normalmap name="nm" type="vector3">\n    <input name="in" type="vector3" nodename="n" />\n  </normalmap>\n'
            + _shader("geometry_tangent", "vector3", "nm"))
    assert _codes(_mtlx(tmp_path, body)).get("OPBR718") == "warning"
    assert "OPBR718" not in _codes(_mtlx(tmp_path, body.replace("geometry_tangent", "geometry_normal"), name="n.mtlx"))


@pytest.mark.parametrize("inverted, expected", [(False, "warning"), (True, None)])
def test_a_unity_mask_maps_smoothness_read_as_roughness(tmp_path, inverted, expected):
    """mb07: Unity HDRP's mask map holds smoothness in A; read into roughness without 1 - x it renders inverted."""
    body = ('  <image name="mask" type="color4">\n    <input name="file" type="filename" value="oak_MaskMap.png" />\n'
            '  </image>\n  <extract name="a" type="float">\n    <input name="in" type="color4" nodename="mask" />\n'
            '    <input name="index" type="integer" value="3" />\n  </extract>\n'
            + ('  <invert name="r" type="float">\n    <input name="in" type="float" nodename="a" />\n  </invert>\n'
               if inverted else "") + _shader("specular_roughness", "float", "r" if inverted else "a"))
    assert _codes(_mtlx(tmp_path, body)).get("OPBR721") == expected


@pytest.mark.parametrize("chunk, expected", [(True, "warning"), (False, None)])
def test_an_srgb_png_tagged_acescg(tmp_path, chunk, expected):
    """mb10: the PNG's sRGB chunk declares encoded values; tagged acescg, MaterialX's GLSL (the anchor) runs the AP1
    matrix and no sRGB decode. Without the chunk the tag is the only statement, and nothing is reported."""
    from openpbr_tools.rules.texture_content import SRGB_IMAGE_AS_LINEAR

    data = dict(SRGB_IMAGE_AS_LINEAR.failing_files)["albedo.png"]
    image = Image.open(__import__("io").BytesIO(data))
    assert image.info.get("srgb") == 0
    (tmp_path / "albedo.png").write_bytes(data) if chunk else Image.new("RGB", (2, 2), (200, 120, 40)).save(tmp_path / "albedo.png")
    body = ('  <image name="bc" type="color3">\n    <input name="file" type="filename" value="albedo.png" colorspace="acescg" />\n'
            '  </image>\n' + _shader("base_color", "color3", "bc"))
    path = _mtlx(tmp_path, body, space="acescg")
    code = _glsl(path)
    assert "acescg_to_lin_rec709" in code and "srgb_texture_to_lin_rec709" not in code
    assert _codes(path).get("OPBR722") == expected


# -- converter (set H: renders) --------------------------------------------------------------------------------

_TILED_NORMAL = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <nodegraph name="NG">
    <input name="uvtiling" type="float" value="3" />
    <convert name="tiling" type="vector2">
      <input name="in" type="float" TILING />
    </convert>
    <tiledimage name="nrm" type="vector3">
      <input name="file" type="filename" value="normal.png" />
      <input name="uvtiling" type="vector2" nodename="tiling" />
    </tiledimage>
    <normalmap name="nmap" type="vector3">
      <input name="in" type="vector3" nodename="nrm" />
    </normalmap>
    <output name="out_normal" type="vector3" nodename="nmap" />
  </nodegraph>
  <standard_surface name="S" type="surfaceshader">
    <input name="normal" type="vector3" nodegraph="NG" output="out_normal" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
"""


def test_a_normal_maps_tiling_through_a_graph_input_is_kept(tmp_path):
    """H-01: MaterialX's brick example tiles every map by its graph input uvtiling (3) through a convert node; the
    normal map was read as a plain image and lost the tiling (bumps 3x larger than the bricks; 4.3 mean dE2000 in
    MaterialX's GLSL). NG_tiledimage computes uv * uvtiling: the glTF output's KHR_texture_transform scale is 3."""
    from openpbr_tools.convert import convert_file

    Image.new("RGB", (2, 2), (128, 128, 255)).save(tmp_path / "normal.png")
    source = tmp_path / "brick.mtlx"
    source.write_text(_TILED_NORMAL.replace("TILING", 'interfacename="uvtiling"'))
    convert_file(str(source), str(tmp_path / "out" / "b.gltf"))
    info = json.loads((tmp_path / "out" / "b.gltf").read_text())["materials"][0]["normalTexture"]
    assert info["extensions"]["KHR_texture_transform"]["scale"] == pytest.approx([3.0, 3.0])
    import MaterialX as mx

    convert_file(str(source), str(tmp_path / "out" / "b.mtlx"))
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(tmp_path / "out" / "b.mtlx"))
    # (since session 28 a graph that stands alone is kept whole: its nodes are the node graph's)
    tiled = [n for scope in [document] + document.getNodeGraphs() for n in scope.getNodes()
             if n.getCategory() in ("tiledimage", "place2d")]
    assert tiled, "the written normal map has no placement"


def test_a_tiling_computed_by_nodes_keeps_the_graph(tmp_path):
    """A tiling no constant gives (computed from a texture) cannot be a Texture's transform: the graph is kept whole
    (a procedural input), never read as an untiled image."""
    from openpbr_tools.io.mtlx.reader import read_mtlx
    from openpbr_tools.model import Connection

    Image.new("RGB", (2, 2), (128, 128, 255)).save(tmp_path / "normal.png")
    source = tmp_path / "computed.mtlx"
    source.write_text(_TILED_NORMAL.replace("TILING", 'nodename="noise"').replace(
        '    <convert name="tiling"', '    <noise2d name="noise" type="float" />\n    <convert name="tiling"'))
    (material,) = read_mtlx(str(source)).materials
    assert isinstance(material.inputs["normal"].value, Connection)


_COATED_BRASS = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="rough" type="float">
    <input name="file" type="filename" value="rough.png" />
  </image>
  <standard_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" value="0.9, 0.7, 0.3" />
    <input name="metalness" type="float" value="1" />
    <input name="specular_roughness" type="float" nodename="rough" />
    <input name="coat" type="float" value="1" />
    <input name="coat_roughness" type="float" value="0.6" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
"""


@pytest.mark.parametrize("target, roughness", [("UsdPreviewSurface", "roughness"), ("gltf_pbr", "roughness")])
def test_a_textured_roughness_under_a_rough_coat_survives_between_models_whose_coats_do_not_roughen(tmp_path, target,
                                                                                                       roughness):
    """H-02: MaterialX's brass example (a metal under a coat, roughness 0.16-0.56 from a texture) went to a
    UsdPreviewSurface with a constant roughness of 0: through OpenPBR, whose coat roughens the base, the base
    roughness was unroughened and clamped at 0 on every texel. Standard Surface's, the preview's and glTF's coats do
    not roughen the base (their MaterialX graphs), so the texture is the same quantity: carried as it is."""
    import MaterialX as mx

    from openpbr_tools.convert import convert_file

    Image.frombytes("L", (2, 2), bytes([40, 80, 120, 143])).save(tmp_path / "rough.png")
    source = tmp_path / "brass.mtlx"
    source.write_text(_COATED_BRASS)
    conversion = convert_file(str(source), str(tmp_path / "out" / "brass.mtlx"), target)
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(tmp_path / "out" / "brass.mtlx"))
    shader = next(n for n in document.getNodes() if n.getType() == "surfaceshader")
    image = shader.getInput(roughness).getConnectedNode()
    assert image.getCategory() == "image" and image.getInputValue("file").endswith("rough.png")
    assert any("carried as it is" in d.message for d in conversion.diagnostics)


@pytest.mark.parametrize("orientation, expected", [(6, "warning"), (1, None)])
def test_a_jpeg_texture_with_an_exif_orientation(tmp_path, orientation, expected):
    """The red team's session-17 basecolor_jpeg_exif_rotated: a phone photo's EXIF Orientation 6 (rotate 90) is
    applied by browsers and ignored by most engines; Pillow reads the tag (274) from the header."""
    image = Image.new("RGB", (4, 2), (200, 120, 40))
    exif = Image.Exif()
    exif[0x0112] = orientation
    image.save(tmp_path / "photo.jpg", exif=exif.tobytes())
    assert Image.open(tmp_path / "photo.jpg").getexif().get(0x0112) == orientation
    document = {"asset": {"version": "2.0"}, "images": [{"uri": "photo.jpg"}], "textures": [{"source": 0}],
                "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]}
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps(document))
    assert _codes(path).get("OPBR1232") == expected


def test_a_usd_preview_surface_on_the_materialx_surface_output(tmp_path):
    """ub05: outputs:mtlx:surface fed by info:id UsdPreviewSurface. MaterialX's library (the anchor) defines the
    preview surface as ND_UsdPreviewSurface_surfaceshader and has no node definition named UsdPreviewSurface, so a
    renderer reading the mtlx context through MaterialX finds none. Reported as a warning (Storm knows the id)."""
    import MaterialX as mx

    from openpbr_tools.rules.usd_shading import PREVIEW_IN_MTLX_CONTEXT as rule

    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    assert library.getNodeDef("ND_UsdPreviewSurface_surfaceshader") is not None
    assert library.getNodeDef("UsdPreviewSurface") is None
    for text, expected in ((rule.failing, "warning"), (rule.passing, None)):
        path = tmp_path / f"{expected}.usda"
        path.write_text(text)
        assert _codes(path).get("OPBR1029") == expected
