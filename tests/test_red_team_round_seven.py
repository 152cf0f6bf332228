"""Session 20's fixes: the Khronos glTF-Validator parity audit, the published assets no one here wrote, and
the red team's round seven. Each test builds the case, asks the anchor (the Khronos validator, MaterialX,
usd-core) or quotes the spec, and checks the tool agrees."""

from __future__ import annotations

import io
import re
import json
import struct
import zlib
from pathlib import Path

import pytest
from PIL import Image

from openpbr_tools.validate import validate_file

from gltf_support import validate_many_with_khronos


def _codes(path: Path) -> dict[str, str]:
    return {d.code: str(d.severity) for d in validate_file(str(path)).diagnostics if str(d.severity) != "info"}


def _png(chunks: list[tuple[bytes, bytes]] = ()) -> bytes:
    """A 4 x 4 RGB PNG with ``chunks`` (type, payload) inserted after IHDR, CRCs as the PNG spec has them."""
    buffer = io.BytesIO()
    Image.new("RGB", (4, 4), (128, 128, 255)).save(buffer, "PNG")
    data, after_ihdr = buffer.getvalue(), 8 + 25
    extra = b"".join(struct.pack(">I", len(payload)) + kind + payload + struct.pack(">I", zlib.crc32(kind + payload))
                     for kind, payload in chunks)
    return data[:after_ihdr] + extra + data[after_ihdr:]


def _normal_mapped(tmp_path: Path, image: bytes, name: str = "n.png") -> Path:
    (tmp_path / name).write_bytes(image)
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "images": [{"uri": name}], "textures": [{"source": 0}],
                                "materials": [{"name": "M", "normalTexture": {"index": 0}}]}))
    return path


_ICC = b"sRGB\x00\x00" + zlib.compress(b"\x00" * 128)
PNG_CASES = {  # name: (chunks, whether the Khronos validator warns IMAGE_FEATURES_UNSUPPORTED)
    "icc_profile": ([(b"iCCP", _ICC)], True),
    "non_square_per_metre": ([(b"pHYs", struct.pack(">IIB", 2835, 5670, 1))], True),
    "non_square_unitless": ([(b"pHYs", struct.pack(">IIB", 1, 2, 0))], True),
    "square_pixels": ([(b"pHYs", struct.pack(">IIB", 2835, 2835, 1))], False),
    "srgb_intent": ([(b"sRGB", b"\x00")], False),
    "gamma": ([(b"gAMA", struct.pack(">I", 45455))], False),
    "plain": ([], False),
}


@pytest.fixture(scope="module")
def png_cases(tmp_path_factory):
    """Each case's glTF, and the Khronos validator's report of each (one node process for all)."""
    paths = {}
    for name, (chunks, _) in PNG_CASES.items():
        folder = tmp_path_factory.mktemp(name)
        paths[name] = _normal_mapped(folder, _png(chunks))
    reports = validate_many_with_khronos(paths.values(), tmp_path_factory.mktemp("khronos"))
    return {name: (path, reports[str(path.resolve())]) for name, path in paths.items()}


@pytest.mark.parametrize("name", PNG_CASES)
def test_png_features_glTF_says_a_png_should_not_hold(png_cases, name):
    """glTF 2.0 section 2: "PNG images SHOULD NOT contain animations, non-square pixel ratios, or embedded ICC
    profiles". The Khronos glTF-Validator warns IMAGE_FEATURES_UNSUPPORTED on the iCCP and non-square pHYs
    chunks (the red team's session-17 normal_png_with_icc_profile and png_non_square_pixels, which the tool
    passed in silence); the tool must warn wherever it does, and only there."""
    path, khronos = png_cases[name]
    warned = {m["code"] for m in khronos["issues"]["messages"] if m["severity"] == 1}
    assert ("IMAGE_FEATURES_UNSUPPORTED" in warned) == PNG_CASES[name][1]
    assert _codes(path).get("OPBR1233") == ("warning" if PNG_CASES[name][1] else None)


def test_an_animated_png_is_no_finding(tmp_path):
    """An APNG (acTL chunk): glTF 2.0 section 2 says a PNG should not hold animations and clients must ignore
    them (they show the default image). The Khronos validator says nothing, and the red team's round-five
    gg02_apng_basecolor is a good file: no finding, as the anchor."""
    frames = [Image.new("RGB", (4, 4), (50 * i, 0, 0)) for i in range(3)]
    buffer = io.BytesIO()
    frames[0].save(buffer, "PNG", save_all=True, append_images=frames[1:])
    assert b"acTL" in buffer.getvalue()
    path = _normal_mapped(tmp_path, buffer.getvalue())
    khronos = validate_many_with_khronos([path], tmp_path)[str(path.resolve())]
    assert khronos["issues"]["numWarnings"] == 0 and khronos["issues"]["numErrors"] == 0
    assert "OPBR1233" not in _codes(path)


def _packed_gltf(tmp_path: Path, pixels, material: dict, extensions=()) -> Path:
    """A glTF whose one image (an 8 x 8 RGB PNG of ``pixels``, an (8, 8, 3) array) ``material`` reads as texture 0."""
    import numpy as np

    Image.fromarray(np.asarray(pixels, dtype=np.uint8)).save(tmp_path / "packed.png")
    path = tmp_path / "m.gltf"
    document = {"asset": {"version": "2.0"}, "images": [{"uri": "packed.png"}], "textures": [{"source": 0}],
                "materials": [dict(name="M", **material)]}
    if extensions:
        document["extensionsUsed"] = list(extensions)
    path.write_text(json.dumps(document))
    return path


def _channels(red, green, blue):
    import numpy as np

    gradient = np.tile(np.linspace(0, 255, 8), (8, 1))
    mask = np.where(np.arange(64).reshape(8, 8) % 3 == 0, 255, 0)
    pick = {"gradient": gradient, "mask": mask, "zero": np.zeros((8, 8)), "mid": np.full((8, 8), 128)}
    return np.stack([pick[red], pick[green], pick[blue]], axis=-1)


_CLEARCOAT = {"extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
                                                         "clearcoatRoughnessTexture": {"index": 0}}}}
_METAL_ROUGH = {"pbrMetallicRoughness": {"metallicRoughnessTexture": {"index": 0}}}
_ORM = {"pbrMetallicRoughness": {"metallicRoughnessTexture": {"index": 0}}, "occlusionTexture": {"index": 0}}


@pytest.mark.parametrize("material, channels, expected", [
    # KHR_materials_clearcoat README: "clearcoatRoughnessTexture ... roughness ... in the G channel"
    (_CLEARCOAT, ("gradient", "zero", "zero"), "warning"),   # the red team's clearcoat_roughness_in_red
    (_CLEARCOAT, ("zero", "gradient", "zero"), None),        # where glTF reads it
    (_CLEARCOAT, ("mid", "mid", "mid"), None),               # a flat grey: nothing elsewhere either
    # glTF 2.0 3.9.2: "metalness values are sampled from the B channel. The roughness values ... G channel"
    (_METAL_ROUGH, ("mask", "gradient", "zero"), "warning"),  # metal_rough_channels_swapped: Unity's metal in R
    (_METAL_ROUGH, ("gradient", "gradient", "zero"), None),   # an ORM's occlusion gradient, unread: a dielectric
    (_ORM, ("mask", "gradient", "zero"), None),               # R is read, as occlusion
    (_METAL_ROUGH, ("zero", "gradient", "mask"), None),       # the mask where glTF reads metalness
])
def test_data_packed_in_a_channel_gltf_does_not_read(tmp_path, material, channels, expected):
    """The red team's session-17 clearcoat_roughness_in_red and metal_rough_channels_swapped, which the Khronos
    validator cannot see (it never reads texels) and the tool passed: the channel glTF reads is flat while an
    unread one holds the data."""
    extensions = ("KHR_materials_clearcoat",) if material is _CLEARCOAT else ()
    path = _packed_gltf(tmp_path, _channels(*channels), material, extensions)
    assert _codes(path).get("OPBR1234") == expected


def _sampled(tmp_path: Path, mag: int, minify: int) -> Path:
    Image.new("RGB", (4, 4), (200, 100, 50)).save(tmp_path / "b.png")
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps({
        "asset": {"version": "2.0"}, "images": [{"uri": "b.png"}],
        "samplers": [{"magFilter": mag, "minFilter": minify, "wrapS": 33071}],
        "textures": [{"source": 0, "sampler": 0}],
        "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]}))
    return path


@pytest.mark.parametrize("minify", [9728, 9729, 9984, 9985, 9986, 9987])
def test_a_gltf_samplers_min_filter_survives_gltf_to_gltf(tmp_path, minify):
    """glTF to glTF wrote minFilter NEAREST for every NEAREST magFilter (a NEAREST_MIPMAP_NEAREST pixel-art
    texture lost its mipmaps) and dropped any other minFilter, without a note. Every minFilter value of
    sampler.schema.json now comes back as it was."""
    from openpbr_tools.convert import convert_file

    for mag in (9728, 9729):
        out = tmp_path / f"out{mag}" / "m.gltf"
        convert_file(str(_sampled(tmp_path, mag, minify)), str(out))
        assert json.loads(out.read_text())["samplers"] == [{"magFilter": mag, "minFilter": minify, "wrapS": 33071,
                                                             "wrapT": 10497}]


@pytest.mark.parametrize("suffix, mag, minify, noted", [
    # MaterialX's GLTextureHandler::mapFilterTypeToGL: closest -> NEAREST_MIPMAP_NEAREST, otherwise LINEAR_MIPMAP_LINEAR
    (".mtlx", 9728, 9984, False), (".mtlx", 9729, 9987, False), (".mtlx", 9729, 9986, True), (".mtlx", 9728, 9728, True),
    # UsdUVTexture has no filter input; Storm minifies with LINEAR_MIPMAP_LINEAR
    (".usda", 9729, 9987, False), (".usda", 9728, 9984, True),
])
def test_a_min_filter_the_target_cannot_hold_is_noted(tmp_path, suffix, mag, minify, noted):
    from openpbr_tools.convert import convert_file

    conversion = convert_file(str(_sampled(tmp_path, mag, minify)), str(tmp_path / "out" / f"m{suffix}"),
                              "open_pbr_surface" if suffix == ".mtlx" else None)
    notes = [d for d in conversion.diagnostics if "minFilter" in d.message]
    assert bool(notes) == noted
    assert all(d.code == "OPBR1103" for d in notes)


# -- MaterialX: published assets no one here wrote (the tester's set P) and the red team's set I ---------------------

def _document(body: str, colorspace: str = ' colorspace="lin_rec709"') -> str:
    return f'<?xml version="1.0"?>\n<materialx version="1.39"{colorspace}>\n{body}\n</materialx>\n'


_SHADED = ('<standard_surface name="SR" type="surfaceshader">\n  {inputs}\n</standard_surface>\n'
           '<surfacematerial name="M" type="material">\n  <input name="surfaceshader" type="surfaceshader" '
           'nodename="SR" />\n</surfacematerial>')


def _mx_document(path: Path):
    import MaterialX as mx

    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    return document


@pytest.mark.parametrize("present", [False, True])
def test_an_image_behind_a_computed_texcoord_is_checked_for_its_file(tmp_path, present):
    """P's M1: every GPUOpen-library material reads its images through a texcoord -> multiply chain, which the graph
    follower does not turn into a texture; their files were never looked for (kwokcb's Canyon_Maple_Dark_Wood has
    none of its three and passed). MaterialX generates the shader either way: the file is what is missing."""
    body = ('<nodegraph name="NG">\n  <texcoord name="tc" type="vector2" />\n  <multiply name="tile" type="vector2">\n'
            '    <input name="in1" type="vector2" nodename="tc" />\n    <input name="in2" type="float" value="2" />\n'
            '  </multiply>\n  <image name="img" type="color3">\n    <input name="texcoord" type="vector2" nodename="tile" />\n'
            '    <input name="file" type="filename" value="textures/wood.png" />\n  </image>\n'
            '  <output name="out" type="color3" nodename="img" />\n</nodegraph>\n'
            + _SHADED.format(inputs='<input name="base_color" type="color3" nodegraph="NG" output="out" />'))
    path = tmp_path / "wood.mtlx"
    path.write_text(_document(body))
    if present:
        (tmp_path / "textures").mkdir()
        Image.new("RGB", (2, 2), (120, 80, 40)).save(tmp_path / "textures" / "wood.png")
    assert _mx_document(path).validate()[0]
    assert _codes(path).get("OPBR701") == (None if present else "error")


def test_a_vector_written_with_spaces_is_read_as_materialx_reads_it(tmp_path):
    """P's F1: OpenUSD's MaterialX test documents write coat_color="1 0 1"; MaterialX splits a vector on commas and
    spaces (Types.cpp, ARRAY_VALID_SEPARATORS ", ") and reads Color3(1, 0, 1), where the tool said OPBR202 "has 1
    components". A scalar still reads up to its first separator, so a decimal comma stays reported."""
    path = tmp_path / "spaces.mtlx"
    path.write_text(_document(_SHADED.format(inputs='<input name="coat_color" type="color3" value="1 0 1" />\n'
                                                    '  <input name="base" type="float" value="0,5" />')))
    document = _mx_document(path)
    shader = document.getNode("SR")
    assert tuple(shader.getInputValue("coat_color")) == (1.0, 0.0, 1.0)
    assert shader.getInputValue("base") == 0.0  # MaterialX reads 0 from "0,5"
    found = [d for d in validate_file(str(path)).diagnostics if d.code == "OPBR202"]
    assert [d.location.input for d in found] == ["base"]


def _generated_pixel_code(path: Path, target_unit: str) -> str:
    import MaterialX as mx
    import MaterialX.PyMaterialXGenGlsl as mx_glsl
    import MaterialX.PyMaterialXGenShader as mx_gen

    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    document = _mx_document(path)
    document.importLibrary(library)
    generator = mx_glsl.GlslShaderGenerator.create()
    context = mx_gen.GenContext(generator)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    units = mx_gen.UnitSystem.create(generator.getTarget())
    registry = mx.UnitConverterRegistry.create()
    distance = library.getUnitTypeDef("distance")
    registry.addUnitConverter(distance, mx.LinearUnitConverter.create(distance))
    units.loadLibrary(library)
    units.setUnitConverterRegistry(registry)
    generator.setUnitSystem(units)
    context.getOptions().targetDistanceUnit = target_unit
    return generator.generate("probe", document.getNode("SR"), context).getSourceCode(mx_gen.PIXEL_STAGE)


def test_a_dimensionless_input_written_in_a_distance_unit_is_judged_as_materialx_converts_it(tmp_path):
    """P's F2: MaterialX's own stdlib/units/standard_surface_unit.mtlx writes specular_roughness 250 millimeter; its
    shader generation (target unit metre, as its viewer and test suite run) multiplies by 0.001, so the roughness is
    0.25. The tool said OPBR301 (250 outside [0, 1]) and "its unit attribute is ignored"; it now judges 0.25 and says
    what the unit does (OPBR607, info). A value in range made tiny by a pasted unit stays OPBR604."""
    path = tmp_path / "units.mtlx"
    path.write_text(_document(_SHADED.format(
        inputs='<input name="specular_roughness" type="float" value="250" unittype="distance" unit="millimeter" />\n'
               '  <input name="coat_roughness" type="float" value="0.4" unittype="distance" unit="centimeter" />')))
    code = _generated_pixel_code(path, "meter")
    assert re.search(r"specular_roughness_unit_in2 = 0\.001", code) and re.search(r"coat_roughness_unit_in2 = 0\.01", code)
    found = {(d.code, d.location.input): str(d.severity) for d in validate_file(str(path)).diagnostics
             if d.code.startswith("OPBR3") or d.code.startswith("OPBR60")}
    assert found == {("OPBR607", "specular_roughness"): "info", ("OPBR604", "coat_roughness"): "warning"}


def test_a_colour_space_a_float_image_inherits_from_its_graph_is_no_finding(tmp_path):
    """P's F8: OpenUSD's MaterialXTextured colorspaces.mtlx puts colorspace="srgb_texture" on a node graph holding
    colour and float images; the float images inherit it and MaterialX transforms no float image (its GLSL has no
    colour transform for them). Written on the float image itself it stays OPBR507."""
    for on_image, expected in ((False, None), (True, "warning")):
        tag = ' colorspace="srgb_texture"' if on_image else ""
        body = (f'<nodegraph name="NG" colorspace="srgb_texture">\n  <image name="rough" type="float">\n'
                f'    <input name="file" type="filename" value="rough.png"{tag} />\n  </image>\n'
                '  <output name="out" type="float" nodename="rough" />\n</nodegraph>\n'
                + _SHADED.format(inputs='<input name="specular_roughness" type="float" nodegraph="NG" output="out" />'))
        path = tmp_path / f"inherit{on_image}.mtlx"
        path.write_text(_document(body))
        Image.new("L", (2, 2), 100).save(tmp_path / "rough.png")
        assert _codes(path).get("OPBR507") == expected


def test_a_specular_weight_above_one_is_no_finding(tmp_path):
    """The red team's round-seven good mg04: OpenPBR says "we also allow the specular_weight to exceed 1, thus
    increasing the reflectivity via increase of the IOR above the reference value"; its nodedef's uisoftmax 1 is a
    slider's end. An IOR far outside its soft range stays OPBR302."""
    body = ('<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_weight" type="float" value="1.4" />\n'
            '  <input name="coat_weight" type="float" value="1" />\n  <input name="coat_ior" type="float" value="15" />\n'
            '</open_pbr_surface>\n<surfacematerial name="M" type="material">\n  <input name="surfaceshader" '
            'type="surfaceshader" nodename="S" />\n</surfacematerial>')
    path = tmp_path / "weight.mtlx"
    path.write_text(_document(body))
    found = [d.location.input for d in validate_file(str(path)).diagnostics if d.code == "OPBR302"]
    assert found == ["coat_ior"]


def test_a_folder_named_on_the_command_line_is_the_tree_its_files_may_read(tmp_path):
    """P's F11/F12: MaterialX's examples read ../../../Images and usd-wg's assets ../_common; each file validated on
    its own reads nothing outside its folder and says so as information (OPBR723: the image is there), and the
    folder that holds both, named on the command line, is the tree its files may read from: no finding at all."""
    from openpbr_tools.validate import validate_paths

    (tmp_path / "Images").mkdir()
    (tmp_path / "Materials").mkdir()
    Image.new("RGB", (2, 2), (180, 140, 60)).save(tmp_path / "Images" / "brass.png")
    path = tmp_path / "Materials" / "brass.mtlx"
    body = ('<image name="albedo" type="color3">\n  <input name="file" type="filename" value="../Images/brass.png" '
            'colorspace="srgb_texture" />\n</image>\n'
            + _SHADED.format(inputs='<input name="base_color" type="color3" nodename="albedo" />'))
    path.write_text(_document(body))
    alone = {d.code: str(d.severity) for d in validate_file(str(path)).diagnostics}
    assert alone.get("OPBR723") == "info" and "OPBR704" not in alone
    tree = validate_paths([str(tmp_path)])
    assert not [d for f in tree.files for d in f.diagnostics if d.code in ("OPBR704", "OPBR723")]
    missing = path.with_name("missing.mtlx")
    missing.write_text(_document(body.replace("brass.png", "gone.png")))
    assert _codes(missing).get("OPBR704") == "warning"  # a '..' to nothing is not a shared folder


@pytest.mark.parametrize("name", ["mb02", "mb06", "mb07", "mb08", "mb14"])
def test_the_red_team_round_seven_materialx_misses(tmp_path, name):
    """Set I's MaterialX misses, each built as the red team wrote it, with the anchor's view."""
    import MaterialX as mx

    from openpbr_tools.rules import mtlx_document as rules

    rule, failing = {
        "mb02": (rules.OUTPUT_UNNAMED, rules.OUTPUT_UNNAMED.failing),
        "mb06": (rules.NORMAL_SPACE, rules.NORMAL_SPACE.failing),
        "mb07": (rules.HEXTILED_NORMAL, rules.HEXTILED_NORMAL.failing),
        "mb08": (rules.ASSIGN_BOTH, rules.ASSIGN_BOTH.failing),
        "mb14": (rules.NORMALMAP_UV_SET, rules.NORMALMAP_UV_SET.failing),
    }[name]
    Image.new("RGB", (2, 2), (128, 128, 255)).save(tmp_path / "normal.png")
    Image.new("RGB", (2, 2), (255, 100, 30)).save(tmp_path / "orm.png")
    path = tmp_path / f"{name}.mtlx"
    path.write_text(_document(failing))
    document = _mx_document(path)
    assert document.validate()[0]  # MaterialX's validate() passes every one: the tool is the only one to say it
    if name == "mb02":  # the spec requires output=; MaterialX connects the first output
        assert document.getNode("S").getInput("base_metalness").getConnectedOutput().getName() == "out_roughness"
    if name == "mb07":  # MaterialX's library has the node that rotates the vectors with the lookup
        library = mx.createDocument()
        mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
        assert library.getNodeDef("ND_hextilednormalmap_vector3") is not None
    assert _codes(path).get(rule.code) == str(rule.severity)
    clean = tmp_path / f"{name}_clean.mtlx"
    clean.write_text(_document(rule.passing))
    assert rule.code not in _codes(clean)


def _normal_document(tmp_path: Path, blue: int) -> Path:
    Image.new("RGB", (4, 4), (128, 128, blue)).save(tmp_path / f"n{blue}.png")
    body = (f'<image name="nmap" type="vector3">\n  <input name="file" type="filename" value="n{blue}.png" />\n</image>\n'
            '<normalmap name="nm" type="vector3">\n  <input name="in" type="vector3" nodename="nmap" />\n</normalmap>\n'
            + _SHADED.format(inputs='<input name="normal" type="vector3" nodename="nm" />'))
    path = tmp_path / f"n{blue}.mtlx"
    path.write_text(_document(body))
    return path


@pytest.mark.parametrize("blue, expected", [(255, None), (200, None), (20, "error"), (0, "error")])
def test_a_normal_map_whose_normals_point_into_the_surface(tmp_path, blue, expected):
    """Set I's mb04: a normal map with its blue channel inverted along with green. MaterialX's normalmap decodes a
    texel as 2 t - 1 (ND_normalmap's mx_normalmap: value * 2.0 - 1.0), so blue below one half is a negative z: the
    normal faces into the surface."""
    z = 2 * blue / 255 - 1
    assert (z < 0) == (expected is not None)
    assert _codes(_normal_document(tmp_path, blue)).get("OPBR724") == expected


@pytest.mark.parametrize("peak, expected", [(254, "error"), (65535, None), (40000, None)])
def test_a_16_bit_image_holding_8_bit_values(tmp_path, peak, expected):
    """Set I's mb12: a 16-bit greyscale PNG whose samples are 8-bit values: read over 0-65535 (Pillow's I;16 mode
    holds the samples as written), 254 is 0.0039."""
    image = Image.new("I;16", (2, 2))
    image.putdata([peak // 3, peak, peak // 2, 0])
    image.save(tmp_path / "rough.png")
    assert Image.open(tmp_path / "rough.png").mode == "I;16" and Image.open(tmp_path / "rough.png").getextrema()[1] == peak
    body = ('<image name="rough" type="float">\n  <input name="file" type="filename" value="rough.png" />\n</image>\n'
            + _SHADED.format(inputs='<input name="specular_roughness" type="float" nodename="rough" />'))
    path = tmp_path / "rough.mtlx"
    path.write_text(_document(body))
    assert _codes(path).get("OPBR725") == expected


def test_a_floating_point_bake_with_nan_and_infinite_texels_and_a_cropped_data_window(tmp_path):
    """Set I's mb03 and mb15: OpenImageIO (the anchor that reads the file) counts the non-finite samples and reports
    the data window inside the display window."""
    import numpy as np
    import OpenImageIO as oiio

    def write(name, pixels, full=None, origin=(0, 0)):
        spec = oiio.ImageSpec(pixels.shape[1], pixels.shape[0], 3, "half")
        spec.x, spec.y = origin
        if full:
            spec.full_width, spec.full_height = full
        output = oiio.ImageOutput.create(str(tmp_path / name))
        output.open(str(tmp_path / name), spec)
        output.write_image(pixels.astype(np.float32))
        output.close()

    grey = np.full((4, 4, 3), 0.5)
    broken = grey.copy()
    broken[0, 0, 0], broken[1, 1, 1] = np.nan, np.inf
    write("grey.exr", grey)
    write("broken.exr", broken)
    write("crop.exr", grey, full=(16, 16), origin=(6, 6))
    stats = oiio.ImageBufAlgo.computePixelStats(oiio.ImageBuf(str(tmp_path / "broken.exr")))
    assert sum(stats.nancount) == 1 and sum(stats.infcount) == 1
    crop = oiio.ImageInput.open(str(tmp_path / "crop.exr"))
    assert (crop.spec().width, crop.spec().full_width) == (4, 16)
    crop.close()
    for file, expected in (("grey.exr", {}), ("broken.exr", {"OPBR726": "error"}), ("crop.exr", {"OPBR727": "warning"})):
        body = (f'<image name="albedo" type="color3">\n  <input name="file" type="filename" value="{file}" '
                'colorspace="lin_rec709" />\n</image>\n'
                + _SHADED.format(inputs='<input name="base_color" type="color3" nodename="albedo" />'))
        path = tmp_path / f"{file}.mtlx"
        path.write_text(_document(body))
        found = {k: v for k, v in _codes(path).items() if k in ("OPBR726", "OPBR727")}
        assert found == expected, file


@pytest.mark.parametrize("scale, expected", [(None, "warning"), (400.0, None)])
def test_an_emission_luminance_read_from_a_mask_as_it_is(tmp_path, scale, expected):
    """Set I's mb13: a neon sign's 0-1 emission mask wired to emission_luminance, which OpenPBR gives in nits
    (cd/m^2; ND_open_pbr_surface's uisoftmax 1000): at most 1 nit. Scaled by the luminance meant, it is no finding."""
    import MaterialX as mx

    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    assert library.getNodeDef("ND_open_pbr_surface_surfaceshader").getInput("emission_luminance").getAttribute(
        "uisoftmax") == "1000.0"
    Image.new("L", (4, 4), 255).save(tmp_path / "mask.png")
    node = "mask" if scale is None else "nits"
    multiply = "" if scale is None else (f'<multiply name="nits" type="float">\n  <input name="in1" type="float" '
                                         f'nodename="mask" />\n  <input name="in2" type="float" value="{scale}" />\n</multiply>\n')
    body = ('<image name="mask" type="float">\n  <input name="file" type="filename" value="mask.png" />\n</image>\n'
            + multiply + '<open_pbr_surface name="S" type="surfaceshader">\n  <input name="emission_luminance" '
            f'type="float" nodename="{node}" />\n</open_pbr_surface>\n<surfacematerial name="M" type="material">\n'
            '  <input name="surfaceshader" type="surfaceshader" nodename="S" />\n</surfacematerial>')
    path = tmp_path / "sign.mtlx"
    path.write_text(_document(body))
    assert _codes(path).get("OPBR910") == expected


# -- the converter red team's set K ----------------------------------------------------------------------------------

_SHARED_SURFACE = """#usda 1.0
def Scope "Looks"
{
    def Material "Red"
    {
        token outputs:surface.connect = </Looks/Red/Preview.outputs:surface>
        def Shader "Preview"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor = (0.8, 0.1, 0.1)
            float inputs:roughness = 0.3
            token outputs:surface
        }
    }
    def Material "RedAlias"
    {
        token outputs:surface.connect = </Looks/Red/Preview.outputs:surface>
    }
}
"""


def test_a_material_whose_surface_is_another_materials_shader_is_converted_too(tmp_path):
    """K-03: Pixar's sphereGrid_specwf.usda points Material_39's surface at Material_19's shader; usd-core's
    ComputeSurfaceSource resolves it (Storm renders it), but the reader kept one material per shader and the
    conversion dropped the second Material without a word (99 of 100 written)."""
    from pxr import Usd, UsdShade

    from openpbr_tools.convert import convert_file

    path = tmp_path / "shared.usda"
    path.write_text(_SHARED_SURFACE)
    stage = Usd.Stage.Open(str(path))
    sources = {p: UsdShade.Material(stage.GetPrimAtPath(p)).ComputeSurfaceSource()[0].GetPath()
               for p in ("/Looks/Red", "/Looks/RedAlias")}
    assert set(map(str, sources.values())) == {"/Looks/Red/Preview"}
    assert validate_file(str(path)).materials == 2
    conversion = convert_file(str(path), str(tmp_path / "out" / "shared.mtlx"), "open_pbr_surface")
    assert sorted(m.material_name for m in conversion.materials) == ["Red", "RedAlias"]
    document = _mx_document(tmp_path / "out" / "shared.mtlx")
    assert sorted(m.getName() for m in document.getMaterialNodes()) == ["Red", "RedAlias"]


_GRAPH_NORMAL = ('<nodegraph name="NG">\n  <texcoord name="tc" type="vector2" />\n  <multiply name="tile" type="vector2">\n'
                 '    <input name="in1" type="vector2" nodename="tc" />\n    <input name="in2" type="vector2" nodename="tc" />\n'
                 '  </multiply>\n  <image name="nmap" type="vector3">\n    <input name="file" type="filename" '
                 'value="normal.png" />\n    <input name="texcoord" type="vector2" nodename="tile" />\n  </image>\n'
                 '  <normalmap name="nm" type="vector3">\n    <input name="in" type="vector3" nodename="nmap" />\n'
                 '  </normalmap>\n  <output name="out" type="vector3" nodename="nm" />\n</nodegraph>\n'
                 + _SHADED.format(inputs='<input name="normal" type="vector3" nodegraph="NG" output="out" />'))
_PREVIEW_NORMAL = ('<texcoord name="tc" type="vector2" />\n<multiply name="tile" type="vector2">\n  <input name="in1" '
                   'type="vector2" nodename="tc" />\n  <input name="in2" type="vector2" nodename="tc" />\n</multiply>\n'
                   '<image name="nmap" type="vector3">\n  <input name="file" type="filename" value="normal.png" />\n'
                   '  <input name="texcoord" type="vector2" nodename="tile" />\n</image>\n<multiply name="n2" '
                   'type="vector3">\n  <input name="in1" type="vector3" nodename="nmap" />\n  <input name="in2" '
                   'type="float" value="2" />\n</multiply>\n<subtract name="n1" type="vector3">\n  <input name="in1" '
                   'type="vector3" nodename="n2" />\n  <input name="in2" type="float" value="1" />\n</subtract>\n'
                   '<UsdPreviewSurface name="SR" type="surfaceshader">\n  <input name="normal" type="vector3" '
                   'nodename="n1" />\n</UsdPreviewSurface>\n<surfacematerial name="M" type="material">\n  <input '
                   'name="surfaceshader" type="surfaceshader" nodename="SR" />\n</surfacematerial>')


def _upstream_categories(document, shader_category: str, input_name: str) -> list[str]:
    shader = next(n for n in document.getNodes() if n.getCategory() == shader_category)
    found, node = [], shader.getInput(input_name).getConnectedNode()
    while node is not None and len(found) < 8:
        found.append(node.getCategory())
        port = node.getInput("in1") or node.getInput("in")
        node = port.getConnectedNode() if port is not None else None
    return found


def test_a_normal_graph_goes_to_the_preview_surface_in_tangent_space(tmp_path):
    """K-01: a GPUOpen wood's normal map behind a computed texcoord (a kept graph ending in normalmap, a world-space
    normal) was wired into UsdPreviewSurface's normal, which takes a tangent-space vector in [-1, 1] and applies its
    own normalmap (MaterialX's NG_UsdPreviewSurface: normal * 0.5 + 0.5 into normalmap): decoded twice, 7.5 mean
    CIEDE2000 in MaterialX's renderer where MaterialX's chain gave 0.41. Now the normalmap's input, t * 2 - 1
    (0.41 there too)."""
    from openpbr_tools.convert import convert_file

    import MaterialX as mx

    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    nodes = [n.getCategory() for n in library.getNodeGraph("IMP_UsdPreviewSurface_surfaceshader").getNodes()]
    assert "normalmap" in nodes  # the preview decodes its normal input itself
    Image.new("RGB", (4, 4), (150, 110, 240)).save(tmp_path / "normal.png")
    source = tmp_path / "wood.mtlx"
    source.write_text(_document(_GRAPH_NORMAL))
    conversion = convert_file(str(source), str(tmp_path / "out" / "wood.mtlx"), "UsdPreviewSurface")
    document = _mx_document(tmp_path / "out" / "wood.mtlx")
    assert document.validate()[0]
    assert _upstream_categories(document, "UsdPreviewSurface", "normal")[:3] == ["subtract", "multiply", "image"]
    assert any(d.code == "OPBR1102" and "tangent-space" in d.message for d in conversion.diagnostics)


def test_a_preview_surfaces_tangent_space_normal_graph_is_decoded_for_openpbr(tmp_path):
    """K-07: a UsdPreviewSurface's normal graph (texel * 2 - 1, tangent space) was copied into OpenPBR's
    geometry_normal, a world-space vector, without a note: 12.4 mean CIEDE2000 in MaterialX's renderer. Now decoded
    as MaterialX's own NG_UsdPreviewSurface does (x * 0.5 + 0.5 into a normalmap): 0.22."""
    from openpbr_tools.convert import convert_file

    Image.new("RGB", (4, 4), (150, 110, 240)).save(tmp_path / "normal.png")
    source = tmp_path / "preview.mtlx"
    source.write_text(_document(_PREVIEW_NORMAL))
    conversion = convert_file(str(source), str(tmp_path / "out" / "preview.mtlx"), "open_pbr_surface")
    document = _mx_document(tmp_path / "out" / "preview.mtlx")
    assert document.validate()[0]
    assert _upstream_categories(document, "open_pbr_surface", "geometry_normal")[:3] == ["normalmap", "add", "multiply"]
    assert any(d.code == "OPBR1102" and "normalmap" in d.message for d in conversion.diagnostics)


def test_a_tiledimages_real_world_sizes_survive_as_its_tiling(tmp_path):
    """K-02: MaterialX's TestSuite normalmapped_surfaceshader tiles by uvtiling (12, 10) with realworldimagesize
    (1, 2) cm and realworldtilesize (3, 2) cm; NG_tiledimage computes ((uv * uvtiling - uvoffset) /
    realworldimagesize) * realworldtilesize, so the texture repeats 36 x 10 times. The conversion kept (12, 10) and
    dropped both sizes without a note; the tiling now carries their ratio."""
    import MaterialX as mx

    from openpbr_tools.convert import convert_file

    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    graph = library.getNodeGraph("NG_tiledimage_color3")
    steps = [(n.getCategory(), [i.getInterfaceName() for i in n.getInputs() if i.getInterfaceName()])
             for n in graph.getNodes() if n.getCategory() in ("multiply", "subtract", "divide")]
    assert ("divide", ["realworldimagesize"]) in steps and ("multiply", ["realworldtilesize"]) in steps
    Image.new("RGB", (4, 4), (200, 120, 40)).save(tmp_path / "wood.png")
    body = ('<tiledimage name="tiled" type="color3">\n  <input name="file" type="filename" value="wood.png" />\n'
            '  <input name="uvtiling" type="vector2" value="12, 10" />\n  <input name="realworldimagesize" '
            'type="vector2" value="1.0, 2.0" unit="centimeter" unittype="distance" />\n  <input name="realworldtilesize" '
            'type="vector2" value="3.0, 2.0" unit="centimeter" unittype="distance" />\n</tiledimage>\n'
            + _SHADED.format(inputs='<input name="base_color" type="color3" nodename="tiled" />'))
    source = tmp_path / "tiled.mtlx"
    source.write_text(_document(body))
    convert_file(str(source), str(tmp_path / "out" / "tiled.mtlx"), "open_pbr_surface")
    document = _mx_document(tmp_path / "out" / "tiled.mtlx")
    [tiled] = [n for n in document.getNodes() if n.getCategory() == "tiledimage"]
    assert tuple(tiled.getInputValue("uvtiling")) == pytest.approx((36.0, 10.0))


@pytest.mark.parametrize("anisotropy, noted", [(0.5, True), (0.0, False)])
def test_a_coat_roughness_rescaled_for_anisotropy_is_noted(tmp_path, anisotropy, noted):
    """K-06: Standard Surface's coat_anisotropy 0.5 changed coat_roughness 0.2 to 0.2115 in OpenPBR (the models
    split alpha differently) with no note, where the specular_roughness twin was noted. Without anisotropy the value
    is carried as it is, and nothing is said."""
    from openpbr_tools.convert import convert_file

    source = tmp_path / "coat.mtlx"
    source.write_text(_document(_SHADED.format(
        inputs=f'<input name="coat" type="float" value="1" />\n  <input name="coat_roughness" type="float" value="0.2" />\n'
               f'  <input name="coat_anisotropy" type="float" value="{anisotropy}" />')))
    conversion = convert_file(str(source), str(tmp_path / "out" / "coat.mtlx"), "open_pbr_surface")
    [material] = conversion.materials
    changed = abs(material.inputs["coat_roughness"].value.value - 0.2) > 1e-9
    assert changed == noted
    assert any("coat_roughness: roughness rescaled" in d.message for d in conversion.diagnostics) == noted


def test_no_note_speaks_of_a_source_gltf_the_material_did_not_come_from(tmp_path):
    """K-05: PhysicallyBased's Standard Surface soap bubble converted to glTF was told its thickness was "the source
    glTF's volume thickness", a note meant for materials that came from glTF."""
    from openpbr_tools.convert import convert_file

    source = tmp_path / "bubble.mtlx"
    source.write_text(_document(_SHADED.format(
        inputs='<input name="transmission" type="float" value="1" />\n  <input name="thin_film_thickness" type="float" '
               'value="500" />')))  # (solid, no transmission depth: glTF gets a thickness of one scene unit)
    conversion = convert_file(str(source), str(tmp_path / "out" / "bubble.gltf"))
    assert not [d for d in conversion.diagnostics if "source glTF" in d.message]


_LOOKS = """#usda 1.0
def Scope "Looks"
{
    def Material "M_car"
    {
        token outputs:surface.connect = </Looks/M_car/S.outputs:surface>
        def Shader "S"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor = (0.6, 0.1, 0.1)
            token outputs:surface
        }
    }
}
"""
_VEHICLE = """#usda 1.0
(
    defaultPrim = "Car"
    metersPerUnit = 1
    upAxis = "Y"
)
def Xform "Car"
{
    def Scope "Looks" (
        references = @../materials/looks.usda@</Looks>
    )
    {
    }
    def Mesh "Body" (
        prepend apiSchemas = ["MaterialBindingAPI"]
    )
    {
        rel material:binding = </Car/Looks/M_car>
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 1, 2]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
    }
}
"""


def test_a_usd_arc_into_a_shared_folder_is_information_and_what_it_brings_is_not_called_missing(tmp_path):
    """P's F11 and F13: usd-wg's Vehicles kit references ../materials/... and binds the materials it brings; each file
    validated on its own got an OPBR1011 error per arc (1,939 across usd-wg) and an OPBR1017 error per binding to a
    material the unopened layer holds. usd-core composes and binds them (the anchor). Now: OPBR1039, an info, no
    OPBR1017, and the folder that holds both, validated, reads the material."""
    from pxr import Usd, UsdShade

    from openpbr_tools.validate import validate_paths

    (tmp_path / "materials").mkdir()
    (tmp_path / "vehicles").mkdir()
    (tmp_path / "materials" / "looks.usda").write_text(_LOOKS)
    path = tmp_path / "vehicles" / "car.usda"
    path.write_text(_VEHICLE)
    alone = {d.code: str(d.severity) for d in validate_file(str(path)).diagnostics}
    assert alone.get("OPBR1039") == "info" and "OPBR1011" not in alone and "OPBR1017" not in alone
    tree = validate_paths([str(tmp_path)])
    assert not [d for d in tree.diagnostics if d.code in ("OPBR1011", "OPBR1039", "OPBR1017")]
    assert sum(f.materials for f in tree.files if f.path.endswith("car.usda")) >= 1
    copy = tmp_path / "vehicles" / "anchor.usda"  # (a copy: a layer usd-core holds open is not read again safely)
    copy.write_text(_VEHICLE)
    stage = Usd.Stage.Open(str(copy))
    bound, _ = UsdShade.MaterialBindingAPI(stage.GetPrimAtPath("/Car/Body")).ComputeBoundMaterial()
    assert bound and str(bound.GetPath()) == "/Car/Looks/M_car"
    copy.unlink()
    (tmp_path / "materials" / "looks.usda").unlink()
    assert _codes(path).get("OPBR1011") == "error" or "OPBR002" in _codes(path)  # a '..' to nothing stays a defect


@pytest.mark.parametrize("mode, expected", [("L", "error"), ("I;16", None)])
def test_a_greyscale_metallic_roughness_texture(tmp_path, mode, expected):
    """Set I's gb05 (an 8-bit roughness map dropped in the packed slot: metalness equals roughness) is OPBR1238; a
    16-bit greyscale one, which glTF 3.9.2 allows ("MAY use more than 8 bits per channel") and the red team's
    round-one good core_16bit_grayscale_metal_rough uses, is a deliberate precision export: no finding."""
    image = Image.new(mode, (4, 4))
    image.putdata([120 if mode == "L" else 30000] * 16)
    image.save(tmp_path / "mr.png")
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "images": [{"uri": "mr.png"}], "textures": [{"source": 0}],
                                "materials": [{"name": "M", "pbrMetallicRoughness": {
                                    "metallicRoughnessTexture": {"index": 0}}}]}))
    assert _codes(path).get("OPBR1238") == expected
