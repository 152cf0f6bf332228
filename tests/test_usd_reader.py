"""Reading USD stages: values with their USD types, connections through interfaces and node graphs,
texture chains, colour spaces, units, composition, and files USD cannot open."""

from __future__ import annotations

import math
import os
import zipfile

import pytest

from openpbr_tools.io import ReadError, read_asset
from openpbr_tools.model import Connection, Constant, Texture

HEADER = '#usda 1.0\n(\n    defaultPrim = "M"\n    metersPerUnit = 0.01\n    upAxis = "Y"\n)\n\n'


def material(*shader_lines: str, extra: str = "", shader_id: str = "ND_open_pbr_surface_surfaceshader",
             output: str = "surface", header: str = HEADER, material_lines: str = "") -> str:
    lines = "".join(f"        {line}\n" for line in shader_lines)
    return (f'{header}def Material "M"\n{{\n{material_lines}'
            f"    token outputs:mtlx:surface.connect = </M/S.outputs:{output}>\n\n"
            f'    def Shader "S"\n    {{\n        uniform token info:id = "{shader_id}"\n{lines}'
            f"        token outputs:{output}\n    }}\n{extra}}}\n")


def shader(name: str, shader_id: str, *lines: str) -> str:
    body = "".join(f"        {line}\n" for line in lines)
    return f'\n    def Shader "{name}"\n    {{\n        uniform token info:id = "{shader_id}"\n{body}    }}\n'


@pytest.fixture
def read(tmp_path):
    def run(text: str, name: str = "stage.usda", files=()):
        for file in files:
            (tmp_path / file).parent.mkdir(parents=True, exist_ok=True)
            (tmp_path / file).write_bytes(b"")
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return read_asset(path)

    return run


def only(asset):
    (found,) = asset.materials
    return found


def test_values_keep_usd_types_and_read_as_materialx_values(read):
    asset = read(material("color3f inputs:base_color = (0.8, 0.2, 0.1)", "float inputs:specular_ior = 1.45",
                          "bool inputs:geometry_thin_walled = 1"))
    found = only(asset)
    color, ior, thin = (found.inputs[n] for n in ("base_color", "specular_ior", "geometry_thin_walled"))
    assert (color.type, color.source_type, color.constant) == ("color3", "color3f", (0.8, 0.2, 0.1))
    assert (ior.type, ior.constant) == ("float", 1.45)  # float32 1.45 read back as the decimal authored
    assert (thin.type, thin.source_type, thin.constant) == ("boolean", "bool", True)
    assert color.location.path == "/M/S" and color.location.input == "base_color" and color.location.line is None
    assert asset.format == "usd" and found.model == "open_pbr_surface" and found.material_name == "M" \
        and found.material_location.path == "/M"


def test_a_float3_colour_reads_as_color3_and_keeps_its_usd_type(read):
    entry = only(read(material("float3 inputs:base_color = (0.5, 0.5, 0.5)"))).inputs["base_color"]
    assert (entry.type, entry.source_type) == ("color3", "float3")


@pytest.mark.parametrize("output", ["out", "surface"])
def test_both_producer_conventions_for_the_shader_output_are_accepted(read, output):
    assert only(read(material("float inputs:base_weight = 1", output=output))).model == "open_pbr_surface"


def test_a_value_through_the_material_interface_is_read_and_remembered(read):
    text = material("float inputs:coat_weight.connect = </M.inputs:coat>", material_lines="    float inputs:coat = 0.25\n")
    entry = only(read(text)).inputs["coat_weight"]
    assert entry.constant == 0.25 and entry.interface_name == "coat"


def test_an_interface_input_without_value_leaves_the_input_unset(read):
    """UsdMtlx writes interface inputs without values; the shader's default applies."""
    text = material("float inputs:coat_weight.connect = </M.inputs:coat>", material_lines="    float inputs:coat\n")
    entry = only(read(text)).inputs["coat_weight"]
    assert entry.value is None and entry.error is None


def test_node_graph_outputs_are_followed_to_the_image(read):
    graph = ('\n    def NodeGraph "NG"\n    {\n        color3f outputs:albedo.connect = </M/NG/img.outputs:out>\n'
             + shader("img", "ND_image_color3", "asset inputs:file = @albedo.png@", "color3f outputs:out").replace("\n    ", "\n        ")
             + "    }\n")
    texture = only(read(material("color3f inputs:base_color.connect = </M/NG.outputs:albedo>", extra=graph))).inputs["base_color"].texture
    assert texture is not None and texture.file == "albedo.png" and texture.node == "/M/NG/img"


def test_materialx_image_chain_becomes_one_texture(read):
    extra = (shader("orm", "ND_image_color3", 'asset inputs:file = @orm.png@ (colorSpace = "none")',
                    "float2 inputs:texcoord.connect = </M/place.outputs:out>", 'string inputs:uaddressmode = "clamp"',
                    "color3f outputs:out")
             + shader("rough", "ND_extract_color3", "color3f inputs:in.connect = </M/orm.outputs:out>", "int inputs:index = 1",
                      "float outputs:out")
             + shader("place", "ND_place2d_vector2", "float2 inputs:scale = (2, 2)", "float inputs:rotate = 30",
                      "float2 inputs:texcoord.connect = </M/uv.outputs:out>", "float2 outputs:out")
             + shader("uv", "ND_geompropvalue_vector2", 'string inputs:geomprop = "st1"', "float2 outputs:out"))
    texture = only(read(material("float inputs:specular_roughness.connect = </M/rough.outputs:out>", extra=extra))).inputs[
        "specular_roughness"].texture
    assert (texture.file, texture.channels, texture.colorspace, texture.image_type) == ("orm.png", (1,), "none", "color3")
    assert texture.uv.scale == (2.0, 2.0) and texture.uv.rotate == 30.0 and texture.texcoord == "st1"
    assert texture.wrap == ("clamp", "periodic") and texture.node_category == "image"


def test_normalmap_and_scale_bias_nodes_are_part_of_the_texture(read):
    extra = (shader("img", "ND_image_vector3", "asset inputs:file = @n.png@", "float3 outputs:out")
             + shader("mul", "ND_multiply_vector3", "float3 inputs:in1.connect = </M/img.outputs:out>",
                      "float3 inputs:in2 = (1, 1, 0.5)", "float3 outputs:out")
             + shader("nmap", "ND_normalmap_float", "float3 inputs:in.connect = </M/mul.outputs:out>", "float inputs:scale = 0.8",
                      "float3 outputs:out"))
    texture = only(read(material("float3 inputs:geometry_normal.connect = </M/nmap.outputs:out>", extra=extra))).inputs[
        "geometry_normal"].texture
    assert texture.normal_map == pytest.approx(0.8) and texture.scale == (1.0, 1.0, 0.5)


def _place2d(uv, st):
    """MaterialX place2d, SRT order (stdlib NG_place2d_vector2): rotate2d((st - pivot) / scale,
    rotate) - offset + pivot, with rotate2d as mx_rotate_vector2: (c x + s y, -s x + c y)."""
    x, y = (st[0] - uv.pivot[0]) / uv.scale[0], (st[1] - uv.pivot[1]) / uv.scale[1]
    a = math.radians(uv.rotate)
    x, y = math.cos(a) * x + math.sin(a) * y, -math.sin(a) * x + math.cos(a) * y
    return x - uv.offset[0] + uv.pivot[0], y - uv.offset[1] + uv.pivot[1]


def _transform2d(scale, rotation, translation, st):
    """UsdTransform2d (UsdPreviewSurface spec): st * scale, rotated counter-clockwise, + translation."""
    x, y = st[0] * scale[0], st[1] * scale[1]
    a = math.radians(rotation)
    return math.cos(a) * x - math.sin(a) * y + translation[0], math.sin(a) * x + math.cos(a) * y + translation[1]


def test_usd_uv_texture_with_transform_and_primvar(read):
    extra = (shader("tex", "UsdUVTexture", "asset inputs:file = @albedo.png@", 'token inputs:sourceColorSpace = "sRGB"',
                    "float4 inputs:scale = (0.5, 0.5, 0.5, 1)", "float4 inputs:fallback = (1, 0, 1, 1)",
                    'token inputs:wrapS = "repeat"', 'token inputs:wrapT = "mirror"',
                    "float2 inputs:st.connect = </M/xf.outputs:result>", "float3 outputs:rgb", "float outputs:g")
             + shader("xf", "UsdTransform2d", "float2 inputs:in.connect = </M/pv.outputs:result>", "float inputs:rotation = 90",
                      "float2 inputs:scale = (4, 2)", "float2 inputs:translation = (0.5, 0.25)", "float2 outputs:result")
             + shader("pv", "UsdPrimvarReader_float2", 'string inputs:varname = "uv1"', "float2 outputs:result"))
    found = only(read(material("color3f inputs:base_color.connect = </M/tex.outputs:rgb>",
                               "float inputs:specular_roughness.connect = </M/tex.outputs:g>", extra=extra)))
    color, rough = found.inputs["base_color"].texture, found.inputs["specular_roughness"].texture
    assert color.channels is None and rough.channels == (1,)
    assert (color.colorspace, color.scale, color.fallback, color.wrap) == ("sRGB", (0.5, 0.5, 0.5), (1.0, 0.0, 1.0, 1.0),
                                                                            ("repeat", "mirror"))
    assert rough.scale == 0.5  # the float4's green component: what outputs:g delivers
    assert color.texcoord == "uv1" and color.node_category == "UsdUVTexture"
    for st in ((0.0, 0.0), (1.0, 0.0), (0.3, 0.7)):
        assert _place2d(color.uv, st) == pytest.approx(_transform2d((4, 2), 90, (0.5, 0.25), st))


def test_colour_spaces_from_metadata_and_color_space_api_inheritance(read):
    text = ('#usda 1.0\n(\n    defaultPrim = "Root"\n    metersPerUnit = 1\n)\n\n'
            'def Scope "Root" (\n    prepend apiSchemas = ["ColorSpaceAPI"]\n)\n{\n    uniform token colorSpace:name = "lin_ap1_scene"\n'
            + material("color3f inputs:base_color = (0.5, 0.4, 0.3)",
                       'color3f inputs:coat_color = (0.9, 0.9, 0.9) (colorSpace = "srgb_texture")',
                       header="").replace("</M/", "</Root/M/") + "}\n")
    asset = read(text)
    found = only(asset)
    assert asset.colorspace == "lin_ap1_scene" and found.colorspace == "acescg"
    assert found.inputs["base_color"].authored_colorspace is None and found.inputs["base_color"].colorspace == "lin_ap1_scene"
    assert found.inputs["coat_color"].authored_colorspace == "srgb_texture"


def test_meters_per_unit_is_recorded_only_when_authored(read):
    assert read(material("float inputs:base_weight = 1")).meters_per_unit == 0.01
    unauthored = HEADER.replace("    metersPerUnit = 0.01\n", "")
    assert read(material("float inputs:base_weight = 1", header=unauthored), name="b.usda").meters_per_unit is None


def test_composition_references_payloads_and_variants_are_resolved(read, tmp_path):
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "looks.usda").write_text(
        '#usda 1.0\n\ndef Material "Lib"\n{\n    token outputs:mtlx:surface.connect = </Lib/S.outputs:surface>\n'
        '    def Shader "S"\n    {\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n'
        "        color3f inputs:base_color.connect = </Lib/img.outputs:out>\n        token outputs:surface\n    }\n"
        '    def Shader "img"\n    {\n        uniform token info:id = "ND_image_color3"\n        asset inputs:file = @tex/a.png@\n'
        "        color3f outputs:out\n    }\n}\n")
    (tmp_path / "payload.usda").write_text(
        '#usda 1.0\n\ndef Material "P"\n{\n    token outputs:mtlx:surface.connect = </P/S.outputs:surface>\n'
        '    def Shader "S"\n    {\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n'
        "        float inputs:base_weight = 0.5\n        token outputs:surface\n    }\n}\n")
    text = (HEADER + 'def Material "Ref" (\n    references = @lib/looks.usda@</Lib>\n)\n{\n}\n\n'
            'def Material "Pay" (\n    payload = @payload.usda@</P>\n)\n{\n}\n\n'
            'def Material "V" (\n    variants = {\n        string look = "red"\n    }\n    prepend variantSets = "look"\n)\n{\n'
            "    token outputs:mtlx:surface.connect = </V/S.outputs:surface>\n"
            '    def Shader "S"\n    {\n        uniform token info:id = "ND_open_pbr_surface_surfaceshader"\n        token outputs:surface\n    }\n'
            '    variantSet "look" = {\n        "blue" {\n            over "S"\n            {\n'
            "                color3f inputs:base_color = (0.1, 0.1, 0.9)\n            }\n        }\n"
            '        "red" {\n            over "S"\n            {\n'
            "                color3f inputs:base_color = (0.9, 0.1, 0.1)\n            }\n        }\n    }\n}\n")
    asset = read(text)
    by_material = {m.material_location.path: m for m in asset.materials}
    assert by_material["/Ref"].inputs["base_color"].texture.file == "lib/tex/a.png"  # re-anchored at the root layer
    assert by_material["/Pay"].inputs["base_weight"].constant == 0.5
    assert by_material["/V"].inputs["base_color"].constant == (0.9, 0.1, 0.1)


def test_version_from_a_versioned_id_and_from_custom_data(read):
    legacy = only(read(material("float inputs:base_weight = 1", shader_id="ND_open_pbr_surface_surfaceshader_05")))
    assert legacy.version == "0.5" and legacy.version_basis.startswith("nodedef")
    recorded = material("float inputs:base_weight = 1").replace(
        '    def Shader "S"\n', '    def Shader "S" (\n        customData = {\n            dictionary openpbr = {\n'
                                  '                string version = "1.0"\n            }\n        }\n    )\n')
    found = only(read(recorded, name="r.usda"))
    assert found.version == "1.0" and "customData" in found.version_basis


def test_preview_surface_opacity_mode_token_reads_as_its_enum(read):
    text = (HEADER + 'def Material "M"\n{\n    token outputs:surface.connect = </M/P.outputs:surface>\n'
            + shader("P", "UsdPreviewSurface", 'token inputs:opacityMode = "presence"', "normal3f inputs:normal = (0, 0, 1)",
                     "token outputs:surface") + "}\n")
    found = only(read(text))
    mode, normal = found.inputs["opacityMode"], found.inputs["normal"]
    assert found.model == "UsdPreviewSurface" and (mode.type, mode.constant, mode.raw) == ("integer", 1, "presence")
    assert (normal.type, normal.source_type) == ("vector3", "normal3f")


def test_opaque_and_dangling_connections(read):
    extra = shader("noise", "ND_noise2d_color3", "color3f outputs:out")
    found = only(read(material("color3f inputs:base_color.connect = </M/noise.outputs:out>",
                               "float inputs:base_weight.connect = </M/missing.outputs:out>", extra=extra)))
    procedural, dangling = found.inputs["base_color"].value, found.inputs["base_weight"].value
    assert isinstance(procedural, Connection) and not procedural.dangling and procedural.category == "ND_noise2d_color3"
    assert isinstance(dangling, Connection) and dangling.dangling


def test_usdz_textures_are_marked_as_packaged(tmp_path):
    layer = material("color3f inputs:base_color.connect = </M/img.outputs:out>",
                     extra=shader("img", "ND_image_color3", "asset inputs:file = @textures/a.png@", "color3f outputs:out"))
    (tmp_path / "root.usda").write_text(layer)
    (tmp_path / "a.png").write_bytes(b"\x89PNG")
    from pxr import Sdf

    writer = Sdf.ZipFileWriter.CreateNew(str(tmp_path / "pkg.usdz"))
    writer.AddFile(str(tmp_path / "root.usda"), "root.usda")
    writer.AddFile(str(tmp_path / "a.png"), "textures/a.png")
    writer.Save()
    asset = read_asset(tmp_path / "pkg.usdz")
    texture = only(asset).inputs["base_color"].texture
    assert texture.packaged and texture.file == "textures/a.png" and texture.file in asset.extra["package_files"]


# -- files USD cannot open ------------------------------------------------------------------------

def _usdz(path, members):
    with zipfile.ZipFile(path, "w", zipfile.ZIP_STORED) as package:
        for name, data in members:
            package.writestr(name, data)


@pytest.mark.parametrize(
    "name, content, says",
    [
        ("corrupt.usdc", b"PXR-USDC" + bytes(range(256)) * 4, "USD cannot open"),
        ("random.usdc", os.urandom(512), "USD cannot open"),
        ("syntax.usda", b'#usda 1.0\ndef Material "M" {\n  float inputs:x = \n', "Expected"),
        ("empty.usdz", None, "first file is not a USD layer"),
        ("not_a_zip.usdz", b"hello", "not a USDZ package"),
    ],
)
def test_files_usd_cannot_open_raise_read_errors(tmp_path, name, content, says):
    path = tmp_path / name
    if content is None:
        _usdz(path, [])
    else:
        path.write_bytes(content)
    with pytest.raises(ReadError) as raised:
        read_asset(path)
    assert raised.value.kind == "not_usd" and says in raised.value.message


def test_syntax_error_names_its_line(tmp_path):
    path = tmp_path / "syntax.usda"
    path.write_text('#usda 1.0\n\ndef Material "M"\n{\n    float inputs:x = \n')
    with pytest.raises(ReadError) as raised:
        read_asset(path)
    assert raised.value.location.line == 5


def test_usdz_with_a_missing_layer_is_read_without_it(tmp_path):
    """usd-core composes a stage whose sublayer is missing (a composition error): the missing layer is observed
    (OPBR1042), the rest read."""
    path = tmp_path / "missing.usdz"
    _usdz(path, [("root.usda", '#usda 1.0\n(\n    subLayers = [@looks.usda@]\n)\n')])
    missing = [o for o in read_asset(path).observations if o.kind == "usd_layer_missing"]
    assert len(missing) == 1 and "looks.usda" in missing[0].detail["reason"]


def test_missing_file_is_unreadable(tmp_path):
    with pytest.raises(ReadError) as raised:
        read_asset(tmp_path / "nope.usda")
    assert raised.value.kind == "unreadable"


def test_constants_textures_connections_are_the_three_value_kinds(read):
    """Every authored input is one of the model's value kinds (or None when declared without a value)."""
    extra = shader("img", "ND_image_color3", "asset inputs:file = @a.png@", "color3f outputs:out")
    found = only(read(material("color3f inputs:base_color.connect = </M/img.outputs:out>", "float inputs:base_weight = 1",
                               "float inputs:coat_weight", extra=extra)))
    kinds = {name: type(entry.value) for name, entry in found.inputs.items()}
    assert kinds == {"base_color": Texture, "base_weight": Constant, "coat_weight": type(None)}


def test_a_fifo_named_like_a_stage_is_refused_without_blocking(tmp_path):
    path = tmp_path / "pipe.usda"
    os.mkfifo(path)
    with pytest.raises(ReadError) as raised:
        read_asset(path)
    assert raised.value.kind == "unreadable"
