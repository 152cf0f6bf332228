"""Texture coordinates in USD: a primvar reader that names a primvar the meshes bound to its material do
not have (OPBR1015), and a UsdUVTexture whose ``st`` is not connected (OPBR1016).

Both render a texture as the one texel at (0, 0): the UsdPreviewSurface specification gives
UsdUVTexture's ``st`` the fallback (0, 0), and a UsdPrimvarReader whose primvar is absent returns its
``fallback``, (0, 0) for float2 (OpenUSD docs/spec_usdpreviewsurface.rst). Which meshes a material is
bound to is usd-core's answer (UsdShade.MaterialBindingAPI.ComputeBoundMaterials), and whether a mesh
has a primvar UsdGeom.PrimvarsAPI's.
"""

from __future__ import annotations

import pytest

from openpbr_tools.validate import Options, validate_paths

HEAD = '#usda 1.0\n(\n    defaultPrim = "World"\n    metersPerUnit = 1\n    upAxis = "Y"\n)\n\n'


def _mesh(name: str, primvar: str | None = "st", binding: str | None = "/World/M", purpose: str = "") -> str:
    uv = (f'        texCoord2f[] primvars:{primvar} = [(0, 0), (1, 0), (1, 1), (0, 1)] (\n'
          '            interpolation = "vertex"\n        )\n') if primvar else ""
    bind = f'        rel material:binding{":" + purpose if purpose else ""} = <{binding}>\n' if binding else ""
    api = '        prepend apiSchemas = ["MaterialBindingAPI"]\n' if binding else ""
    return (f'    def Mesh "{name}" (\n{api}    )\n    {{\n'
            '        int[] faceVertexCounts = [4]\n        int[] faceVertexIndices = [0, 1, 2, 3]\n'
            '        point3f[] points = [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1)]\n'
            f'{uv}{bind}    }}\n\n')


def _material(varname: str | None = "st", st: bool = True, interface: str | None = None) -> str:
    if interface is not None:
        frame = f'        string inputs:frame:stPrimvarName = "{interface}"\n'
        reads = '            string inputs:varname.connect = </World/M.inputs:frame:stPrimvarName>\n'
    else:
        frame, reads = "", f'            string inputs:varname = "{varname}"\n'
    st_line = '            float2 inputs:st.connect = </World/M/uv.outputs:result>\n' if st else ""
    return ('    def Material "M"\n    {\n' + frame +
            '        token outputs:surface.connect = </World/M/S.outputs:surface>\n\n'
            '        def Shader "S"\n        {\n            uniform token info:id = "UsdPreviewSurface"\n'
            '            color3f inputs:diffuseColor.connect = </World/M/albedo.outputs:rgb>\n'
            '            token outputs:surface\n        }\n\n'
            '        def Shader "albedo"\n        {\n            uniform token info:id = "UsdUVTexture"\n'
            '            asset inputs:file = @albedo.png@\n            token inputs:sourceColorSpace = "sRGB"\n'
            f'{st_line}            float3 outputs:rgb\n        }}\n\n'
            '        def Shader "uv"\n        {\n            uniform token info:id = "UsdPrimvarReader_float2"\n'
            f'{reads}            float2 outputs:result\n        }}\n    }}\n')


def _stage(tmp_path, meshes: str, material: str, name="m.usda", xform_binding: bool = False, flat: bool = False):
    from PIL import Image

    image = Image.new("RGB", (4, 4), (200, 100, 50))
    if not flat:
        image.putpixel((3, 3), (20, 40, 60))
    image.save(tmp_path / "albedo.png")
    world = ('def Xform "World" (\n    prepend apiSchemas = ["MaterialBindingAPI"]\n)\n{\n'
             '    rel material:binding = </World/M>\n\n') if xform_binding else 'def Xform "World"\n{\n'
    path = tmp_path / name
    path.write_text(HEAD + world + meshes + material + "}\n", encoding="utf-8")
    return path


def _findings(path, code):
    return [d for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics if d.code == code]


def test_a_reader_of_a_primvar_the_bound_mesh_lacks_is_an_error_at_the_reader(tmp_path):
    path = _stage(tmp_path, _mesh("Plane", primvar="UVMap"), _material("st"))
    [finding] = _findings(path, "OPBR1015")
    assert finding.severity.name == "ERROR"
    assert (finding.location.path, finding.location.input) == ("/World/M/uv", "varname")
    assert "/World/Plane" in finding.message and "UVMap" in finding.message


def test_a_reader_of_a_primvar_every_bound_mesh_has_is_quiet(tmp_path):
    path = _stage(tmp_path, _mesh("A", primvar="st") + _mesh("B", primvar="st"), _material("st"))
    assert _findings(path, "OPBR1015") == []


def test_one_mesh_of_several_without_the_primvar_is_named(tmp_path):
    path = _stage(tmp_path, _mesh("A", primvar="st") + _mesh("B", primvar="uv") + _mesh("C", primvar="st"), _material("st"))
    [finding] = _findings(path, "OPBR1015")
    assert "/World/B" in finding.message and "/World/A" not in finding.message


def test_a_varname_connected_to_the_material_interface_is_read_through_it(tmp_path):
    assert _findings(_stage(tmp_path, _mesh("A", primvar="st"), _material(interface="st")), "OPBR1015") == []
    [finding] = _findings(_stage(tmp_path, _mesh("A", primvar="st"), _material(interface="uv2"), name="b.usda"), "OPBR1015")
    assert "'uv2'" in finding.message


@pytest.mark.parametrize("how", ["inherited from the parent", "render purpose only"])
def test_bindings_are_resolved_as_usd_core_resolves_them(tmp_path, how):
    if how == "inherited from the parent":
        path = _stage(tmp_path, _mesh("A", primvar="UVMap", binding=None), _material("st"), xform_binding=True)
    else:
        path = _stage(tmp_path, _mesh("A", primvar="UVMap", purpose="full"), _material("st"))
    assert len(_findings(path, "OPBR1015")) == 1


def test_a_material_bound_to_no_mesh_is_not_judged(tmp_path):
    path = _stage(tmp_path, _mesh("A", primvar="UVMap", binding=None), _material("st"))
    assert _findings(path, "OPBR1015") == []


def test_a_uv_texture_without_st_reads_one_texel(tmp_path):
    [finding] = _findings(_stage(tmp_path, _mesh("A", primvar="st"), _material(st=False)), "OPBR1016")
    assert finding.severity.name == "ERROR"  # (an error since session 19: the texture does not show at all)
    assert (finding.location.path, finding.location.input) == ("/World/M/albedo", "st")
    assert _findings(_stage(tmp_path, _mesh("A", primvar="st"), _material(st=True), name="b.usda"), "OPBR1016") == []


def test_a_texture_of_one_flat_colour_looks_the_same_at_any_coordinate(tmp_path):
    """usd-wg's USD_Mini_Car_Kit colours its parts with 32 x 32 single-colour JPEGs and no st: nothing renders wrong."""
    assert _findings(_stage(tmp_path, _mesh("A", primvar="st"), _material(st=False), flat=True), "OPBR1016") == []
    assert _findings(_stage(tmp_path, _mesh("A", primvar="UVMap"), _material("st"), name="b.usda", flat=True), "OPBR1015") == []


def test_a_texture_that_cannot_be_read_is_not_judged(tmp_path):
    path = _stage(tmp_path, _mesh("A", primvar="st"), _material(st=False))
    (tmp_path / "albedo.png").unlink()
    codes = [d.code for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics]
    assert "OPBR701" in codes and "OPBR1016" not in codes


def test_a_stage_composed_without_some_of_its_layers_is_not_judged(tmp_path):
    """Its primvars may live in the layer that is missing (or that the path guard kept out)."""
    meshes = _mesh("A", primvar="UVMap") + '    def Xform "Extra" (\n        prepend references = @missing.usda@\n    )\n    {\n    }\n\n'
    assert _findings(_stage(tmp_path, meshes, _material("st")), "OPBR1015") == []


def test_st_connected_to_a_material_interface_value_is_not_unconnected(tmp_path):
    material = _material(st=False).replace(
        '            float3 outputs:rgb\n',
        '            float2 inputs:st.connect = </World/M.inputs:coords>\n            float3 outputs:rgb\n', 1)
    material = material.replace('    def Material "M"\n    {\n', '    def Material "M"\n    {\n        float2 inputs:coords = (0.5, 0.5)\n', 1)
    assert _findings(_stage(tmp_path, _mesh("A", primvar="st"), material), "OPBR1016") == []


def _materialx_material(geomprop: str) -> str:
    return ('    def Material "M"\n    {\n'
            '        token outputs:mtlx:surface.connect = </World/M/S.outputs:surface>\n\n'
            '        def Shader "S"\n        {\n            uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n'
            '            color3f inputs:base_color.connect = </World/M/albedo.outputs:out>\n'
            '            token outputs:surface\n        }\n\n'
            '        def Shader "albedo"\n        {\n            uniform token info:id = "ND_image_color3"\n'
            '            asset inputs:file = @albedo.png@ (\n                colorSpace = "srgb_texture"\n            )\n'
            '            float2 inputs:texcoord.connect = </World/M/uv.outputs:out>\n'
            '            color3f outputs:out\n        }\n\n'
            '        def Shader "uv"\n        {\n            uniform token info:id = "ND_geompropvalue_vector2"\n'
            f'            string inputs:geomprop = "{geomprop}"\n            float2 outputs:out\n        }}\n    }}\n')


def test_a_materialx_geompropvalue_naming_a_primvar_the_mesh_lacks_is_reported_too(tmp_path):
    [finding] = _findings(_stage(tmp_path, _mesh("A", primvar="st"), _materialx_material("UVMap")), "OPBR1015")
    assert (finding.location.path, finding.location.input) == ("/World/M/uv", "geomprop")
    assert _findings(_stage(tmp_path, _mesh("A", primvar="UVMap"), _materialx_material("UVMap"), name="b.usda"),
                     "OPBR1015") == []


def test_an_openexr_texture_is_judged_through_openimageio(tmp_path):
    oiio = pytest.importorskip("OpenImageIO")
    path = _stage(tmp_path, _mesh("A", primvar="st"), _material(st=False).replace("albedo.png", "albedo.exr"))
    buffer = oiio.ImageBuf(oiio.ImageSpec(8, 8, 3, oiio.HALF))
    oiio.ImageBufAlgo.fill(buffer, (0.5, 0.2, 0.1))
    assert buffer.write(str(tmp_path / "albedo.exr"))
    assert _findings(path, "OPBR1016") == []  # one flat colour
    buffer.setpixel(3, 3, (0.9, 0.9, 0.9))
    assert buffer.write(str(tmp_path / "albedo.exr"))
    assert len(_findings(path, "OPBR1016")) == 1
