"""Session 20's fixes: the Khronos glTF-Validator parity audit, the published assets no one here wrote, and
the red team's round seven. Each test builds the case, asks the anchor (the Khronos validator, MaterialX,
usd-core) or quotes the spec, and checks the tool agrees."""

from __future__ import annotations

import io
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
