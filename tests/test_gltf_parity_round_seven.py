"""Parity with the Khronos glTF-Validator, round seven (session 20's audit, KP): defects on materials, textures,
images, samplers and the structure needed to read them that the validator reports and the toolkit did not.

Each case is a small document built here, a broken one and its repaired twin. All of them are run through the
validator in one node process (:func:`khronos`); each test asserts the validator's code and severity on the broken
file and not on the twin, and the toolkit's finding (code and severity: an error where the validator has an error, a
warning or an error where it has a warning) on the broken file and not on the twin."""

from __future__ import annotations

import base64
import copy
import io
import json
import struct
import zlib
from pathlib import Path

import pytest
from PIL import Image, ImageCms

from gltf_support import validate_many_with_khronos
from redteam_support import findings

_QUAD = {"POSITION": ("12f", (-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0), "VEC3"),
         "NORMAL": ("12f", (0, 0, 1) * 4, "VEC3"),
         "TANGENT": ("16f", (1, 0, 0, 1) * 4, "VEC4"),
         "TEXCOORD_0": ("8f", (0, 1, 1, 1, 1, 0, 0, 0), "VEC2"),
         "TEXCOORD_1": ("8f", (0, 0.5, 0.5, 0.5, 0.5, 0, 0, 0), "VEC2")}


def png(mode: str = "RGB", colour=(200, 120, 40), size=(4, 4)) -> bytes:
    handle = io.BytesIO()
    Image.new(mode, size, colour).save(handle, "PNG")
    return handle.getvalue()


def data_uri(data: bytes, mime: str = "image/png") -> str:
    return f"data:{mime};base64," + base64.b64encode(data).decode("ascii")


def quad(attributes=("POSITION", "NORMAL", "TEXCOORD_0"), material: dict | None = None, images=None) -> dict:
    """A quad drawn with material 0 (a base colour texture on TEXCOORD_0 unless ``material`` is given), its vertex data
    in one data-URI buffer, one bufferView per attribute (with its target); ``images`` replace the one PNG image."""
    data, views, accessors, named = b"", [], [], {}
    for name in attributes:
        layout, values, kind = _QUAD[name]
        packed = struct.pack("<" + layout, *values)
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(packed), "target": 34962})
        accessor = {"bufferView": len(views) - 1, "componentType": 5126, "count": 4, "type": kind}
        if name == "POSITION":
            accessor.update({"min": [-1, -1, 0], "max": [1, 1, 0]})
        named[name] = len(accessors)
        accessors.append(accessor)
        data += packed
    indices = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(indices), "target": 34963})
    accessors.append({"bufferView": len(views) - 1, "componentType": 5123, "count": 6, "type": "SCALAR"})
    data += indices + bytes(-len(indices) % 4)
    return {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "buffers": [{"byteLength": len(data), "uri": data_uri(data, "application/octet-stream")}],
        "bufferViews": views, "accessors": accessors,
        "images": images if images is not None else [{"uri": data_uri(png())}],
        "samplers": [{"magFilter": 9729}], "textures": [{"source": 0, "sampler": 0}],
        "materials": [material if material is not None else
                      {"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "meshes": [{"primitives": [{"attributes": named, "indices": len(accessors) - 1, "material": 0}]}],
    }


def _without(document: dict, *keys: str) -> dict:
    changed = copy.deepcopy(document)
    for key in keys:
        changed.pop(key, None)
    return changed


def _extensions_used_number():
    broken = quad()
    broken["extensionsUsed"] = [5]
    return broken, quad()


def _samplers_empty():
    broken, fixed = quad(), quad()
    broken["samplers"], broken["textures"] = [], [{"source": 0}]
    fixed["textures"] = [{"source": 0}]
    return broken, _without(fixed, "samplers")


def _textures_empty():
    plain = {"name": "M", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.2, 1]}}
    broken = _without(quad(material=plain), "images", "samplers")
    broken["textures"] = []
    return broken, _without(broken, "textures")


def _image_uri(uri: str):
    def build():
        broken, fixed = quad(), quad()
        broken["images"] = [{"uri": uri}]
        fixed["images"] = [{"uri": uri.replace("[::1", "[::1]")}]
        return broken, fixed
    return build


def _buffer_uri():
    broken, fixed = quad(), quad()
    broken["buffers"].append({"byteLength": 4, "uri": "1http://example.com/a.bin"})
    fixed["buffers"].append({"byteLength": 4, "uri": "http://example.com/a.bin"})
    return broken, fixed


def _unexpected(array: str, name: str, value):
    def build():
        broken = quad()
        broken[array][0][name] = value
        return broken, quad()
    return build


def _extension_name(name: str):
    def build():
        documents = []
        for used in (name, "KHR_materials_clearcoat"):
            document = quad(material={"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}},
                                      "extensions": {used: {"clearcoatFactor": 1}}})
            document["extensionsUsed"] = [used]
            documents.append(document)
        return tuple(documents)
    return build


def _image_view(shared: bool):
    """The PNG in a bufferView of its own (the twin), or in one with target 34962; or (``shared``) in TEXCOORD_0's
    bufferView, an accessor on which the primitive draws with."""
    def build():
        documents = []
        for broken in (True, False):
            document = quad()
            image = png()
            buffer = base64.b64decode(document["buffers"][0]["uri"].split(",", 1)[1])
            view = {"buffer": 0, "byteOffset": len(buffer), "byteLength": len(image)}
            if broken and not shared:
                view["target"] = 34962
            document["bufferViews"].append(view)
            buffer += image + bytes(-len(image) % 4)
            document["buffers"][0] = {"byteLength": len(buffer), "uri": data_uri(buffer, "application/octet-stream")}
            document["images"] = [{"bufferView": len(document["bufferViews"]) - 1, "mimeType": "image/png"}]
            if broken and shared:
                texcoord = document["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"]
                document["accessors"].append({**document["accessors"][texcoord], "bufferView": len(document["bufferViews"]) - 1})
                document["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = len(document["accessors"]) - 1
                # the image's view is the TEXCOORD_0 accessor's now; keep it free of a target, as an image view is
                document["accessors"][-1]["count"] = 4
            documents.append(document)
        return tuple(documents)
    return build


def _normal_map_without_tangents(with_normals: bool):
    """A normal-mapped quad without TANGENT (and, unless ``with_normals``, without NORMAL), and the quad with both."""
    def build():
        material = {"name": "M", "normalTexture": {"index": 0}}
        attributes = ("POSITION", "NORMAL", "TEXCOORD_0") if with_normals else ("POSITION", "TEXCOORD_0")
        return (quad(attributes, material=material),
                quad(("POSITION", "NORMAL", "TANGENT", "TEXCOORD_0"), material=material))
    return build


def _tangent_texture_uv_set(extension: str, texture: str, factors: dict):
    """A normalTexture on UV set 0 beside ``texture`` of ``extension`` on set 1 (the twin: on set 0)."""
    def build():
        documents = []
        for texcoord in (1, 0):
            material = {"name": "M", "normalTexture": {"index": 0},
                        "extensions": {extension: {**factors, texture: {"index": 0, "texCoord": texcoord}}}}
            document = quad(("POSITION", "NORMAL", "TANGENT", "TEXCOORD_0", "TEXCOORD_1"), material=material)
            document["extensionsUsed"] = [extension]
            documents.append(document)
        return tuple(documents)
    return build


_JSON, _BIN = 0x4E4F534A, 0x004E4942


def glb(document: dict, extra_chunks=(), bin_padding: int = 0) -> bytes:
    """``document`` as a GLB: its data-URI buffer 0 moved into the BIN chunk (with ``bin_padding`` more zero bytes),
    then ``extra_chunks`` ((type, bytes), ...)."""
    document = copy.deepcopy(document)
    binary = base64.b64decode(document["buffers"][0].pop("uri").split(",", 1)[1])
    binary += bytes(-len(binary) % 4 + bin_padding)
    text = json.dumps(document).encode("utf-8")
    text += b" " * (-len(text) % 4)
    body = b"".join(struct.pack("<II", len(data), kind) + data
                    for kind, data in ((_JSON, text), (_BIN, binary), *extra_chunks))
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


def image_in_buffer(document: dict) -> dict:
    """``document`` with its PNG moved from a data URI into buffer 0, through a bufferView of its own."""
    image = png()
    binary = base64.b64decode(document["buffers"][0]["uri"].split(",", 1)[1])
    document["bufferViews"].append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(image)})
    binary += image + bytes(-len(image) % 4)
    document["buffers"][0] = {"byteLength": len(binary), "uri": data_uri(binary, "application/octet-stream")}
    document["images"] = [{"bufferView": len(document["bufferViews"]) - 1, "mimeType": "image/png"}]
    return document


def _glb_case(**options):
    def build():
        return glb(image_in_buffer(quad()), **options), glb(image_in_buffer(quad()))
    return build


def _glb_image_data_uri():
    return glb(quad()), glb(image_in_buffer(quad()))


def png_chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png_with(chunks=(), ihdr_length: int = 13) -> bytes:
    """A 4 x 4 RGB PNG with ``chunks`` ((type, data), ...) after its IHDR, whose data is cut to ``ihdr_length``."""
    plain = png()
    ihdr = plain[16:16 + 13][:ihdr_length]
    return plain[:8] + png_chunk(b"IHDR", ihdr) + b"".join(png_chunk(k, d) for k, d in chunks) + plain[33:]


def _image_case(broken_image: bytes, fixed_image: bytes, mime: str = "image/png"):
    def build():
        return tuple(quad(images=[{"uri": data_uri(image, mime)}]) for image in (broken_image, fixed_image))
    return build


def jpeg(app0_length: int | None = None) -> bytes:
    handle = io.BytesIO()
    Image.new("RGB", (8, 8), (200, 120, 40)).save(handle, "JPEG")
    data = handle.getvalue()
    assert data[2:4] == b"\xff\xe0"  # JFIF's APP0 first
    return data if app0_length is None else data[:4] + struct.pack(">H", app0_length) + data[6:]


def webp(**options) -> bytes:
    """A 4 x 4 WebP (Pillow's encoder; ``save_all`` with ``append_images`` for an animation, ``icc_profile``)."""
    handle = io.BytesIO()
    Image.new("RGB", (4, 4), (200, 120, 40)).save(handle, "WEBP", **options)
    return handle.getvalue()


def _webp_case(broken_image, fixed_image):
    """A texture whose EXT_texture_webp source is the WebP (its core source the PNG fallback)."""
    def build():
        documents = []
        for image in (broken_image, fixed_image):
            document = quad(images=[{"uri": data_uri(png())}, {"uri": data_uri(image, "image/webp")}])
            document["textures"] = [{"source": 0, "extensions": {"EXT_texture_webp": {"source": 1}}}]
            document["extensionsUsed"] = ["EXT_texture_webp"]
            documents.append(document)
        return tuple(documents)
    return build


_SRGB_CHRM = struct.pack(">8I", 31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000)
_WIDE_CHRM = struct.pack(">8I", 31270, 32900, 70800, 29200, 17000, 79700, 13100, 4600)  # Rec. 2020 primaries
_GAMMA_22 = struct.pack(">I", 45455)


# name: (builder, Khronos code, Khronos severity (0 error, 1 warning), toolkit code, toolkit severity)
CASES = {
    "extensions_used_number": (_extensions_used_number, "ARRAY_TYPE_MISMATCH", 0, "OPBR1210", "error"),
    "samplers_empty": (_samplers_empty, "EMPTY_ENTITY", 0, "OPBR1210", "error"),
    "textures_empty": (_textures_empty, "EMPTY_ENTITY", 0, "OPBR1210", "error"),
    "image_uri_unclosed_ipv6": (_image_uri("http://[::1/a.png"), "INVALID_URI", 0, "OPBR1210", "error"),
    "buffer_uri_bad_scheme": (_buffer_uri, "INVALID_URI", 0, "OPBR1210", "error"),
    "sampler_unexpected_property": (_unexpected("samplers", "wrapR", 33071), "UNEXPECTED_PROPERTY", 1, "OPBR1213", "warning"),
    "image_unexpected_property": (_unexpected("images", "width", 4), "UNEXPECTED_PROPERTY", 1, "OPBR1213", "warning"),
    "texture_unexpected_property": (_unexpected("textures", "wrapS", 33071), "UNEXPECTED_PROPERTY", 1, "OPBR1213", "warning"),
    "extension_without_vendor_prefix": (_extension_name("clearcoat"), "INVALID_EXTENSION_NAME_FORMAT", 1, "OPBR1216",
                                        "warning"),
    "image_view_with_target": (_image_view(shared=False), "BUFFER_VIEW_TARGET_OVERRIDE", 0, "OPBR1210", "error"),
    "image_view_shared_with_texcoords": (_image_view(shared=True), "BUFFER_VIEW_TARGET_OVERRIDE", 0, "OPBR1210", "error"),
    "normal_map_without_tangents": (_normal_map_without_tangents(True), "MESH_PRIMITIVE_GENERATED_TANGENT_SPACE", 1,
                                    "OPBR1235", "warning"),
    "normal_map_without_normals_or_tangents": (_normal_map_without_tangents(False),
                                               "MESH_PRIMITIVE_GENERATED_TANGENT_SPACE", 1, "OPBR1235", "warning"),
    "anisotropy_texture_on_another_uv_set": (
        _tangent_texture_uv_set("KHR_materials_anisotropy", "anisotropyTexture", {"anisotropyStrength": 0.5}),
        "KHR_MATERIALS_ANISOTROPY_ANISOTROPY_TEXTURE_TEXCOORD", 1, "OPBR1236", "warning"),
    "clearcoat_normal_texture_on_another_uv_set": (
        _tangent_texture_uv_set("KHR_materials_clearcoat", "clearcoatNormalTexture", {"clearcoatFactor": 1}),
        "KHR_MATERIALS_CLEARCOAT_CLEARCOAT_NORMAL_TEXTURE_TEXCOORD", 1, "OPBR1236", "warning"),
    "glb_bin_chunk_too_big": (_glb_case(bin_padding=16), "BUFFER_GLB_CHUNK_TOO_BIG", 1, "OPBR1237", "warning"),
    "glb_unknown_chunk": (_glb_case(extra_chunks=((0x41525458, b"abcd"),)), "GLB_UNKNOWN_CHUNK_TYPE", 1, "OPBR1237",
                          "warning"),
    "glb_second_bin_chunk": (_glb_case(extra_chunks=((_BIN, b"abcd"),)), "GLB_DUPLICATE_CHUNK", 0, "OPBR1209", "error"),
    "glb_second_json_chunk": (_glb_case(extra_chunks=((_JSON, b"{}  "),)), "GLB_DUPLICATE_CHUNK", 0, "OPBR1209",
                              "error"),
    "glb_image_data_uri": (_glb_image_data_uri, "DATA_URI_GLB", 1, "OPBR1237", "warning"),
    "png_ihdr_12_bytes": (_image_case(png_with(ihdr_length=12), png()), "IMAGE_DATA_INVALID", 0, "OPBR707", "error"),
    "png_phys_8_bytes": (_image_case(png_with([(b"pHYs", bytes(8))]), png_with([(b"pHYs", bytes(9))])),
                         "IMAGE_DATA_INVALID", 0, "OPBR707", "error"),
    "png_srgb_2_bytes": (_image_case(png_with([(b"sRGB", bytes(2))]), png_with([(b"sRGB", bytes(1))])),
                         "IMAGE_DATA_INVALID", 0, "OPBR707", "error"),
    "png_gama_3_bytes": (_image_case(png_with([(b"gAMA", _GAMMA_22[:3])]), png_with([(b"gAMA", _GAMMA_22)])),
                         "IMAGE_DATA_INVALID", 0, "OPBR707", "error"),
    "png_chrm_28_bytes": (_image_case(png_with([(b"cHRM", _SRGB_CHRM[:28])]), png_with([(b"cHRM", _SRGB_CHRM)])),
                          "IMAGE_DATA_INVALID", 0, "OPBR707", "error"),
    "jpeg_app0_length_1": (_image_case(jpeg(app0_length=1), jpeg(), "image/jpeg"), "IMAGE_DATA_INVALID", 0, "OPBR707",
                           "error"),
    "webp_unknown_first_chunk": (_webp_case(webp()[:12] + b"VP8Q" + webp()[16:], webp()), "IMAGE_DATA_INVALID", 0,
                                 "OPBR707", "error"),
    "webp_cut_in_its_header": (_webp_case(webp()[:20], webp()), "IMAGE_UNEXPECTED_EOS", 0, "OPBR707", "error"),
    "png_wide_gamut_chromaticities": (_image_case(png_with([(b"cHRM", _WIDE_CHRM)]), png_with([(b"cHRM", _SRGB_CHRM)])),
                                      "IMAGE_FEATURES_UNSUPPORTED", 1, "OPBR1233", "warning"),
    "png_gamma_1_8": (_image_case(png_with([(b"gAMA", struct.pack(">I", 55555))]), png_with([(b"gAMA", _GAMMA_22)])),
                      "IMAGE_FEATURES_UNSUPPORTED", 1, "OPBR1233", "warning"),
    "webp_animation": (_webp_case(webp(save_all=True, append_images=[Image.new("RGB", (4, 4))]), webp()),
                       "IMAGE_FEATURES_UNSUPPORTED", 1, "OPBR1233", "warning"),
    "webp_icc_profile": (_webp_case(webp(icc_profile=ImageCms.ImageCmsProfile(ImageCms.createProfile("sRGB")).tobytes()),
                                    webp()), "IMAGE_FEATURES_UNSUPPORTED", 1, "OPBR1233", "warning"),
}

def _grey(mode: str, values) -> bytes:
    image = Image.new(mode, (2, 2))
    image.putdata(values)
    handle = io.BytesIO()
    image.save(handle, "PNG")
    return handle.getvalue()


def _judged(material: dict, broken_image: bytes, fixed_image: bytes, fixed_material: dict | None = None):
    """A material reading image 1 (image 0 is the base colour PNG) in its broken and repaired form."""
    def build():
        return tuple(quad(material=m, images=[{"uri": data_uri(png())}, {"uri": data_uri(i)}])
                     | {"textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}]}
                     for m, i in ((material, broken_image), (fixed_material or material, fixed_image)))
    return build


_BASE = {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}
_ROUGHNESS = [40, 90, 160, 230]
#: Defects the validator has no verdict on (it reports no error or warning on either file), each judged from the
#: glTF specification (the red team's session-20 gb02, gb05, gb12): name: (builder, toolkit code, severity).
JUDGED = {
    "occlusion_texture_black": (_judged({"name": "M", "pbrMetallicRoughness": _BASE, "occlusionTexture": {"index": 1}},
                                        _grey("L", [0] * 4), _grey("L", [255, 200, 180, 255])), "OPBR1239", "warning"),
    "greyscale_roughness_as_metallic_roughness": (
        _judged({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 1.0,
                                                       "metallicRoughnessTexture": {"index": 1}}},
                _grey("L", _ROUGHNESS), _grey("L", _ROUGHNESS),
                {"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0,
                                                       "metallicRoughnessTexture": {"index": 1}}}), "OPBR1238", "error"),
    "greyscale_roughness_repacked": (
        _judged({"name": "M", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 1.0,
                                                       "metallicRoughnessTexture": {"index": 1}}},
                _grey("L", _ROUGHNESS), _grey("RGB", [(0, v, 0) for v in _ROUGHNESS])), "OPBR1238", "error"),
    "white_emission_on_a_textured_material": (
        _judged({"name": "M", "pbrMetallicRoughness": _BASE, "emissiveFactor": [1, 1, 1]}, png(), png(),
                {"name": "M", "pbrMetallicRoughness": _BASE, "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 1}}),
        "OPBR1240", "warning"),
}


#: Base colour images the validator accepts without a warning (probed), and the toolkit must too: a linear gAMA, a gAMA
#: or cHRM after or before an sRGB chunk (which decoders take instead), an APNG, an RGBA image whose alpha is 0 under
#: alphaMode OPAQUE.
CLEAN_IMAGES = {
    "png_gamma_linear": (png_with([(b"gAMA", struct.pack(">I", 100000))]), "image/png"),
    "png_gamma_1_8_after_srgb": (png_with([(b"sRGB", b"\x00"), (b"gAMA", struct.pack(">I", 55555))]), "image/png"),
    "png_wide_gamut_before_srgb": (png_with([(b"cHRM", _WIDE_CHRM), (b"sRGB", b"\x00")]), "image/png"),
    "apng": (png_with([(b"acTL", struct.pack(">II", 1, 0))]), "image/png"),
    # (the red team's session-20 good gg01: alpha is not read under alphaMode OPAQUE, so a flat A is no unread data)
    "rgba_base_colour_alpha_0_under_opaque": (_grey("RGBA", [(200, 40, 40, 0), (40, 200, 40, 0), (40, 40, 200, 0),
                                                              (120, 120, 120, 0)]), "image/png"),
}


def _write(path: Path, document) -> Path:
    if isinstance(document, (bytes, bytearray)):
        path.write_bytes(document)
    else:
        path.write_text(json.dumps(document, indent=1), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def cases(tmp_path_factory) -> dict[str, tuple[Path, Path]]:
    folder = tmp_path_factory.mktemp("parity")
    written = {}
    for name, (build, *_) in CASES.items():
        broken, fixed = build()
        suffix = ".glb" if isinstance(broken, (bytes, bytearray)) else ".gltf"
        written[name] = (_write(folder / f"{name}{suffix}", broken), _write(folder / f"{name}_fixed{suffix}", fixed))
    return written


@pytest.fixture(scope="module")
def judged(tmp_path_factory) -> dict[str, tuple[Path, Path]]:
    folder = tmp_path_factory.mktemp("judged")
    return {name: tuple(_write(folder / f"{name}{suffix}.gltf", document) for suffix, document in zip(("", "_fixed"), build()))
            for name, (build, _, _) in JUDGED.items()}


@pytest.fixture(scope="module")
def clean(tmp_path_factory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("clean")
    return {name: _write(folder / f"{name}.gltf", quad(images=[{"uri": data_uri(image, mime)}]))
            for name, (image, mime) in CLEAN_IMAGES.items()}


@pytest.fixture(scope="module")
def khronos(cases, clean, judged, tmp_path_factory) -> dict[Path, set[tuple[str, int]]]:
    """(code, severity) of every error and warning the Khronos glTF-Validator reports, per file, in one node run."""
    paths = [p for pair in (*cases.values(), *judged.values()) for p in pair] + list(clean.values())
    reports = validate_many_with_khronos(paths, tmp_path_factory.mktemp("khronos"))
    return {Path(file): {(m["code"], m["severity"]) for m in report["issues"]["messages"] if m["severity"] <= 1}
            for file, report in reports.items()}


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_toolkit_reports_what_the_khronos_validator_reports(name, cases, khronos):
    _, code, severity, tool_code, tool_severity = CASES[name]
    broken, fixed = cases[name]
    assert (code, severity) in khronos[broken.resolve()], khronos[broken.resolve()]
    assert code not in {c for c, _ in khronos[fixed.resolve()]}, khronos[fixed.resolve()]
    assert (tool_code, tool_severity) in {(c, s) for c, s, _, _ in findings(broken)}, findings(broken)
    assert tool_code not in {c for c, _, _, _ in findings(fixed)}, findings(fixed)


@pytest.mark.parametrize("name", sorted(CLEAN_IMAGES))
def test_images_the_khronos_validator_accepts_stay_clean(name, clean, khronos):
    path = clean[name]
    assert not {c for c, _ in khronos[path.resolve()]} & {"IMAGE_FEATURES_UNSUPPORTED", "IMAGE_DATA_INVALID"}
    assert findings(path) == [], findings(path)


@pytest.mark.parametrize("name", sorted(JUDGED))
def test_defects_the_khronos_validator_does_not_judge_are_found(name, judged, khronos):
    _, tool_code, tool_severity = JUDGED[name]
    broken, fixed = judged[name]
    assert khronos[broken.resolve()] == set() and khronos[fixed.resolve()] == set()
    assert findings(broken) == [(tool_code, tool_severity, *findings(broken)[0][2:])], findings(broken)
    assert findings(fixed) == [], findings(fixed)
