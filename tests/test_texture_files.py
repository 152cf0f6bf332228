"""Texture files that exist but are no readable image (OPBR707/OPBR708) and greyscale images in a
normal slot (OPBR709), in every input format, and what `convert` does with them.

The expected verdicts come from outside the code under test: OpenImageIO (the image library
MaterialX's renderers and most VFX pipelines load textures with) fails to read each damaged PNG,
and the Khronos glTF-Validator's image findings (IMAGE_UNRECOGNIZED_FORMAT, IMAGE_UNEXPECTED_EOS)
are each matched here at the same image with at least the same severity.
"""

from __future__ import annotations

import io
import json
import random
import struct
import zlib

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image

from openpbr_tools.convert import convert_file
from openpbr_tools.diagnostics import Severity
from openpbr_tools.io.image_files import damage
from openpbr_tools.translate.common import Settings
from openpbr_tools.validate import Options, validate_paths

from gltf_support import describe_issues, validate_with_khronos


def _noise_png() -> bytes:
    generator = random.Random(3)
    buffer = io.BytesIO()
    Image.frombytes("RGB", (64, 64), bytes(generator.randrange(256) for _ in range(64 * 64 * 3))).save(buffer, "PNG")
    return buffer.getvalue()


def _noise_jpeg() -> bytes:
    buffer = io.BytesIO()
    Image.open(io.BytesIO(_noise_png())).save(buffer, "JPEG", quality=90)
    return buffer.getvalue()


def _flip_in_idat(png: bytes) -> bytes:
    """One bit flipped inside the IDAT data, its CRC left as it was (what a bad disk or transfer does)."""
    at = png.index(b"IDAT") + 20
    return png[:at] + bytes([png[at] ^ 0x10]) + png[at + 1:]


PNG, JPEG = _noise_png(), _noise_jpeg()
LFS = b"version https://git-lfs.github.com/spec/v1\noid sha256:" + b"0" * 64 + b"\nsize 4096\n"

#: name -> (bytes, the expected Damage kind or None)
VARIANTS = {
    "png": (PNG, None),
    "jpeg": (JPEG, None),
    "jpeg with bytes after its end": (JPEG + b"\0" * 64, None),
    "png without IEND": (PNG[:-12], None),  # decoders show it whole (libpng, Pillow, OpenImageIO)
    "png cut in its signature": (PNG[:6], "corrupt"),
    "png cut in IHDR": (PNG[:30], "corrupt"),
    "png cut in IDAT": (PNG[:len(PNG) // 2], "corrupt"),
    "png with a flipped bit": (_flip_in_idat(PNG), "corrupt"),
    "jpeg cut in its scan": (JPEG[:len(JPEG) // 2], "corrupt"),
    "empty": (b"", "empty"),
    "git lfs pointer": (LFS, "text"),
    "html page": (b"<!DOCTYPE html>\n<html><body>404 Not Found</body></html>\n", "text"),
    "random bytes": (bytes(random.Random(5).randrange(256) for _ in range(900)), "unrecognised"),
}


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_damage_of_each_variant_from_a_file_and_from_bytes(tmp_path, name):
    data, expected = VARIANTS[name]
    path = tmp_path / "image.bin"
    path.write_bytes(data)
    found = damage(str(path))
    assert (found.kind if found else None) == expected, found
    assert damage(data) == found and damage(memoryview(data)) == found


def test_openimageio_fails_on_every_png_reported_corrupt_and_reads_every_png_passed(tmp_path):
    """The anchor: OpenImageIO reads the whole image (pixels included); where it fails, the PNG is corrupt."""
    oiio = pytest.importorskip("OpenImageIO")
    checked = 0
    for name, (data, expected) in VARIANTS.items():
        if not name.startswith("png"):
            continue
        path = tmp_path / f"{name.replace(' ', '_')}.png"
        path.write_bytes(data)
        buffer = oiio.ImageBuf(str(path))
        readable = not buffer.has_error and buffer.get_pixels(oiio.FLOAT) is not None and not buffer.has_error
        assert readable == (expected is None), name
        checked += 1
    assert checked == 6


def test_other_formats_are_judged_by_their_header(tmp_path):
    oiio = pytest.importorskip("OpenImageIO")
    path = str(tmp_path / "a.exr")
    buffer = oiio.ImageBuf(oiio.ImageSpec(4, 4, 3, oiio.HALF))
    assert buffer.write(path)
    assert damage(path) is None
    with open(path, "rb") as handle:
        exr = handle.read()
    assert damage(exr[:40]) is None  # an EXR signature is trusted: OpenEXR is not decoded here
    for signature in (b"\xabKTX 20\xbb\r\n\x1a\n", b"#?RADIANCE\n", b"\x00\x00\x00\x1cftypavif"):
        assert damage(signature + b"\x01" * 64) is None, signature


KHRONOS_CODES = {"IMAGE_UNRECOGNIZED_FORMAT", "IMAGE_UNEXPECTED_EOS", "IMAGE_DATA_INVALID", "IMAGE_MIME_TYPE_INVALID"}


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_every_image_finding_of_the_khronos_validator_is_one_here(tmp_path, name):
    """Never weaker than the anchor: an image the validator reports (error or warning) is reported
    here at /images/0 at least as severely. The validator reads headers only, so the files cut after
    their header are reported here alone."""
    data, expected = VARIANTS[name]
    suffix = ".jpg" if name.startswith("jpeg") else ".png"
    (tmp_path / f"t{suffix}").write_bytes(data)
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "images": [{"uri": f"t{suffix}"}], "textures": [{"source": 0}],
                                "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]}))
    report = validate_with_khronos(path, tmp_path)
    theirs = [m for m in report["issues"]["messages"] if m["code"] in KHRONOS_CODES]
    ours = [d for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics
            if d.code in ("OPBR707", "OPBR708")]
    assert bool(ours) == (expected is not None), [d.message for d in ours]
    for message in theirs:
        assert any(d.location.path == message["pointer"] and d.severity >= (Severity.ERROR if message["severity"] == 0 else Severity.WARNING) for d in ours), \
            describe_issues(report)
    if ours:
        [finding] = ours
        assert finding.location.path == "/images/0"
        assert finding.code == ("OPBR708" if expected == "unrecognised" else "OPBR707")


def _codes(path) -> list[str]:
    return [d.code for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics]


MTLX = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="albedo" type="color3"><input name="file" type="filename" value="{file}" colorspace="srgb_texture" /></image>
  <open_pbr_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="albedo" /></open_pbr_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
</materialx>
"""


def test_a_damaged_udim_tile_is_found_among_good_ones(tmp_path):
    for tile in (1001, 1002, 1003):
        (tmp_path / f"paint.{tile}.png").write_bytes(PNG if tile != 1002 else PNG[:len(PNG) // 3])
    path = tmp_path / "m.mtlx"
    path.write_text(MTLX.format(file="paint.<UDIM>.png"))
    [finding] = [d for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics if d.code == "OPBR707"]
    assert "paint.1002.png" in finding.message


def test_a_file_outside_the_asset_is_never_opened_to_be_judged(tmp_path):
    (tmp_path / "shared").mkdir()
    (tmp_path / "shared" / "a.png").write_bytes(LFS)
    (tmp_path / "asset").mkdir()
    path = tmp_path / "asset" / "m.mtlx"
    path.write_text(MTLX.format(file="../shared/a.png"))
    codes = _codes(path)
    # a '..' to a file that is there: a shared folder (OPBR723), the file not opened, so not judged (OPBR707)
    assert "OPBR723" in codes and "OPBR707" not in codes


USDA = """#usda 1.0
(
    metersPerUnit = 1
    upAxis = "Y"
)

def Material "M"
{{
    token outputs:surface.connect = </M/S.outputs:surface>

    def Shader "S"
    {{
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor.connect = </M/albedo.outputs:rgb>
        normal3f inputs:normal.connect = </M/bump.outputs:rgb>
        token outputs:surface
    }}

    def Shader "albedo"
    {{
        uniform token info:id = "UsdUVTexture"
        asset inputs:file = @{albedo}@
        token inputs:sourceColorSpace = "sRGB"
        float3 outputs:rgb
    }}

    def Shader "bump"
    {{
        uniform token info:id = "UsdUVTexture"
        asset inputs:file = @{normal}@
        token inputs:sourceColorSpace = "raw"
        float4 inputs:scale = (2, 2, 2, 1)
        float4 inputs:bias = (-1, -1, -1, 0)
        float3 outputs:rgb
    }}
}}
"""


def _grey_png() -> bytes:
    buffer = io.BytesIO()
    Image.new("L", (4, 4), 128).save(buffer, "PNG")
    return buffer.getvalue()


def test_usd_and_usdz_textures_are_judged_inside_the_package_too(tmp_path):
    from pxr import UsdUtils

    (tmp_path / "albedo.png").write_bytes(PNG[:100])
    (tmp_path / "height.png").write_bytes(_grey_png())
    layer = tmp_path / "m.usda"
    layer.write_text(USDA.format(albedo="albedo.png", normal="height.png"))
    assert sorted(c for c in _codes(layer) if c.startswith("OPBR70")) == ["OPBR707", "OPBR709"]
    package = tmp_path / "m.usdz"
    assert UsdUtils.CreateNewUsdzPackage(str(layer), str(package))
    (tmp_path / "albedo.png").unlink()
    (tmp_path / "height.png").unlink()
    assert sorted(c for c in _codes(package) if c.startswith("OPBR70")) == ["OPBR707", "OPBR709"]


def test_a_greyscale_normal_map_is_reported_in_materialx_and_an_rgb_one_is_not(tmp_path):
    body = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <image name="n" type="vector3"><input name="file" type="filename" value="{file}" /></image>
  <normalmap name="decode" type="vector3"><input name="in" type="vector3" nodename="n" /></normalmap>
  <open_pbr_surface name="S" type="surfaceshader"><input name="geometry_normal" type="vector3" nodename="decode" /></open_pbr_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
</materialx>
"""
    (tmp_path / "grey.png").write_bytes(_grey_png())
    buffer = io.BytesIO()
    Image.new("LA", (4, 4), (128, 255)).save(buffer, "PNG")
    (tmp_path / "grey_alpha.png").write_bytes(buffer.getvalue())
    (tmp_path / "rgb.png").write_bytes(PNG)
    for file, reported in (("grey.png", True), ("grey_alpha.png", True), ("rgb.png", False)):
        path = tmp_path / f"{file}.mtlx"
        path.write_text(body.format(file=file))
        assert ("OPBR709" in _codes(path)) == reported, file


def test_damaged_embedded_images_used_or_not_are_reported_at_the_image(tmp_path):
    half = len(JPEG) // 2
    binary = JPEG[:half] + b"\0" * (-half % 4)  # (the PNG's view starts 4-byte aligned, as GLB chunks must end)
    document = {"asset": {"version": "2.0"}, "buffers": [{"byteLength": len(binary) + len(PNG) + (-len(PNG) % 4)}],
                "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": half},
                                {"buffer": 0, "byteOffset": len(binary), "byteLength": len(PNG)}],
                "images": [{"bufferView": 0, "mimeType": "image/jpeg"}, {"bufferView": 1, "mimeType": "image/png"}],
                "textures": [{"source": 1}],
                "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]}
    binary += PNG + b"\0" * (-len(PNG) % 4)

    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    path = tmp_path / "m.glb"
    path.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks)
    found = [(d.code, d.location.path) for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics
             if d.code in ("OPBR707", "OPBR708", "OPBR1209")]
    assert found == [("OPBR707", "/images/0")]  # unused, cut short; the PNG material image is whole


@pytest.mark.parametrize("target", ["out.gltf", "out.glb", "out.usdz"])
def test_convert_leaves_a_damaged_texture_out_with_a_note_and_goes_on(tmp_path, target):
    (tmp_path / "albedo.png").write_bytes(LFS)
    source = tmp_path / "m.mtlx"
    source.write_text(MTLX.format(file="albedo.png"))
    conversion = convert_file(str(source), str(tmp_path / target), None, Settings())
    notes = [d for d in conversion.diagnostics if d.code == "OPBR1104"]
    assert notes and all("Git LFS pointer" in d.message for d in notes), [d.message for d in conversion.diagnostics]
    assert all(d.location.input == "base_color" for d in notes)
    written = (tmp_path / target).read_bytes()
    assert LFS not in written  # neither embedded nor packaged


def test_convert_leaves_out_an_openexr_cut_short_with_a_note_and_prints_nothing(tmp_path, capfd):
    """OpenImageIO reads an OpenEXR cut short with its missing chunks as garbage and, left unasked, prints its
    error to stderr when the buffer is destroyed: the texture is left out with a note instead."""
    oiio = pytest.importorskip("OpenImageIO")
    buffer = oiio.ImageBuf(oiio.ImageSpec(64, 64, 3, oiio.HALF))
    oiio.ImageBufAlgo.fill(buffer, (0.5, 0.2, 0.1))
    assert buffer.write(str(tmp_path / "whole.exr"))
    data = (tmp_path / "whole.exr").read_bytes()
    (tmp_path / "albedo.exr").write_bytes(data[:len(data) // 2])
    source = tmp_path / "m.mtlx"
    source.write_text(MTLX.format(file="albedo.exr"))
    conversion = convert_file(str(source), str(tmp_path / "out.gltf"), None, Settings())
    [note] = [d for d in conversion.diagnostics if d.code == "OPBR1104"]
    assert note.location.input == "base_color" and "\n" not in note.message and "albedo.exr" in note.message
    document = json.loads((tmp_path / "out.gltf").read_text())
    assert "images" not in document and "baseColorTexture" not in json.dumps(document)
    captured = capfd.readouterr()
    assert captured.err == "" and captured.out == ""


# -- found in review: the path guard, special files, and files renderers read that Pillow does not ----------

def _codes_of(path) -> list[str]:
    return [d.code for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics]


def test_a_udim_tile_linked_outside_the_asset_is_reported_and_never_opened(tmp_path):
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "secret.png").write_bytes(LFS)  # read, it would be OPBR707
    (tmp_path / "asset").mkdir()
    (tmp_path / "asset" / "paint.1001.png").write_bytes(PNG)
    (tmp_path / "asset" / "paint.1002.png").symlink_to(tmp_path / "outside" / "secret.png")
    path = tmp_path / "asset" / "m.mtlx"
    path.write_text(MTLX.format(file="paint.<UDIM>.png"))
    findings = [d for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics]
    assert "OPBR707" not in [d.code for d in findings]
    [outside] = [d for d in findings if d.code == "OPBR704"]
    assert "paint.1002.png" in outside.message


def test_dot_dot_after_a_symbolic_link_is_resolved_as_the_system_opens_it(tmp_path):
    """``link/../../x.png`` with link -> a/b names asset/x.png to the operating system (links first), but
    ../x.png to a path joined as text: the file outside is never opened."""
    (tmp_path / "x.png").write_bytes(LFS)
    (tmp_path / "asset" / "a" / "b").mkdir(parents=True)
    (tmp_path / "asset" / "link").symlink_to(tmp_path / "asset" / "a" / "b")
    path = tmp_path / "asset" / "m.mtlx"
    path.write_text(MTLX.format(file="link/../../x.png"))
    assert "OPBR707" not in _codes_of(path)


def test_a_named_pipe_as_texture_is_never_read(tmp_path):
    import os
    import signal

    os.mkfifo(tmp_path / "albedo.png")
    path = tmp_path / "m.mtlx"
    path.write_text(MTLX.format(file="albedo.png"))

    def expire(signum, frame):
        raise TimeoutError("validate blocked reading a FIFO")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.alarm(20)
    try:
        codes = _codes_of(path)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    assert "OPBR707" not in codes and damage(str(tmp_path / "albedo.png")) is None


def test_a_multi_picture_jpeg_from_a_camera_is_a_jpeg(tmp_path):
    """Pillow calls a JPEG with an MPF second picture 'MPO'; glTF viewers and MaterialX read it as the JPEG it is."""
    first, second = Image.open(io.BytesIO(JPEG)).convert("RGB"), Image.new("RGB", (64, 64), (9, 9, 9))
    first.save(tmp_path / "t.jpg", "MPO", save_all=True, append_images=[second])
    with Image.open(tmp_path / "t.jpg") as written:
        assert written.format == "MPO"
    path = tmp_path / "m.gltf"
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "images": [{"uri": "t.jpg", "mimeType": "image/jpeg"}],
                                "textures": [{"source": 0}],
                                "materials": [{"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]}))
    assert not {"OPBR707", "OPBR708", "OPBR1207", "OPBR1214"} & set(_codes_of(path))


def _chunk(kind: bytes, data: bytes, crc_delta: int = 0) -> bytes:
    crc = (zlib.crc32(kind + data) + crc_delta) & 0xFFFFFFFF
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)


def test_png_crcs_are_judged_as_libpng_judges_them(tmp_path):
    """libpng (through OpenImageIO, as renderers read PNGs) drops an ancillary chunk whose CRC fails and
    refuses image data whose CRC fails; Pillow refuses the first and decodes the second."""
    pytest.importorskip("OpenImageIO")
    at = PNG.index(b"IDAT") - 4
    text_bad = PNG[:at] + _chunk(b"tEXt", b"Comment\x00made here", crc_delta=1) + PNG[at:]
    crc_at = at + 8 + struct.unpack(">I", PNG[at:at + 4])[0]
    idat_bad = PNG[:crc_at] + bytes([PNG[crc_at] ^ 0x01]) + PNG[crc_at + 1:]
    for data, expected in ((text_bad, None), (idat_bad, "corrupt")):
        (tmp_path / "t.png").write_bytes(data)
        for found in (damage(str(tmp_path / "t.png")), damage(data)):
            assert (found.kind if found else None) == expected


@pytest.mark.parametrize("name", ["t.iff", "t.pfm"])
def test_formats_openimageio_reads_are_not_unrecognised(tmp_path, name):
    oiio = pytest.importorskip("OpenImageIO")
    buffer = oiio.ImageBuf(oiio.ImageSpec(4, 4, 3, oiio.FLOAT if name.endswith(".pfm") else oiio.UINT8))
    oiio.ImageBufAlgo.fill(buffer, (0.5, 0.25, 0.125))
    assert buffer.write(str(tmp_path / name)), oiio.geterror()
    assert damage(str(tmp_path / name)) is None


def test_a_png_cut_between_its_data_chunks_is_corrupt_and_one_lacking_only_iend_is_not(tmp_path):
    at = PNG.index(b"IDAT") - 4
    length = struct.unpack(">I", PNG[at:at + 4])[0]
    data = PNG[at + 8:at + 8 + length]
    split = PNG[:at] + _chunk(b"IDAT", data[:len(data) // 2]) + _chunk(b"IDAT", data[len(data) // 2:])
    assert damage(split + _chunk(b"IEND", b"")) is None
    assert damage(split) is None  # every data chunk there, only IEND missing: decoders show it whole
    assert damage(PNG[:at] + _chunk(b"IDAT", data[:len(data) // 2])).kind == "corrupt"  # cut at a chunk boundary


def test_checking_damaged_pngs_prints_nothing(tmp_path, capfd):
    """The library never prints: libpng (through OpenImageIO) writes its errors to the C stderr."""
    crc_at = PNG.index(b"IDAT") + 4 + struct.unpack(">I", PNG[PNG.index(b"IDAT") - 4:PNG.index(b"IDAT")])[0]
    for name, data in (("crc.png", PNG[:crc_at] + bytes([PNG[crc_at] ^ 1]) + PNG[crc_at + 1:]),
                       ("cut.png", PNG[:len(PNG) // 2]), ("head.png", PNG[:30])):
        (tmp_path / name).write_bytes(data)
        path = tmp_path / f"{name}.mtlx"
        path.write_text(MTLX.format(file=name))
        assert "OPBR707" in _codes_of(path), name
    captured = capfd.readouterr()
    assert captured.err == "" and captured.out == ""


def test_a_folder_name_that_is_not_utf8_is_judged_like_any_other(tmp_path):
    import os

    folder = os.path.join(os.fsencode(str(tmp_path)), b"bad\xffdir")
    os.mkdir(folder)
    with open(os.path.join(folder, b"a.png"), "wb") as handle:
        handle.write(bytes(random.Random(9).randrange(256) for _ in range(300)))
    with open(os.path.join(folder, b"b.png"), "wb") as handle:
        handle.write(PNG[:len(PNG) // 2])
    document = os.path.join(folder, b"m.mtlx")
    for file, code in (("a.png", "OPBR708"), ("b.png", "OPBR707")):
        with open(document, "w", encoding="utf-8") as handle:
            handle.write(MTLX.format(file=file))
        assert code in _codes_of(os.fsdecode(document)), file


def test_the_tiles_of_a_udim_path_are_listed_where_the_system_finds_them(tmp_path):
    """link/../../paint.<UDIM>.png with link -> a/b names the asset's own folder (links before '..')."""
    (tmp_path / "paint.1001.png").write_bytes(PNG)  # beside the asset: text joining would list here
    (tmp_path / "asset" / "a" / "b").mkdir(parents=True)
    (tmp_path / "asset" / "link").symlink_to(tmp_path / "asset" / "a" / "b")
    (tmp_path / "asset" / "paint.1002.png").write_bytes(LFS)
    path = tmp_path / "asset" / "m.mtlx"
    path.write_text(MTLX.format(file="link/../../paint.<UDIM>.png"))
    [finding] = [d for d in validate_paths([str(path)], options=Options(use_config=False)).diagnostics if d.code == "OPBR707"]
    assert "paint.1002.png" in finding.message


@settings(max_examples=300, deadline=None, database=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(base=st.sampled_from([PNG, JPEG]), edits=st.lists(st.tuples(st.integers(0, 10**6), st.integers(0, 2), st.binary(max_size=16)),
                                                           min_size=1, max_size=6))
def test_a_damaged_image_never_makes_the_check_raise(tmp_path_factory, base, edits):
    """Byte flips, deletions and insertions anywhere in a PNG or a JPEG: the verdict is a Damage of a known
    kind or None, from a file and from the same bytes, and never an exception."""
    data = bytearray(base)
    for at, operation, payload in edits:
        at %= len(data)
        if operation == 0:
            data[at] ^= (payload[:1] or b"\x01")[0] or 1
        elif operation == 1:
            del data[at:at + 1 + len(payload)]
        else:
            data[at:at] = payload
        if not data:
            data = bytearray(b"\x00")
    path = tmp_path_factory.mktemp("fuzz") / "image.bin"
    path.write_bytes(bytes(data))
    for found in (damage(str(path)), damage(bytes(data))):
        assert found is None or found.kind in ("empty", "text", "corrupt", "unrecognised")
