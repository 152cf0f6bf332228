"""The rules on USD stages: the MaterialX rules whose meaning carries over (same codes), and the
USD family's own behaviour beyond its documented examples."""

from __future__ import annotations

import pytest

from openpbr_tools.validate import validate_file

HEADER = '#usda 1.0\n(\n    defaultPrim = "M"\n    metersPerUnit = 0.01\n    upAxis = "Y"\n)\n\n'


def shader(name: str, shader_id: str | None, *lines: str) -> str:
    body = "".join(f"        {line}\n" for line in lines)
    identifier = f'        uniform token info:id = "{shader_id}"\n' if shader_id else ""
    return f'\n    def Shader "{name}"\n    {{\n{identifier}{body}    }}\n'


def openpbr(*lines: str, extra: str = "", header: str = HEADER, material_lines: str = "") -> str:
    return (f'{header}def Material "M"\n{{\n{material_lines}    token outputs:mtlx:surface.connect = </M/S.outputs:surface>\n'
            + shader("S", "ND_open_pbr_surface_surfaceshader", *lines, "token outputs:surface") + extra + "}\n")


def preview(*lines: str, extra: str = "") -> str:
    return (f'{HEADER}def Material "M"\n{{\n    token outputs:surface.connect = </M/P.outputs:surface>\n'
            + shader("P", "UsdPreviewSurface", *lines, "token outputs:surface") + extra + "}\n")


@pytest.fixture
def findings(tmp_path):
    """findings(text, code, files=()) -> the diagnostics with that code for the stage."""

    def run(text: str, code: str, files=(), name: str = "stage.usda"):
        for file in files:
            (tmp_path / file).write_bytes(b"")
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return [d for d in validate_file(str(path)).diagnostics if d.code == code]

    return run


# -- MaterialX rules that judge USD materials unchanged --------------------------------------------

@pytest.mark.parametrize(
    "line, code, input_name",
    [
        ("color3f inputs:base_colour = (0.5, 0.5, 0.5)", "OPBR101", "base_colour"),
        ("float inputs:base_color = 0.5", "OPBR201", "base_color"),
        ("float inputs:base_weight = 1.5", "OPBR301", "base_weight"),
        ("float3 inputs:base_color = (1.5, 0.5, 0.5)", "OPBR301", "base_color"),  # role mismatch still range-checked
        ("float inputs:specular_ior = 4.5", "OPBR302", "specular_ior"),
        ("float inputs:base_weight = nan", "OPBR203", "base_weight"),
    ],
)
def test_materialx_rules_apply_to_usd_inputs(findings, line, code, input_name):
    (finding,) = findings(openpbr(line), code)
    assert finding.location.path == "/M/S" and finding.location.input == input_name


def test_unknown_input_hint_names_the_meant_input(findings):
    (finding,) = findings(openpbr("float inputs:specular_roughnes = 0.3"), "OPBR101")
    assert finding.hint == "did you mean 'specular_roughness'?"


def test_use_specular_workflow_outside_its_values(findings):
    (finding,) = findings(preview("int inputs:useSpecularWorkflow = 2"), "OPBR303")
    assert finding.location.input == "useSpecularWorkflow"


def test_opacity_mode_token_outside_its_values(findings):
    (finding,) = findings(preview('token inputs:opacityMode = "cutout"'), "OPBR303")
    assert "cutout" in finding.message
    assert not findings(preview('token inputs:opacityMode = "presence"'), "OPBR303")


def test_wrap_tokens_from_the_other_scheme(findings):
    extra = shader("tex", "UsdUVTexture", "asset inputs:file = @a.exr@", 'token inputs:wrapS = "periodic"', "float3 outputs:rgb")
    (finding,) = findings(preview("color3f inputs:diffuseColor.connect = </M/tex.outputs:rgb>", extra=extra), "OPBR303",
                          files=("a.exr",))
    assert finding.location.path == "/M/tex" and finding.location.input == "wrapS"


def test_missing_texture_and_image_type_checks_apply(findings):
    extra = shader("tex", "UsdUVTexture", "asset inputs:file = @gone.png@", 'token inputs:sourceColorSpace = "sRGB"',
                   "float outputs:r")
    text = openpbr("color3f inputs:base_color.connect = </M/tex.outputs:r>", extra=extra)
    assert findings(text, "OPBR701") and findings(text, "OPBR702")


def test_world_normal_from_a_texture_needs_a_normalmap_node(findings):
    extra = shader("n", "ND_image_vector3", "asset inputs:file = @n.png@", "float3 outputs:out")
    assert findings(openpbr("float3 inputs:geometry_normal.connect = </M/n.outputs:out>", extra=extra), "OPBR703",
                    files=("n.png",))


def test_legacy_names_and_plausibility_apply(findings):
    assert findings(openpbr("float inputs:base_roughness = 0.2"), "OPBR402")
    assert findings(openpbr("float inputs:base_metalness = 1", "color3f inputs:base_color = (0.1, 0.1, 0.1)"), "OPBR901")


def test_dangling_connections_on_inputs_and_on_the_surface_output(findings):
    (on_input,) = findings(openpbr("float inputs:base_weight.connect = </M/missing.outputs:out>"), "OPBR802")
    assert on_input.location.input == "base_weight"
    text = f'{HEADER}def Material "M"\n{{\n    token outputs:mtlx:surface.connect = </M/Nope.outputs:surface>\n}}\n'
    (on_output,) = findings(text, "OPBR802")
    assert on_output.location.path == "/M" and on_output.location.input == "outputs:mtlx:surface"


def test_connection_to_an_output_the_shader_does_not_have_is_dangling(findings):
    text = openpbr("float inputs:base_weight = 1").replace("</M/S.outputs:surface>", "</M/S.outputs:result>")
    assert findings(text, "OPBR802")


@pytest.mark.parametrize(
    "material_body",
    ["", "    token outputs:mtlx:surface\n"],
    ids=["no-surface-output", "unconnected-output"],
)
def test_material_without_surface_is_reported_with_the_usd_hint(findings, material_body):
    (finding,) = findings(f'{HEADER}def Material "M"\n{{\n{material_body}}}\n', "OPBR801")
    assert finding.location.path == "/M" and "outputs:mtlx:surface" in finding.hint


# -- colour spaces --------------------------------------------------------------------------------

def image(colorspace: str, file: str = "a.png", node: str = "ND_image_color3", output: str = "color3f outputs:out") -> str:
    return shader("img", node, f'asset inputs:file = @{file}@ (colorSpace = "{colorspace}")', output)


def test_unknown_colour_space_on_a_materialx_image(findings):
    text = openpbr("color3f inputs:base_color.connect = </M/img.outputs:out>", extra=image("srgb_tx"))
    (finding,) = findings(text, "OPBR502", files=("a.png",))
    assert finding.hint == "did you mean 'srgb_texture'?" and finding.location.path == "/M/img"


@pytest.mark.parametrize(
    "where, name, meant",
    [
        ("materialx-image", "lin_ap1_scene", "acescg"),
        ("materialx-image", "raw", "none"),
        ("color-space-api", "acescg", "lin_ap1_scene"),
        ("color-space-api", "srgb_texture", "srgb_rec709_scene"),
        ("source-color-space", "srgb_texture", "sRGB"),
        ("source-color-space", "none", "raw"),
    ],
)
def test_names_from_the_wrong_scheme_get_the_equivalent(findings, where, name, meant):
    if where == "materialx-image":
        text = openpbr("color3f inputs:base_color.connect = </M/img.outputs:out>", extra=image(name))
    elif where == "color-space-api":
        text = openpbr("color3f inputs:base_color = (0.5, 0.4, 0.3)").replace(
            'def Material "M"\n{\n', f'def Material "M" (\n    prepend apiSchemas = ["ColorSpaceAPI"]\n)\n{{\n'
                                      f'    uniform token colorSpace:name = "{name}"\n')
    else:
        extra = shader("tex", "UsdUVTexture", "asset inputs:file = @a.png@", f'token inputs:sourceColorSpace = "{name}"',
                       "float3 outputs:rgb")
        text = preview("color3f inputs:diffuseColor.connect = </M/tex.outputs:rgb>", extra=extra)
    # a Gf name on a MaterialX image is mapped by MaterialX 1.39.4+ (info, OPBR1014); the rest is wrong (OPBR1004)
    code = "OPBR1014" if (where, name) == ("materialx-image", "lin_ap1_scene") else "OPBR1004"
    (finding,) = findings(text, code, files=("a.png",))
    assert finding.hint == f"use {meant!r}"
    assert not findings(text, "OPBR502", files=("a.png",))


def test_colour_texture_read_raw(findings):
    extra = shader("tex", "UsdUVTexture", "asset inputs:file = @a.png@", 'token inputs:sourceColorSpace = "raw"', "float3 outputs:rgb")
    assert findings(preview("color3f inputs:diffuseColor.connect = </M/tex.outputs:rgb>", extra=extra), "OPBR503", files=("a.png",))


@pytest.mark.parametrize(
    "file, source, fires",
    [("rough.png", None, True), ("rough.png", "auto", True), ("rough.png", "sRGB", True), ("rough.png", "raw", False),
     ("rough.exr", None, False), ("rough.exr", "sRGB", True)],
)
def test_data_texture_decoded_as_srgb(findings, file, source, fires):
    lines = [f"asset inputs:file = @{file}@"] + ([f'token inputs:sourceColorSpace = "{source}"'] if source else [])
    extra = shader("tex", "UsdUVTexture", *lines, "float outputs:g")
    found = findings(preview("float inputs:roughness.connect = </M/tex.outputs:g>", extra=extra), "OPBR504", files=(file,))
    assert bool(found) == fires
    if found and source is None:
        assert "auto" in found[0].message


def test_data_texture_through_a_materialx_image_with_srgb(findings):
    extra = image("srgb_texture") + shader("g", "ND_extract_color3", "color3f inputs:in.connect = </M/img.outputs:out>",
                                           "int inputs:index = 1", "float outputs:out")
    text = openpbr("float inputs:specular_roughness.connect = </M/g.outputs:out>", extra=extra)
    assert findings(text, "OPBR504", files=("a.png",))
    assert not findings(text.replace("srgb_texture", "none"), "OPBR504", files=("a.png",))


# -- units ----------------------------------------------------------------------------------------

def test_length_without_meters_per_unit(findings):
    unauthored = HEADER.replace("    metersPerUnit = 0.01\n", "")
    (finding,) = findings(openpbr("float inputs:transmission_depth = 2", header=unauthored), "OPBR603")
    assert "0.01" in finding.message and finding.location.input == "transmission_depth"
    assert not findings(openpbr("float inputs:transmission_depth = 2"), "OPBR603")
    assert not findings(openpbr("float inputs:base_weight = 1", header=unauthored), "OPBR603")


# -- USD family -----------------------------------------------------------------------------------

def test_role_mismatch_is_reported_once_not_again_by_usd_core(findings, tmp_path):
    text = openpbr("float3 inputs:base_color = (0.5, 0.4, 0.3)")
    assert len(findings(text, "OPBR1002")) == 1
    assert not findings(text, "OPBR1010")


def test_preview_normal_declared_float3_is_not_reported(findings):
    # UsdMtlx writes float3 inputs:normal on UsdPreviewSurface; Storm reads any float3 role there
    assert findings(preview("float3 inputs:normal = (0, 0, 1)"), "OPBR1002") == []
    assert findings(preview("float3 inputs:diffuseColor = (0.5, 0.5, 0.5)"), "OPBR1002") == []


def test_preview_input_of_another_shape_is_still_reported(findings):
    assert findings(preview("float inputs:opacity = 0.5\n        double inputs:roughness = 0.5"), "OPBR1002")


def test_texture_node_without_id(findings):
    extra = shader("img", None, "asset inputs:file = @a.png@", "color3f outputs:out")
    (finding,) = findings(openpbr("color3f inputs:base_color.connect = </M/img.outputs:out>", extra=extra), "OPBR1001",
                          files=("a.png",))
    assert finding.location.path == "/M/img"


def test_unknown_ids_inside_and_outside_materialx_networks(findings):
    extra = shader("n", "ND_mystery_color3", "color3f outputs:out")
    (inside,) = findings(openpbr("color3f inputs:base_color.connect = </M/n.outputs:out>", extra=extra), "OPBR1003")
    assert inside.location.path == "/M/n" and inside.hint is None
    renderman = (f'{HEADER}def Material "M"\n{{\n    token outputs:ri:surface.connect = </M/R.outputs:out>\n'
                 + shader("R", "PxrSurface", "token outputs:out") + "}\n")
    assert not findings(renderman, "OPBR1003")


def test_float_output_into_colour_input(findings):
    extra = shader("n", "ND_noise2d_float", "float outputs:out")
    (finding,) = findings(openpbr("color3f inputs:base_color.connect = </M/n.outputs:out>", extra=extra), "OPBR1005")
    assert "float" in finding.message and finding.location.input == "base_color"


def test_normal_map_encoding_is_only_judged_for_eight_bit_images(findings):
    extra = shader("n", "UsdUVTexture", "asset inputs:file = @n.exr@", 'token inputs:sourceColorSpace = "raw"', "float3 outputs:rgb")
    assert not findings(preview("normal3f inputs:normal.connect = </M/n.outputs:rgb>", extra=extra), "OPBR1006", files=("n.exr",))


def test_opacity_threshold_with_nothing_to_cut(findings):
    (finding,) = findings(preview("float inputs:opacityThreshold = 0.5"), "OPBR1007")
    assert "cuts nothing" in finding.message


def test_metallic_ignored_in_the_specular_workflow(findings):
    (finding,) = findings(preview("int inputs:useSpecularWorkflow = 1", "float inputs:metallic = 1"), "OPBR1008")
    assert finding.location.input == "metallic"


def both(openpbr_lines, preview_lines) -> str:
    return (f'{HEADER}def Material "M"\n{{\n    token outputs:mtlx:surface.connect = </M/S.outputs:surface>\n'
            "    token outputs:surface.connect = </M/P.outputs:surface>\n"
            + shader("S", "ND_open_pbr_surface_surfaceshader", *openpbr_lines, "token outputs:surface")
            + shader("P", "UsdPreviewSurface", *preview_lines, "token outputs:surface") + "}\n")


@pytest.mark.parametrize(
    "openpbr_line, preview_line, fires",
    [
        ("float inputs:base_metalness = 1", "float inputs:metallic = 0", True),
        ("float inputs:base_metalness = 1", "float inputs:metallic = 1", False),
        ("float inputs:specular_roughness = 0.1", "float inputs:roughness = 0.7", True),
        ("float inputs:specular_roughness = 0.3", "float inputs:roughness = 0.5", False),  # both defaults-ish: 0.2 apart
        ("float inputs:geometry_opacity = 1", "float inputs:opacity = 0.2", True),
        ("color3f inputs:base_color = (0.8, 0.8, 0.8)", "color3f inputs:diffuseColor = (0.18, 0.18, 0.18)", True),
        ("color3f inputs:base_color = (0.18, 0.18, 0.18)", "color3f inputs:diffuseColor = (0.2, 0.18, 0.16)", False),
    ],
)
def test_preview_fallback_must_agree_with_openpbr(findings, openpbr_line, preview_line, fires):
    assert bool(findings(both([openpbr_line], [preview_line]), "OPBR1009")) == fires


def test_base_weight_darkens_the_colour_compared(findings):
    """0.8 grey at base_weight 0.25 is a 0.2 albedo: close to a 0.18 diffuseColor."""
    lines = ["color3f inputs:base_color = (0.8, 0.8, 0.8)", "float inputs:base_weight = 0.25"]
    assert not findings(both(lines, ["color3f inputs:diffuseColor = (0.18, 0.18, 0.18)"]), "OPBR1009")


def test_usd_core_findings_pass_through_unless_covered(findings):
    """usd-core's finding passes through at its prim and input; a value of another shape than its declaration (float3
    for UsdUVTexture's float4 scale), an error of usd-core's, is OPBR201's error (session 26's red team, D4: an OPBR1010
    warning before)."""
    extra = shader("tex", "UsdUVTexture", "asset inputs:file = @a.png@", 'token inputs:sourceColorSpace = "sRGB"',
                   "float3 inputs:scale = (1, 1, 1)", "float3 outputs:rgb")
    (finding,) = findings(preview("color3f inputs:diffuseColor.connect = </M/tex.outputs:rgb>", extra=extra), "OPBR201",
                          files=("a.png",))
    assert finding.message.startswith("usd-core") and "float4" in finding.message
    assert finding.location.path == "/M/tex" and finding.location.input == "scale"


def test_an_input_of_the_other_workflow_left_at_its_default_is_not_reported(findings):
    """UsdMtlx authors every input; specularColor (0, 0, 0) is the default and changes nothing."""
    assert not findings(preview("color3f inputs:specularColor = (0, 0, 0)"), "OPBR1035")


def test_a_specular_colour_in_the_metalness_workflow_is_only_noted(findings):
    """Exporters write specularColor beside metalness materials (usd-wg's intent-vfx teapot: (1, 1, 1)); it renders
    nothing, and the published assets that carry it are not broken: an info, not OPBR1008's warning."""
    (finding,) = findings(preview("color3f inputs:specularColor = (1, 1, 1)"), "OPBR1035")
    assert str(finding.severity) == "info"
    assert not findings(preview("color3f inputs:specularColor = (1, 1, 1)"), "OPBR1008")


def test_a_texture_read_by_two_inputs_reports_its_colour_space_once(findings):
    extra = shader("tex", "UsdUVTexture", "asset inputs:file = @a.png@", 'token inputs:sourceColorSpace = "srgb_texture"',
                   "float3 outputs:rgb", "float outputs:a")
    text = preview("color3f inputs:diffuseColor.connect = </M/tex.outputs:rgb>", "float inputs:opacity.connect = </M/tex.outputs:a>",
                   extra=extra)
    assert len(findings(text, "OPBR1004", files=("a.png",))) == 1


@pytest.mark.parametrize("scale, bias, caught", [
    ("(2, 2, 2, 1)", "(-1, -1, -1, 0)", False),    # the UsdPreviewSurface specification's decode
    ("(2, -2, 2, 1)", "(-1, 1, -1, 0)", False),     # green reversed: a DirectX-convention map, deliberately
    ("(-2, -2, 2, 1)", "(1, 1, -1, 0)", False),     # both tangent axes reversed
    ("(2, 2, 1, 1)", "(-1, -1, 0, 0)", False),      # z stored in [0, 1]
    ("(1, 1, 2, 1)", "(-0.5, -0.5, -1, 0)", False),  # a glTF normalTexture.scale of 0.5 carried on x and y
    ("(0, 0, 2, 1)", "(0, 0, -1, 0)", True),        # x and y flattened to 0: no normal map at all
    ("(1, 1, 1, 1)", "(0, 0, 0, 0)", True),         # no decode: every normal tilts to +x+y
    ("(2, 2, 2, 1)", "(-0.5, -0.5, -1, 0)", True),  # x and y onto [-0.5, 1.5]: not unit components
    ("(2, 2, -1, 1)", "(-1, -1, 0, 0)", True),      # z onto [-1, 0]: points into the surface
])
def test_normal_map_encoding_accepts_every_decode_onto_normal_components(findings, scale, bias, caught):
    extra = shader("n", "UsdUVTexture", "asset inputs:file = @n.png@", 'token inputs:sourceColorSpace = "raw"',
                   f"float4 inputs:scale = {scale}", f"float4 inputs:bias = {bias}", "float3 outputs:rgb")
    found = findings(preview("normal3f inputs:normal.connect = </M/n.outputs:rgb>", extra=extra), "OPBR1006", files=("n.png",))
    assert bool(found) is caught


def _png(channels: int, bits: int = 8, gamma: float | None = None) -> bytes:
    """A 2x2 PNG written by hand from ISO/IEC 15948 (IHDR colour types 0, 4, 2, 6; optional gAMA)."""
    import struct
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    colour_type = {1: 0, 2: 4, 3: 2, 4: 6}[channels]
    row = b"\x00" + b"\x80" * (2 * channels * bits // 8)
    header = chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, bits, colour_type, 0, 0, 0))
    gama = chunk(b"gAMA", struct.pack(">I", round(gamma * 100000))) if gamma is not None else b""
    return b"\x89PNG\r\n\x1a\n" + header + gama + chunk(b"IDAT", zlib.compress(row * 2)) + chunk(b"IEND", b"")


@pytest.mark.parametrize("channels, bits, gamma, fires", [
    (1, 8, None, False),     # greyscale: both of OpenUSD's readers read it raw under auto
    (2, 8, None, False),     # greyscale + alpha
    (3, 8, None, True),      # RGB: sRGB under auto
    (4, 8, None, True),      # RGBA
    (3, 16, None, True),     # stb reads PNGs at 8 bits, then guesses sRGB for 3 channels
    (3, 8, 1.0, False),      # gAMA 1.0: stb takes it as linear
    (1, 8, 1 / 2.2, True),   # gAMA 1/2.2: stb takes it as sRGB whatever the channels
])
def test_auto_judges_the_image_itself_as_openusd_readers_do(findings, tmp_path, channels, bits, gamma, fires):
    (tmp_path / "rough.png").write_bytes(_png(channels, bits, gamma))
    extra = shader("tex", "UsdUVTexture", "asset inputs:file = @rough.png@", "float outputs:r")
    found = findings(preview("float inputs:roughness.connect = </M/tex.outputs:r>", extra=extra), "OPBR504")
    assert bool(found) is fires


def test_hand_written_png_headers_are_what_pillow_reads(tmp_path):
    from PIL import Image

    for channels, mode in ((1, "L"), (2, "LA"), (3, "RGB"), (4, "RGBA")):
        (tmp_path / "x.png").write_bytes(_png(channels))
        with Image.open(tmp_path / "x.png") as opened:
            assert opened.mode == mode
