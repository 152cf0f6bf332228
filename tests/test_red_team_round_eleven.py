"""Session 24's red team: set X (93 unmodified published files from nine repositories no round had used: bevy,
three.js-era sample models, microsoft/glTF-SDK, bhouston/materialx.js, kwokcb/glTF_MaterialX, Unity's and
Omniverse's USD samples) and set Y (the anchors' own negative suites: the Khronos glTF-Validator's test files,
OpenUSD's usdchecker assets). Each finding here against its authority:

* X, false alarms: an empty KHR_materials_sheen/transmission/iridescence object (valid glTF the validator passes;
  MaterialX's standard_surface_to_gltf_pbr graph, baked, writes one per lobe at 0) was an OPBR1211 warning: now
  OPBR1251, an info. usd-core's MissingSourceTypeInRegistry for sourceType 'mdl' and its unresolvable 'OmniPBR.mdl'
  are facts of a usd-core without MDL, not of the file: OPBR1040. A gltf_pbr's uniform attenuation_color fed by
  MaterialX's own translation graph applied to constants (MaterialX validates and renders it) was OPBR204.
* X, messages: an SVG texture was "text, not an image"; a buffer without data was reported twice; a glTF image in
  that buffer was "not found in the package"; OPBR1233 said a browser "bends" the values of an sRGB-profiled PNG.
* Y, weaker than the anchor: a byte-order mark before glTF JSON (the validator's INVALID_JSON), a malformed data
  URI (INVALID_URI), usd-core's normal-map findings on a preview no Material output reaches. Y, wrong: one byte
  after a GLB's declared length made the file unreadable (exit 2; the validator warns, GLB_EXTRA_DATA); a
  placeholder buffer no view reads was OPBR1209 (the validator's valid_placeholder.glb).
"""

from __future__ import annotations

import json
import struct

from PIL import Image

from redteam_support import codes, findings, khronos_errors, khronos_warnings, messages, mtlx, preview_stage, report

_PNG = ("iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAEklEQVR4nGP4z8DAwMDAwMDAAAANHQEDasKb6QAAAABJRU5ErkJggg==")


def _gltf(tmp_path, document: dict, name: str = "m.gltf", prefix: bytes = b""):
    path = tmp_path / name
    path.write_bytes(prefix + json.dumps({"asset": {"version": "2.0"}, **document}).encode("utf-8"))
    return path


def _glb(document: dict, binary: bytes) -> bytes:
    text = json.dumps({"asset": {"version": "2.0"}, **document}).encode("utf-8")
    text += b" " * (-len(text) % 4)
    binary += bytes(-len(binary) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    return b"glTF" + struct.pack("<II", 2, 12 + len(chunks)) + chunks


# -- set X: published files that should stay quiet --------------------------------------------------------------

def test_an_empty_extension_object_is_a_note_not_a_warning(tmp_path):
    # KHR_materials_sheen: "If sheenColorFactor is zero, the whole sheen layer is disabled", and it defaults to 0
    path = _gltf(tmp_path, {"extensionsUsed": ["KHR_materials_sheen", "KHR_materials_transmission"],
                            "materials": [{"name": "M", "extensions": {"KHR_materials_sheen": {},
                                                                        "KHR_materials_transmission": {}}}]})
    assert "OPBR1211" not in codes(path)
    assert codes(path, ("info",)).get("OPBR1251") == 2
    assert not khronos_warnings(path, tmp_path) and not khronos_errors(path, tmp_path)  # (when the validator is set)
    # a texture without its factor still does nothing visible, and stays a warning
    textured = _gltf(tmp_path, {"extensionsUsed": ["KHR_materials_sheen"], "images": [{"uri": "data:image/png;base64,"
                                                                                              + _PNG}],
                                "textures": [{"source": 0}],
                                "materials": [{"name": "M", "extensions": {"KHR_materials_sheen": {
                                    "sheenColorTexture": {"index": 0}}}}]}, name="textured.gltf")
    assert "OPBR1251" not in codes(textured, ("info",))


_MDL_STAGE = """#usda 1.0
(
    defaultPrim = "M"
    metersPerUnit = 1
    upAxis = "Y"
)
def Material "M"
{{
    token outputs:mdl:surface.connect = </M/Shader.outputs:out>
    def Shader "Shader"
    {{
        uniform token info:implementationSource = "sourceAsset"
        uniform asset info:mdl:sourceAsset = @{module}@
        uniform token info:mdl:sourceAsset:subIdentifier = "OmniPBR"
        token outputs:out
    }}
}}
"""


def test_an_mdl_shader_is_not_blamed_for_the_machine_having_no_mdl(tmp_path):
    """usd-core on PyPI has no MDL parser (Sdr's source types: glslfx and USD), and an MDL module named without a
    folder is found on the MDL renderer's search path, never through USD's resolver."""
    from pxr import Sdr

    assert "mdl" not in Sdr.Registry().GetAllShaderNodeSourceTypes()
    core = tmp_path / "core.usda"
    core.write_text(_MDL_STAGE.format(module="OmniPBR.mdl"), encoding="utf-8")
    assert "OPBR1010" not in codes(core)
    notes = messages(core, "OPBR1040")
    assert any("MissingSourceTypeInRegistry" in m and "'mdl'" in m for m in notes)
    assert any("UnresolvableDependency" in m and "OmniPBR.mdl" in m for m in notes)
    # a module the asset names by path is the asset's to ship: still usd-core's warning
    shipped = tmp_path / "shipped.usda"
    shipped.write_text(_MDL_STAGE.format(module="./materials/Custom.mdl"), encoding="utf-8")
    assert any("Custom.mdl" in m for m in messages(shipped, "OPBR1010"))


_TRANSLATED = '''
    <nodegraph name="NG">
      <standard_surface_to_gltf_pbr name="translate" type="multioutput" nodedef="ND_standard_surface_to_gltf_pbr">
        <input name="base_color" type="color3" value="0.1, 0.6, 0.85" />
        <input name="transmission" type="float" value="0.5" />
        {transmission_color}
      </standard_surface_to_gltf_pbr>
      {image}
      <output name="attenuation_color_out" type="color3" nodename="translate" output="attenuation_color_out" />
      <output name="base_color_out" type="color3" nodename="translate" output="base_color_out" />
    </nodegraph>
    <gltf_pbr name="S" type="surfaceshader">
      <input name="base_color" type="color3" nodegraph="NG" output="base_color_out" />
      <input name="attenuation_color" type="color3" nodegraph="NG" output="attenuation_color_out" />
    </gltf_pbr>
    <surfacematerial name="M" type="material">
      <input name="surfaceshader" type="surfaceshader" nodename="S" />
    </surfacematerial>
'''


def test_a_uniform_input_fed_by_a_constant_translation_graph_is_uniform(tmp_path):
    """gltf_pbr's attenuation_color is uniform; MaterialX's ShaderTranslator connects its standard_surface_to_gltf_pbr
    graph to it. Applied to constants the graph is constant over the surface, and MaterialX validates the document
    (the anchor); fed by an image it is not, and OPBR204 stands."""
    import MaterialX as mx

    constant = mtlx(tmp_path, _TRANSLATED.format(transmission_color='<input name="transmission_color" type="color3" '
                                                                   'value="0.9, 0.5, 0.2" />', image=""),
                    name="constant.mtlx")
    document = mx.createDocument()
    mx.readFromXmlFile(document, str(constant))
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    document.importLibrary(library)
    assert document.validate()[0]
    assert "OPBR204" not in codes(constant)
    Image.new("RGB", (4, 4), (200, 120, 40)).save(tmp_path / "tint.png")
    textured = mtlx(tmp_path, _TRANSLATED.format(
        transmission_color='<input name="transmission_color" type="color3" nodename="tint" />',
        image='<image name="tint" type="color3"><input name="file" type="filename" value="tint.png" /></image>'),
        name="textured.mtlx")
    assert [f[:2] for f in findings(textured) if f[0] == "OPBR204"] == [("OPBR204", "error")]
    # the base colour output does not read the normal the translation node passes through (defaultgeomprop Nworld)
    assert messages(textured, "OPBR204")[0].startswith("attenuation_color is uniform")


def test_an_svg_texture_is_called_an_svg(tmp_path):
    (tmp_path / "checker.svg").write_text('<?xml version="1.0"?>\n<svg xmlns="http://www.w3.org/2000/svg" width="4" '
                                          'height="4"><rect width="4" height="4" fill="red"/></svg>\n', encoding="utf-8")
    path = mtlx(tmp_path, '''
        <image name="albedo" type="color3"><input name="file" type="filename" value="checker.svg" /></image>
        <open_pbr_surface name="S" type="surfaceshader">
          <input name="base_color" type="color3" nodename="albedo" />
        </open_pbr_surface>
        <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>''')
    message, = messages(path, "OPBR707")
    assert "an SVG drawing" in message and "text, not an image" not in message


def test_a_buffer_without_data_is_reported_once_and_its_image_says_why(tmp_path):
    path = _gltf(tmp_path, {"buffers": [{"byteLength": 68}], "bufferViews": [{"buffer": 0, "byteLength": 68}],
                            "images": [{"bufferView": 0, "mimeType": "image/png"}], "textures": [{"source": 0}],
                            "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]})
    assert [f[:3] for f in findings(path) if f[0] == "OPBR1209"] == [("OPBR1209", "error", "/buffers/0")]
    message, = messages(path, "OPBR701")
    assert "has no data to read" in message and "package" not in message


def test_a_placeholder_buffer_no_view_reads_is_not_broken(tmp_path):
    """The Khronos validator's own valid_placeholder.glb: a second buffer without a uri, which no bufferView names."""
    path = tmp_path / "placeholder.glb"
    path.write_bytes(_glb({"buffers": [{"byteLength": 4}, {"byteLength": 1024}]}, bytes(4)))
    assert "OPBR1209" not in codes(path)
    assert not khronos_errors(path, tmp_path)


def test_the_png_profile_message_quotes_the_specification(tmp_path):
    image = Image.new("RGB", (4, 4), (128, 128, 255))
    image.save(tmp_path / "normal.png", icc_profile=b"\0" * 128)
    path = _gltf(tmp_path, {"images": [{"uri": "normal.png"}], "textures": [{"source": 0}],
                            "materials": [{"name": "M", "normalTexture": {"index": 0}}]})
    message, = messages(path, "OPBR1233")
    # glTF 2.0, section 2: "PNG images SHOULD NOT contain ... embedded ICC profiles"
    assert "SHOULD NOT" in message and "bends" not in message


# -- set Y: the anchors' negative suites --------------------------------------------------------------------------

def test_a_byte_order_mark_before_the_json_is_an_error(tmp_path):
    # glTF 2.0: "glTF exporters MUST NOT add a byte order mark"; the Khronos validator: INVALID_JSON
    path = _gltf(tmp_path, {"materials": [{"name": "M"}]}, prefix=b"\xef\xbb\xbf")
    assert [f[:2] for f in findings(path) if f[0] == "OPBR1210"] == [("OPBR1210", "error")]
    assert "byte-order mark" in messages(path, "OPBR1210")[0]
    assert khronos_errors(path, tmp_path) in (None, {"INVALID_JSON"})
    clean = _gltf(tmp_path, {"materials": [{"name": "M"}]}, name="clean.gltf")
    assert "OPBR1210" not in codes(clean)


def test_bytes_after_a_glb_are_a_warning_not_an_unreadable_file(tmp_path):
    path = tmp_path / "extra.glb"
    path.write_bytes(_glb({"materials": [{"name": "M", "pbrMetallicRoughness": {"metallicFactor": 0.0}}]}, b"") + b"\0")
    result = report(path)
    assert result.exit_code != 2 and [m.name for m in result.materials] == ["M"] if hasattr(result, "materials") \
        else result.exit_code != 2
    assert [f[:2] for f in findings(path)] == [("OPBR1237", "warning")]
    assert "1 byte follows" in messages(path, "OPBR1237")[0]
    assert khronos_warnings(path, tmp_path) in (None, {"GLB_EXTRA_DATA"})


def test_a_malformed_data_uri_is_refused(tmp_path):
    # RFC 2397: data:[<mediatype>][;base64],<data>; the validator's INVALID_URI for ';;'
    path = _gltf(tmp_path, {"buffers": [{"byteLength": 1, "uri": "data:application/octet-stream;;base64,AA=="}],
                            "materials": [{"name": "M"}]})
    assert any("malformed" in m for m in messages(path, "OPBR1209"))
    good = _gltf(tmp_path, {"buffers": [{"byteLength": 1, "uri": "data:application/octet-stream;base64,AA=="}],
                            "materials": [{"name": "M"}]}, name="good.gltf")
    assert "OPBR1209" not in codes(good)


def test_usd_core_normal_map_findings_on_an_unwired_preview_are_kept(tmp_path):
    """OpenUSD's badNormalMapReader.usda: a UsdPreviewSurface that no Material output reaches reads an 8-bit normal
    map without raw colour space, scale and bias. The rules judge the normal maps of the surfaces they read (OPBR1006);
    usd-core's findings on this one were dropped as covered, and nothing said it."""
    Image.new("RGB", (4, 4), (128, 128, 255)).save(tmp_path / "normal.png")
    path = tmp_path / "unwired.usda"
    path.write_text("""#usda 1.0
(
    defaultPrim = "M"
    metersPerUnit = 1
    upAxis = "Y"
)
def Material "M"
{
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        normal3f inputs:normal.connect = </M/N.outputs:rgb>
        token outputs:surface
    }
    def Shader "N"
    {
        uniform token info:id = "UsdUVTexture"
        asset inputs:file = @normal.png@
        float3 outputs:rgb
    }
}
""", encoding="utf-8")
    passed = " ".join(messages(path, "OPBR1010"))
    assert "NonCompliantBiasAndScale" in passed and "InvalidSourceColorSpace" in passed
    wired = preview_stage(tmp_path, "normal3f inputs:normal.connect = </M/N.outputs:rgb>",
                          extra='    def Shader "N"\n    {\n        uniform token info:id = "UsdUVTexture"\n'
                                '        asset inputs:file = @normal.png@\n        float3 outputs:rgb\n    }\n',
                          name="wired.usda")
    assert "NonCompliantBiasAndScale" not in " ".join(messages(wired, "OPBR1010"))
    assert "OPBR1006" in codes(wired)


def test_a_texture_without_a_source_is_said_once_per_input(tmp_path):
    path = _gltf(tmp_path, {"textures": [{}], "materials": [{"name": "M", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 0}}}]})
    said = messages(path, "OPBR802")
    assert sorted(said) == sorted(set(said)) and all("has no image source" in m for m in said)
    assert not [m for m in said if "(none)" in m]


def test_a_root_variants_object_without_variants_is_invalid(tmp_path):
    # KHR_materials_variants' root schema: "variants" required, minItems 1 (the validator: UNDEFINED_PROPERTY,
    # EMPTY_ENTITY); a mapping that lists none was already OPBR1210
    for index, declared in enumerate(({}, {"variants": []})):
        path = _gltf(tmp_path, {"extensionsUsed": ["KHR_materials_variants"],
                                "extensions": {"KHR_materials_variants": declared}}, name=f"{index}.gltf")
        assert [f[:3] for f in findings(path)] == [("OPBR1210", "error", "/extensions/KHR_materials_variants")]
        assert khronos_errors(path, tmp_path) in (None, {"UNDEFINED_PROPERTY"}, {"EMPTY_ENTITY"})
    named = _gltf(tmp_path, {"extensionsUsed": ["KHR_materials_variants"],
                             "extensions": {"KHR_materials_variants": {"variants": [{"name": "red"}]}}}, name="named.gltf")
    assert "OPBR1210" not in codes(named)


def test_an_image_format_extension_on_an_image_is_out_of_place(tmp_path):
    # EXT_texture_webp extends a texture (its schema: texture.EXT_texture_webp); on an image viewers ignore it
    webp = "data:image/webp;base64,UklGRhwAAABXRUJQVlA4TA8AAAAv/8AfAAcQ/Y/+ByKi/wEA"
    misplaced = _gltf(tmp_path, {"extensionsUsed": ["EXT_texture_webp"],
                                 "images": [{"uri": webp, "extensions": {"EXT_texture_webp": {}}}]})
    assert [f[:3] for f in findings(misplaced)] == [("OPBR1210", "error", "/images/0/extensions/EXT_texture_webp")]
    assert khronos_errors(misplaced, tmp_path) in (None, {"UNEXPECTED_EXTENSION_OBJECT"})
    placed = _gltf(tmp_path, {"extensionsUsed": ["EXT_texture_webp"], "extensionsRequired": ["EXT_texture_webp"],
                              "images": [{"uri": webp}], "textures": [{"extensions": {"EXT_texture_webp": {"source": 0}}}],
                              "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]},
                   name="placed.gltf")
    assert "OPBR1210" not in codes(placed)


def _coloured_triangle(tmp_path, colours, name="colours.gltf"):
    import base64

    positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
    data = struct.pack("<9f", *positions) + struct.pack("<9f", *colours)
    return _gltf(tmp_path, {
        "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}, "material": 0}]}],
        "materials": [{"name": "M"}]}, name=name)


def test_vertex_colours_above_one_are_an_error(tmp_path):
    """glTF 2.0 (3.7.2.1): COLOR_0 multiplies the base colour; the Khronos validator calls a float colour outside
    [0, 1] an error (ACCESSOR_NON_CLAMPED), which the red team's repaired colors_non_clamped case showed passing here."""
    hot = _coloured_triangle(tmp_path, [1.0, 1.0, 1.0, 1.5, 0.0, 0.5, 0.2, 0.2, 0.2])
    (code, severity, path, attribute), = [f for f in findings(hot) if f[0] == "OPBR1231"]
    assert (severity, path, attribute) == ("error", "/meshes/0/primitives/0/attributes", "COLOR_0")
    assert "1.5, 0, 0.5" in messages(hot, "OPBR1231")[0]
    assert khronos_errors(hot, tmp_path) in (None, {"ACCESSOR_NON_CLAMPED"})
    plain = _coloured_triangle(tmp_path, [1.0, 1.0, 1.0, 1.0, 0.0, 0.5, 0.2, 0.2, 0.2], name="plain.gltf")
    assert "OPBR1231" not in codes(plain)


def test_a_lone_empty_extension_object_is_still_a_warning(tmp_path):
    """Set s17 B's glass: "KHR_materials_transmission": {} as the material's one extension (its factor never
    written: the glass renders opaque) stays OPBR1211; kwokcb's files write every extension empty (ior, specular,
    sheen, iridescence...), boilerplate for lobes at 0, and get OPBR1251."""
    glass = _gltf(tmp_path, {"extensionsUsed": ["KHR_materials_transmission"],
                             "materials": [{"name": "Glass", "pbrMetallicRoughness": {"metallicFactor": 0.0},
                                            "extensions": {"KHR_materials_transmission": {}}}]}, name="glass.gltf")
    assert codes(glass) == {"OPBR1211": 1} and "OPBR1251" not in codes(glass, ("info",))
    blanket = _gltf(tmp_path, {"extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior"],
                               "materials": [{"name": "Paint", "extensions": {"KHR_materials_transmission": {},
                                                                              "KHR_materials_ior": {}}}]},
                    name="blanket.gltf")
    assert "OPBR1211" not in codes(blanket) and codes(blanket, ("info",)).get("OPBR1251") == 1
