"""Session 23's red team, set U: one realistic defect in a real published asset (and the unmodified assets as
controls). Four misses and one false alarm, each against its authority:

* m03: a GPUOpen material's normal map swapped for its one-channel height map, read through a node graph whose
  texture coordinates are tiled by a multiply (so no input reads it as a texture): OPBR709 never saw it. The
  image's channel count is Pillow's; MaterialX's normalmap decodes three channels.
* u12: a UsdPreviewSurface diffuseColor authored float3: usd-core's ShaderSdrCompliance reports
  MismatchedPropertyType (an error there); it was dropped as covered by OPBR1002, which allows a preview's role.
  It is passed through as a note (OPBR1040): Storm reads the value whatever its role, and set W's published files
  (the USD working group's McUsd writes every normal as float3) render as authored.
* u18: a UsdTransform2d rotation of 0.3927 (22.5 degrees in radians, where the node takes degrees): OPBR719 knew
  only multiples of 15 degrees.
* uc12 (false alarm): usd-wg's intent-vfx teapot authors specularColor (1, 1, 1) in the metalness workflow, which
  renders nothing: OPBR1035 (info) now, OPBR1008's warning kept for a metallic the specular workflow ignores
  (tests/test_usd_rules.py).
"""

from __future__ import annotations

from PIL import Image

from redteam_support import findings, messages, mtlx, preview_stage, report, uv_texture

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
    # (the tiling multiply is read as the texture's UV transform since session 24, so the texture rule says it at the
    # input; a graph the reader keeps is judged by document_checks, tests/test_red_team_round_eleven_convert.py)
    assert "'height.png' is a greyscale image" in messages(broken, "OPBR709")[0]
    good = mtlx(tmp_path, _GRAPH.format(file="normal.png"), name="good.mtlx")
    assert not [f for f in findings(good) if f[0] == "OPBR709"]




def test_a_float3_preview_colour_keeps_usd_cores_finding(tmp_path):
    from pxr import Usd, UsdValidation

    path = preview_stage(tmp_path, "float3 inputs:diffuseColor = (0.8, 0.2, 0.1)", name="float3.usda")
    passed = [d for d in report(path).diagnostics if d.code == "OPBR1040"]
    assert len(passed) == 1 and "MismatchedPropertyType" in passed[0].message
    assert str(passed[0].severity) == "info" and passed[0].location.input == "diffuseColor"
    assert not [d for d in report(path).diagnostics if d.code == "OPBR1010"]
    stage = Usd.Stage.Open(str(path))  # the anchor: usd-core's own validator on the same stage
    validator = UsdValidation.ValidationRegistry().GetOrLoadValidatorByName("usdShadeValidators:ShaderSdrCompliance")
    errors = [e for prim in stage.Traverse() for e in validator.Validate(prim)]
    assert any(e.GetName() == "MismatchedPropertyType" for e in errors)
    good = preview_stage(tmp_path, "color3f inputs:diffuseColor = (0.8, 0.2, 0.1)", name="color3f.usda")
    assert not [d for d in report(good).diagnostics if d.code in ("OPBR1010", "OPBR1040")]


_ROTATOR = uv_texture("T", "albedo.png", "rgb", "float3", "float2 inputs:st.connect = </M/R.outputs:result>") + (
    '    def Shader "R"\n    {\n        uniform token info:id = "UsdTransform2d"\n'
    '        float inputs:rotation = {rotation}\n        float2 outputs:result\n    }\n')


def test_a_transform2d_rotation_of_22_5_degrees_in_radians_is_found(tmp_path):
    import math

    Image.new("RGB", (4, 4), (200, 120, 40)).save(tmp_path / "albedo.png")
    for rotation, expected in ((round(math.pi / 8, 4), True), (22.5, False), (0.5, False)):
        path = preview_stage(tmp_path, "color3f inputs:diffuseColor.connect = </M/T.outputs:rgb>",
                             extra=_ROTATOR.replace("{rotation}", str(rotation)), name=f"rotated_{rotation}.usda")
        found = messages(path, "OPBR719")
        assert bool(found) is expected, rotation
        if expected:
            assert "22.5 degrees written in radians" in found[0]


def test_a_scaled_srgb_preview_texture_is_decoded_before_its_scale(tmp_path):
    """Set T's u15 (7.2 mean CIEDE2000 against MaterialX's GLSL, unexplained in session 22): a UsdUVTexture with
    sourceColorSpace sRGB and scale 0.5 feeding emissiveColor. The UsdPreviewSurface specification decodes the
    texture (sourceColorSpace) and then applies ``value * scale + bias``, as Storm does (an sRGB texture format
    decodes at sampling; the shader scales). MaterialX's GLSL transforms the UsdUVTexture node's output instead,
    after the scale: decode(0.5 x), darker and more saturated. The conversion keeps the specification's product."""
    import glob

    import numpy as np

    image = Image.new("RGB", (4, 1))
    image.putdata([(255, 76, 51), (128, 152, 204), (10, 200, 90), (240, 240, 240)])
    image.save(tmp_path / "emit.png")
    preview_stage(tmp_path, "color3f inputs:diffuseColor = (0, 0, 0)",
                  "color3f inputs:emissiveColor.connect = </M/T.outputs:rgb>", name="emit.usda",
                  extra=uv_texture("T", "emit.png", "rgb", "float3", 'token inputs:sourceColorSpace = "sRGB"',
                                   "float4 inputs:scale = (0.5, 0.5, 0.5, 1)"))
    from openpbr_tools.convert import convert_file
    from openpbr_tools.translate.common import Settings

    convert_file(str(tmp_path / "emit.usda"), str(tmp_path / "out" / "emit.mtlx"), "open_pbr_surface", Settings())

    def decode(v):  # the sRGB transfer function (IEC 61966-2-1)
        return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)

    texels = np.asarray(image, dtype=np.float64) / 255.0
    colour = decode(np.asarray(Image.open(glob.glob(str(tmp_path / "out" / "*" / "*emission_color*"))[0]).convert("RGB"),
                               dtype=np.float64) / 255.0)
    luminance = np.asarray(Image.open(glob.glob(str(tmp_path / "out" / "*" / "*emission_luminance*"))[0]),
                           dtype=np.float64)
    luminance = luminance / (65535.0 if luminance.max() > 255 else 255.0)
    baked = colour * luminance[..., None]
    assert np.allclose(baked, 0.5 * decode(texels), atol=0.004)  # the specification's order
    assert not np.allclose(baked, decode(0.5 * texels), atol=0.02)  # MaterialX GLSL's order


# Set W (session 23): 103 published files from eleven repositories no earlier round used, unmodified. Each test below
# is one false alarm group, with the fact that makes the file good.

def test_blenders_specular_on_a_preview_is_a_note_and_a_misspelling_stays_an_error(tmp_path):
    """Blender 3.0-4.1's USD exporter writes inputs:specular on every UsdPreviewSurface (tinyusdz's test files);
    the preview's definition has no such input and readers ignore it: OPBR107 (info), not OPBR101."""
    from pxr import Sdr

    definition = Sdr.Registry().GetShaderNodeByIdentifier("UsdPreviewSurface")
    assert "specular" not in definition.GetShaderInputNames() and "roughness" in definition.GetShaderInputNames()
    found = findings_all(preview_stage(tmp_path, "float inputs:specular = 0.5"))
    assert ("OPBR107", "info") in found and not [f for f in found if f[0] == "OPBR101"]
    found = findings_all(preview_stage(tmp_path, "float inputs:roughnes = 0.5"))
    assert ("OPBR101", "error") in found


def test_stage_conventions_usd_core_calls_errors_are_notes(tmp_path):
    """A stage without metersPerUnit, upAxis or defaultPrim, and a primvar reader's varname authored as a token
    (USD 21.08's form): usd-core's validators report them; every material still binds and renders. OPBR1040."""
    from pxr import Usd, UsdValidation

    reader = '''    def Shader "uv"
    {
        uniform token info:id = "UsdPrimvarReader_float2"
        token inputs:varname = "st"
        float2 outputs:result
    }
'''
    path = preview_stage(tmp_path, "color3f inputs:diffuseColor = (0.5, 0.4, 0.3)", metadata="doc = \"\"", extra=reader)
    found = findings_all(path)
    assert not [f for f in found if f[0] == "OPBR1010"], found
    assert sum(1 for f in found if f == ("OPBR1040", "info")) >= 3  # metersPerUnit, upAxis (or defaultPrim), varname
    stage = Usd.Stage.Open(str(path))  # the anchor reports them
    registry = UsdValidation.ValidationRegistry()
    metadata = registry.GetOrLoadValidatorByName("usdGeomValidators:StageMetadataChecker").Validate(stage)
    assert any("MetersPerUnit" in str(e.GetName()) for e in metadata)
    types = registry.GetOrLoadValidatorByName("usdShadeValidators:ShaderSdrCompliance")
    assert any(e.GetName() == "MismatchedPropertyType" for e in types.Validate(stage.GetPrimAtPath("/M/uv")))


def test_a_materialx_gltf_pbr_attenuation_distance_of_zero_is_its_own_default(tmp_path):
    """KhronosGroup's glTF-MaterialX-Converter writes attenuation_distance 0 on gltf_pbr: MaterialX's nodedef
    declares it without a value, so an unset input reads 0 too. A glTF file's attenuationDistance 0 is still out of
    its schema's range (exclusiveMinimum 0)."""
    import MaterialX as mx

    document = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), document)
    declared = document.getNodeDef("ND_gltf_pbr_surfaceshader").getActiveInput("attenuation_distance")
    assert not declared.hasValueString()  # no default value: MaterialX reads 0
    path = mtlx(tmp_path, '''
        <gltf_pbr name="S" type="surfaceshader">
          <input name="attenuation_distance" type="float" value="0" />
        </gltf_pbr>
        <surfacematerial name="M" type="material">
          <input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>
        ''')
    assert not [f for f in findings(path) if f[0] == "OPBR301"]
    from openpbr_tools.convert import convert_file
    from openpbr_tools.translate.common import Settings

    conversion = convert_file(str(path), str(tmp_path / "out.gltf"), None, Settings())  # and written as glTF's absent
    assert not [d for d in conversion.diagnostics if d.code == "OPBR1104"]
    gltf = tmp_path / "volume.gltf"
    gltf.write_text('{"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_volume"], "materials": [{"name": '
                    '"M", "extensions": {"KHR_materials_volume": {"thicknessFactor": 0.1, "attenuationDistance": 0}}}]}',
                    encoding="utf-8")
    assert [f for f in findings(gltf) if f[0] == "OPBR301"]


def _glb(json_text: str, binary: bytes) -> bytes:
    import struct

    body = json_text.encode("utf-8")
    body += b" " * (-len(body) % 4)
    binary += b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<I4s", len(body), b"JSON") + body + struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def test_a_meshopt_fallback_buffer_may_have_no_uri(tmp_path):
    """EXT_meshopt_compression's README ("Fallback buffers"): a file that requires the extension may give the
    fallback buffer no URI; glTF-Transform and meshoptimizer write GLBs so (pirate.glb)."""
    import json

    def document(fallback: bool) -> str:
        extension = {"EXT_meshopt_compression": {"fallback": True}} if fallback else {}
        return json.dumps({"asset": {"version": "2.0"}, "extensionsUsed": ["EXT_meshopt_compression"],
                           "extensionsRequired": ["EXT_meshopt_compression"],
                           "buffers": [{"byteLength": 4}, {"byteLength": 64, "extensions": extension}],
                           "bufferViews": [{"buffer": 1, "byteLength": 64}],  # (read: a buffer no view reads is fine)
                           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 16, "type": "SCALAR"}],
                           "materials": [{"name": "M"}]})

    good, bad = tmp_path / "fallback.glb", tmp_path / "missing.glb"
    good.write_bytes(_glb(document(True), b"\0\0\0\0"))
    bad.write_bytes(_glb(document(False), b"\0\0\0\0"))
    assert not [f for f in findings(good) if f[0] == "OPBR1209"]
    assert [f for f in findings(bad) if f[0] == "OPBR1209"]


def test_an_arnold_volume_shader_is_another_renderers_node(tmp_path):
    """Autodesk's arnold-usd test scenes connect arnold:standard_volume to outputs:arnold:volume; usd-core's registry
    has no Arnold plugin, so its MissingShaderIdInRegistry says nothing about the asset (as for arnold:surface)."""
    volume = '''    token outputs:arnold:volume.connect = </M/V.outputs:shader>
    def Shader "V"
    {
        uniform token info:id = "arnold:standard_volume"
        token outputs:shader
    }
'''
    found = report(preview_stage(tmp_path, "color3f inputs:diffuseColor = (0.5, 0.4, 0.3)", extra=volume)).diagnostics
    assert not [d for d in found if d.code == "OPBR1010" and "arnold:standard_volume" in d.message]


def test_a_preview_reading_an_undeclared_texture_output_says_so(tmp_path):
    """arnold-usd's shading test connects diffuseColor to a UsdUVTexture's authored outputs:out, which the node does
    not declare (rgb, r, g, b, a): the message said the target does not exist, though the attribute does."""
    texture = uv_texture("T", "albedo.png", "out", "color3f")
    Image.new("RGB", (4, 4), (200, 120, 40)).save(tmp_path / "albedo.png")
    path = preview_stage(tmp_path, "color3f inputs:diffuseColor.connect = </M/T.outputs:out>", extra=texture)
    (message,) = messages(path, "OPBR802")
    assert "UsdUVTexture declares no output 'out'" in message


def findings_all(path) -> list[tuple[str, str]]:
    """(code, severity) of every finding, infos included."""
    return [(d.code, str(d.severity)) for d in report(path).diagnostics]


def test_a_preview_specular_input_in_materialx_stays_an_error(tmp_path):
    """OPBR107 is USD's: MaterialX rejects a node with an input its nodedef lacks (its validate() says so)."""
    import MaterialX as mx

    path = mtlx(tmp_path, '''
        <UsdPreviewSurface name="S" type="surfaceshader">
          <input name="specular" type="float" value="0.5" />
        </UsdPreviewSurface>
        <surfacematerial name="M" type="material">
          <input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>
        ''')
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), document)
    assert not document.validate()[0]
    assert ("OPBR101", "error") in findings_all(path) and ("OPBR107", "info") not in findings_all(path)


def test_a_16_bit_rgba_mask_is_judged_by_an_upper_bound(tmp_path):
    """Pillow decodes a 16-bit RGBA PNG to 8 bits: an alpha of 0x7FFF (0.49999) reads 127/255 (0.498). Against a
    threshold of 0.499 the 8-bit reading would cut a material Storm draws; one level of doubt is allowed."""
    import struct
    import zlib

    rows = b"".join(b"\0" + struct.pack(">HHHH", 1000, 2000, 3000, 0x7FFF) * 2 for _ in range(2))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    (tmp_path / "mask.png").write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 16, 6, 0, 0, 0))
                                        + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
    texture = uv_texture("T", "mask.png", "a", "float")
    near = preview_stage(tmp_path, "float inputs:opacity.connect = </M/T.outputs:a>", "float inputs:opacityThreshold = 0.499",
                          extra=texture)
    assert "OPBR1034" not in [f[0] for f in findings_all(near)]
    far = preview_stage(tmp_path, "float inputs:opacity.connect = </M/T.outputs:a>", "float inputs:opacityThreshold = 0.6",
                         extra=texture)
    assert "OPBR1034" in [f[0] for f in findings_all(far)]


def test_a_normal_map_scaled_whole_is_no_broken_decode(tmp_path):
    """Adobe's USD writer (set W) writes a glTF normal strength of 0.75 as scale 1.5 and bias -0.75 on all three
    channels: 0.75 (2c - 1), which normalised (Storm normalises the normal) is the unit decode. A scale on x and y
    alone bends the normals; one on all three does not. Scale 2 without the bias still maps nothing to [-1, 1]."""
    import numpy as np

    c = np.array([0.8, 0.3, 0.9])
    unit = (2 * c - 1) / np.linalg.norm(2 * c - 1)
    scaled = 1.5 * c - 0.75
    assert np.allclose(scaled / np.linalg.norm(scaled), unit)
    Image.new("RGB", (4, 4), (128, 128, 255)).save(tmp_path / "normal.png")
    texture = uv_texture("N", "normal.png", "rgb", "float3", 'token inputs:sourceColorSpace = "raw"',
                         "float4 inputs:scale = ({s}, {s}, {s}, 1)", "float4 inputs:bias = ({b}, {b}, {b}, 0)")
    whole = preview_stage(tmp_path, "normal3f inputs:normal.connect = </M/N.outputs:rgb>",
                           extra=texture.replace("{s}", "1.5").replace("{b}", "-0.75"))
    assert "OPBR1006" not in [f[0] for f in findings_all(whole)]
    unbiased = preview_stage(tmp_path, "normal3f inputs:normal.connect = </M/N.outputs:rgb>",
                              extra=texture.replace("{s}", "2").replace("{b}", "0"))
    assert "OPBR1006" in [f[0] for f in findings_all(unbiased)]
