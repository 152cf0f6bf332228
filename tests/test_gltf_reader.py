"""Reading glTF: every material becomes gltf_pbr inputs with glTF's channels, colour encodings,
factor semantics and locations; bad files are findings or a clean read error, never a traceback.

Expected channels, defaults and formulas come from the glTF 2.0 specification and the KHR_*
extension READMEs; the texture-transform expectation is checked by evaluating MaterialX's own
``place2d`` (stdlib ``NG_place2d_vector2`` and ``mx_rotate_vector2.glsl``) on the extension's example.
"""

from __future__ import annotations

import base64
import io
import json
import math
import struct

import pytest
from PIL import Image

from openpbr_tools.inventory import describe
from openpbr_tools.io import ReadError, available_suffixes, read_asset
from openpbr_tools.model import Connection, Constant, Texture
from openpbr_tools.validate import validate_paths

from gltf_support import place2d


def png(size=(4, 4), colour=(255, 128, 0, 255), mode="RGBA") -> bytes:
    out = io.BytesIO()
    Image.new(mode, size, colour[: len(mode)]).save(out, "PNG")
    return out.getvalue()


def data_uri(data: bytes, mime="image/png") -> str:
    return f"data:{mime};base64,{base64.b64encode(data).decode()}"


def gltf(materials, **members) -> dict:
    return {"asset": {"version": "2.0"}, **members, "materials": materials}


def write(tmp_path, document, name="doc.gltf"):
    path = tmp_path / name
    path.write_text(json.dumps(document) if isinstance(document, dict) else document, encoding="utf-8")
    return path


def only(asset):
    assert len(asset.materials) == 1
    return asset.materials[0]


def codes(path):
    return [d.code for d in validate_paths([str(path)]).diagnostics]


# -- factors -------------------------------------------------------------------------------------

def test_factors_become_constants_of_the_gltf_pbr_parameters(tmp_path):
    material = {
        "name": "Brass",
        "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.6, 0.2, 0.5], "metallicFactor": 1.0, "roughnessFactor": 0.3},
        "emissiveFactor": [0.1, 0.2, 0.3], "alphaMode": "BLEND", "alphaCutoff": 0.25,
        "extensions": {
            "KHR_materials_clearcoat": {"clearcoatFactor": 0.7, "clearcoatRoughnessFactor": 0.1},
            "KHR_materials_sheen": {"sheenColorFactor": [0.2, 0.3, 0.4], "sheenRoughnessFactor": 0.6},
            "KHR_materials_specular": {"specularFactor": 0.8, "specularColorFactor": [1.0, 0.9, 0.8]},
            "KHR_materials_transmission": {"transmissionFactor": 0.4},
            "KHR_materials_volume": {"thicknessFactor": 0.02, "attenuationDistance": 0.5, "attenuationColor": [0.9, 0.8, 0.7]},
            "KHR_materials_ior": {"ior": 1.45},
            "KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceIor": 1.8, "iridescenceThicknessMaximum": 550.0},
            "KHR_materials_anisotropy": {"anisotropyStrength": 0.6, "anisotropyRotation": 1.2},
            "KHR_materials_emissive_strength": {"emissiveStrength": 4.0},
            "KHR_materials_dispersion": {"dispersion": 0.4},
        },
    }
    found = only(read_asset(write(tmp_path, gltf([material]))))
    assert (found.model, found.version, found.name) == ("gltf_pbr", "2.0.1", "Brass")
    expected = {
        "base_color": (0.9, 0.6, 0.2), "alpha": 0.5, "metallic": 1.0, "roughness": 0.3, "emissive": (0.1, 0.2, 0.3),
        "alpha_mode": 2, "alpha_cutoff": 0.25, "clearcoat": 0.7, "clearcoat_roughness": 0.1,
        "sheen_color": (0.2, 0.3, 0.4), "sheen_roughness": 0.6, "specular": 0.8, "specular_color": (1.0, 0.9, 0.8),
        "transmission": 0.4, "thickness": 0.02, "attenuation_distance": 0.5, "attenuation_color": (0.9, 0.8, 0.7),
        "ior": 1.45, "iridescence": 1.0, "iridescence_ior": 1.8, "iridescence_thickness": 550.0,
        "anisotropy_strength": 0.6, "anisotropy_rotation": 1.2, "emissive_strength": 4.0, "dispersion": 0.4,
    }
    assert {name: entry.constant for name, entry in found.inputs.items()} == expected
    location = found.inputs["roughness"].location
    assert (location.path, location.input) == ("/materials/0/pbrMetallicRoughness", "roughnessFactor")
    assert found.inputs["ior"].location.path == "/materials/0/extensions/KHR_materials_ior"
    assert found.inputs["thickness"].unit == "meter" and found.inputs["thickness"].unittype == "distance"


def test_unauthored_properties_are_not_inputs(tmp_path):
    found = only(read_asset(write(tmp_path, gltf([{"name": "Plain"}]))))
    assert found.inputs == {}


# -- textures ------------------------------------------------------------------------------------

TEXTURED = {
    "name": "T", "alphaMode": "MASK",
    "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 1, "texCoord": 1},
                             "roughnessFactor": 0.5},
    "normalTexture": {"index": 1, "scale": 0.8},
    "occlusionTexture": {"index": 1, "strength": 0.25},
    "emissiveTexture": {"index": 0},
    "extensions": {
        "KHR_materials_clearcoat": {"clearcoatTexture": {"index": 1}, "clearcoatRoughnessTexture": {"index": 1},
                                    "clearcoatNormalTexture": {"index": 1, "scale": 0.5}},
        "KHR_materials_sheen": {"sheenColorTexture": {"index": 0}, "sheenRoughnessTexture": {"index": 0}},
        "KHR_materials_specular": {"specularTexture": {"index": 0}, "specularColorTexture": {"index": 0}},
        "KHR_materials_transmission": {"transmissionTexture": {"index": 1}},
        "KHR_materials_volume": {"thicknessTexture": {"index": 1}, "thicknessFactor": 0.1},
        "KHR_materials_iridescence": {"iridescenceTexture": {"index": 1}, "iridescenceThicknessTexture": {"index": 1},
                                      "iridescenceThicknessMinimum": 200.0, "iridescenceThicknessMaximum": 800.0},
        "KHR_materials_anisotropy": {"anisotropyTexture": {"index": 1}, "anisotropyStrength": 0.5},
    },
}


@pytest.fixture
def textured(tmp_path):
    (tmp_path / "base colour.png").write_bytes(png())
    (tmp_path / "orm.png").write_bytes(png(mode="RGB"))
    document = gltf([TEXTURED], images=[{"uri": "base%20colour.png"}, {"uri": "orm.png"}],
                    textures=[{"source": 0}, {"source": 1}])
    return only(read_asset(write(tmp_path, document)))


# (parameter, channels, colour space): glTF 2.0 section 3.9 and each extension's README
SLOT_CHANNELS = [
    ("base_color", (0, 1, 2), "srgb_texture"), ("alpha", (3,), "none"), ("metallic", (2,), "none"),
    ("roughness", (1,), "none"), ("occlusion", (0,), "none"), ("emissive", (0, 1, 2), "srgb_texture"),
    ("clearcoat", (0,), "none"), ("clearcoat_roughness", (1,), "none"), ("sheen_color", (0, 1, 2), "srgb_texture"),
    ("sheen_roughness", (3,), "none"), ("specular", (3,), "none"), ("specular_color", (0, 1, 2), "srgb_texture"),
    ("transmission", (0,), "none"), ("thickness", (1,), "none"), ("iridescence", (0,), "none"),
    ("iridescence_thickness", (1,), "none"), ("anisotropy_strength", (2,), "none"),
]


@pytest.mark.parametrize("name,channels,colorspace", SLOT_CHANNELS, ids=[s[0] for s in SLOT_CHANNELS])
def test_each_texture_slot_reads_the_channels_the_spec_assigns(textured, name, channels, colorspace):
    texture = textured.inputs[name].texture
    assert texture is not None and texture.channels == channels and texture.colorspace == colorspace


def test_base_colour_alpha_is_read_only_where_alpha_mode_uses_it(tmp_path):
    (tmp_path / "a.png").write_bytes(png())
    for mode, has_alpha in (("OPAQUE", False), (None, False), ("BLEND", True), ("MASK", True)):
        material = {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}
        if mode:
            material["alphaMode"] = mode
        document = gltf([material], images=[{"uri": "a.png"}], textures=[{"source": 0}])
        assert ("alpha" in only(read_asset(write(tmp_path, document))).inputs) == has_alpha, mode


def test_texture_files_are_decoded_uris(textured):
    assert textured.inputs["base_color"].texture.file == "base colour.png"
    assert not textured.inputs["base_color"].texture.packaged


def test_factor_multiplying_a_texture_is_its_scale_with_glTF_defaults(textured):
    inputs = textured.inputs
    assert inputs["roughness"].texture.scale == 0.5
    assert inputs["metallic"].texture.scale is None  # metallicFactor defaults to 1
    assert inputs["emissive"].texture.scale == (0.0, 0.0, 0.0)  # emissiveFactor defaults to black
    assert inputs["clearcoat"].texture.scale == 0.0  # clearcoatFactor defaults to 0
    assert inputs["thickness"].texture.scale == 0.1


def test_normal_scale_and_occlusion_strength(textured):
    normal = textured.inputs["normal"].texture
    assert normal.normal_map == 0.8 and normal.colorspace == "none" and textured.inputs["normal"].type == "vector3"
    assert textured.inputs["clearcoat_normal"].texture.normal_map == 0.5
    occlusion = textured.inputs["occlusion"].texture
    # glTF: occlusion = 1 + strength * (r - 1) = strength * r + (1 - strength)
    assert (occlusion.scale, occlusion.bias) == (0.25, 0.75)


def test_iridescence_thickness_texture_mixes_minimum_and_maximum(textured):
    texture = textured.inputs["iridescence_thickness"].texture
    # KHR_materials_iridescence: thickness = mix(min, max, g) = g * (max - min) + min
    assert (texture.scale, texture.bias) == (600.0, 200.0)


def test_anisotropy_direction_is_kept_beside_the_strength(textured):
    direction = textured.extra["gltf"]["anisotropy_direction"]
    assert isinstance(direction, Texture) and direction.channels == (0, 1) and direction.file == "orm.png"
    assert textured.inputs["anisotropy_strength"].texture.scale == 0.5


def test_texcoord_and_location(textured):
    metallic = textured.inputs["metallic"]
    assert metallic.texture.texcoord == 1 and textured.inputs["base_color"].texture.texcoord is None
    assert (metallic.location.path, metallic.location.input) == ("/materials/0/pbrMetallicRoughness", "metallicRoughnessTexture")


def test_texture_transform_matches_the_extension_example_in_materialx_uv_space(tmp_path):
    """KHR_texture_transform's README: offset [0, 1], rotation pi/2, scale [0.5, 0.5] "utilizes only
    the lower left quadrant of the source image, rotated clockwise 90 degrees". In MaterialX's
    bottom-left-origin UV space the lower-left quadrant is u, v in [0, 0.5]; glTF mesh UVs arrive
    with V flipped (v_mx = 1 - v_gltf)."""
    (tmp_path / "a.png").write_bytes(png())
    info = {"index": 0, "extensions": {"KHR_texture_transform": {"offset": [0, 1], "rotation": math.pi / 2, "scale": [0.5, 0.5]}}}
    document = gltf([{"pbrMetallicRoughness": {"baseColorTexture": info}}], images=[{"uri": "a.png"}], textures=[{"source": 0}],
                    extensionsUsed=["KHR_texture_transform"])
    transform = only(read_asset(write(tmp_path, document))).inputs["base_color"].texture.uv
    corners = {}
    for u_gltf, v_gltf in ((0, 0), (1, 0), (0, 1), (1, 1)):
        u, v = place2d((u_gltf, 1 - v_gltf), transform)
        corners[(u_gltf, v_gltf)] = (round(u, 9) + 0.0, round(v, 9) + 0.0)
        assert -1e-9 <= u <= 0.5 + 1e-9 and -1e-9 <= v <= 0.5 + 1e-9
    # Rotated clockwise by 90 degrees, the image's left edge (bottom to top) shows along the mesh's
    # top edge (v_gltf = 0, left to right): in MaterialX image space, u = 0 with v from 0 to 0.5.
    assert corners[(0, 0)] == (0.0, 0.0) and corners[(1, 0)] == (0.0, 0.5)
    assert corners[(0, 1)] == (0.5, 0.0) and corners[(1, 1)] == (0.5, 0.5)


def test_sampler_wrap_modes_become_address_modes(tmp_path):
    (tmp_path / "a.png").write_bytes(png())
    document = gltf([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], images=[{"uri": "a.png"}],
                    samplers=[{"wrapS": 33071, "wrapT": 33648}], textures=[{"source": 0, "sampler": 0}])
    texture = only(read_asset(write(tmp_path, document))).inputs["base_color"].texture
    assert texture.wrap == ("clamp", "mirror")  # CLAMP_TO_EDGE 33071, MIRRORED_REPEAT 33648 (spec 5.26)


# -- embedded images and GLB ---------------------------------------------------------------------

def test_data_uri_images_are_packaged(tmp_path):
    document = gltf([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], images=[{"uri": data_uri(png((8, 2)))}],
                    textures=[{"source": 0}])
    path = write(tmp_path, document)
    asset = read_asset(path)
    texture = only(asset).inputs["base_color"].texture
    assert texture.file == "#/images/0" and texture.packaged
    assert asset.extra["gltf"]["images"][0]["width"] == 8 and "OPBR701" not in codes(path)


def test_glb_written_by_pygltflib_reads_with_its_embedded_image(tmp_path):
    """pygltflib (an independent producer) builds the GLB: image in a bufferView of the BIN chunk."""
    import pygltflib

    image = png((2, 2))
    padded = image + b"\0" * (-len(image) % 4)
    document = pygltflib.GLTF2(
        asset=pygltflib.Asset(version="2.0"),
        buffers=[pygltflib.Buffer(byteLength=len(padded))],
        bufferViews=[pygltflib.BufferView(buffer=0, byteOffset=0, byteLength=len(image))],
        images=[pygltflib.Image(bufferView=0, mimeType="image/png")],
        textures=[pygltflib.Texture(source=0)],
        materials=[pygltflib.Material(name="Glb", pbrMetallicRoughness=pygltflib.PbrMetallicRoughness(
            baseColorTexture=pygltflib.TextureInfo(index=0), roughnessFactor=0.25))],
    )
    document.set_binary_blob(padded)
    path = tmp_path / "made.glb"
    document.save_binary(str(path))
    asset = read_asset(path)
    found = only(asset)
    assert found.name == "Glb" and found.inputs["roughness"].constant == 0.25
    assert found.inputs["base_color"].texture.file == "#/images/0"
    assert asset.extra["gltf"]["images"][0]["mime"] == "image/png"
    assert "OPBR701" not in codes(path) and "OPBR1209" not in codes(path)


@pytest.mark.parametrize("data,message", [
    (b"glTF" + struct.pack("<II", 1, 12), "version 1"),
    (b"glTX" + struct.pack("<II", 2, 12), "magic"),
    (b"glTF" + struct.pack("<II", 2, 40) + b"\0" * 4, "header length"),
    (b"glTF" + struct.pack("<II", 2, 24) + struct.pack("<II", 100, 0x4E4F534A) + b"{}  ", "past the end"),
    (b"glTF" + struct.pack("<II", 2, 24) + struct.pack("<II", 4, 0x004E4942) + b"\0" * 4, "first chunk is not JSON"),
    (b"gl", "shorter than"),
], ids=["version", "magic", "length", "chunk", "bin-first", "short"])
def test_bad_glb_containers_are_read_errors(tmp_path, data, message):
    path = tmp_path / "bad.glb"
    path.write_bytes(data)
    with pytest.raises(ReadError) as raised:
        read_asset(path)
    assert raised.value.kind == "not_gltf" and message in raised.value.message


@pytest.mark.parametrize("text,message", [
    ("{not json", "not JSON"), ("[1, 2]", "not an object"), ('{"materials": []}', "asset.version"),
    ('{"asset": {"version": "1.0"}}', "not 2.x"),
])
def test_files_that_are_not_gltf_are_read_errors(tmp_path, text, message):
    with pytest.raises(ReadError) as raised:
        read_asset(write(tmp_path, text))
    assert raised.value.kind == "not_gltf" and message in raised.value.message


def test_broken_base64_is_a_finding_not_a_crash(tmp_path):
    document = gltf([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
                    images=[{"uri": "data:image/png;base64,@@@@"}], textures=[{"source": 0}])
    assert "OPBR1209" in codes(write(tmp_path, document))


def test_a_data_uri_above_the_size_limit_is_refused_before_decoding(tmp_path, monkeypatch):
    payload = base64.b64encode(b"\0" * 3000).decode()
    document = gltf([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
                    images=[{"uri": "data:image/png;base64," + payload}], textures=[{"source": 0}])
    path = write(tmp_path, document)
    monkeypatch.setenv("OPENPBR_MAX_FILE_MB", str(2000 / 2**20))
    with pytest.raises(ReadError) as raised:
        read_asset(path)
    assert raised.value.kind == "unreadable" and "limit" in raised.value.message


def test_a_data_uri_payload_above_the_limit_is_not_decoded(monkeypatch):
    from openpbr_tools.io.gltf.document import ResourceError, decode_data_uri

    monkeypatch.setenv("OPENPBR_MAX_FILE_MB", str(1000 / 2**20))
    with pytest.raises(ResourceError, match="limit"):
        decode_data_uri("data:image/png;base64," + "A" * 4000, "/images/0")


def test_out_of_range_indices_are_dangling_references(tmp_path):
    (tmp_path / "a.png").write_bytes(png())
    document = gltf([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 7}},
                      "normalTexture": {"index": 0}, "occlusionTexture": {"index": 1}}],
                    images=[{"uri": "a.png"}], textures=[{"source": 0, "sampler": 3}, {"source": 9}])
    path = write(tmp_path, document)
    found = only(read_asset(path))
    assert isinstance(found.inputs["base_color"].value, Connection) and found.inputs["base_color"].value.dangling
    messages = [d.message for d in validate_paths([str(path)]).diagnostics if d.code == "OPBR802"]
    assert any("7" in m for m in messages) and any("sampler 3" in m for m in messages) and any("source 9" in m for m in messages)


def test_missing_and_outside_image_files_reuse_the_texture_rules(tmp_path):
    document = gltf([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "emissiveTexture": {"index": 1}}],
                    images=[{"uri": "missing.png"}, {"uri": "../elsewhere/e.png"}], textures=[{"source": 0}, {"source": 1}])
    found = codes(write(tmp_path, document))
    assert "OPBR701" in found and "OPBR704" in found


# -- what gltf_pbr does not hold -----------------------------------------------------------------

def test_unknown_extensions_extras_and_double_sided_are_kept_raw(tmp_path):
    material = {"name": "K", "doubleSided": True, "extras": {"id": 42},
                "extensions": {"KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.3},
                               "VENDOR_glitter": {"amount": 2}, "KHR_materials_ior": {"ior": 1.3}}}
    found = only(read_asset(write(tmp_path, gltf([material]))))
    extra = found.extra["gltf"]
    assert extra["doubleSided"] is True and extra["extras"] == {"id": 42}
    assert extra["extensions"] == {"KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.3},
                                   "VENDOR_glitter": {"amount": 2}}
    assert found.inputs["ior"].constant == 1.3


def test_unlit_and_specular_glossiness_are_recorded_and_only_specular_glossiness_reported(tmp_path):
    """Both are kept as data; specular-glossiness, which Khronos archived (viewers that dropped it show the
    fallback), is a warning, and `openpbr info` says how conversions read it; an unlit material, which
    conversions read as emission of its base colour (and Khronos' samples use), is not reported, nor is
    KHR_materials_unlit in extensionsRequired (OPBR1202)."""
    materials = [{"name": "U", "extensions": {"KHR_materials_unlit": {}}},
                 {"name": "SG", "extensions": {"KHR_materials_pbrSpecularGlossiness": {"glossinessFactor": 0.2}}}]
    path = write(tmp_path, gltf(materials, extensionsUsed=["KHR_materials_unlit", "KHR_materials_pbrSpecularGlossiness"],
                                extensionsRequired=["KHR_materials_unlit"]))
    asset = read_asset(path)
    assert asset.materials[0].extra["gltf"]["extensions"]["KHR_materials_unlit"] == {}
    assert asset.materials[1].extra["gltf"]["extensions"]["KHR_materials_pbrSpecularGlossiness"] == {"glossinessFactor": 0.2}
    found = [d for d in validate_paths([str(path)]).diagnostics
             if d.code in ("OPBR1204", "OPBR1202", "OPBR1212")]
    assert [(d.code, d.location.path) for d in found] == [("OPBR1204", "/materials/1/extensions/KHR_materials_pbrSpecularGlossiness")]
    statuses = [m["extensions"] for m in describe(asset)["materials"]]  # what `openpbr info` lists
    assert statuses == [[{"name": "KHR_materials_unlit", "status": "read as emission"}],
                        [{"name": "KHR_materials_pbrSpecularGlossiness", "status": "read as metal-rough (spec-gloss solve)"}]]


# -- the generic rules see glTF values -------------------------------------------------------------

def test_out_of_range_factor_is_a_hard_range_error(tmp_path):
    path = write(tmp_path, gltf([{"pbrMetallicRoughness": {"roughnessFactor": 1.5}}]))
    found = [d for d in validate_paths([str(path)]).diagnostics if d.code == "OPBR301"]
    assert len(found) == 1 and found[0].location.input == "roughnessFactor"


def test_out_of_range_factor_on_a_texture_is_a_hard_range_error_too(tmp_path):
    (tmp_path / "a.png").write_bytes(png())
    document = gltf([{"pbrMetallicRoughness": {"metallicRoughnessTexture": {"index": 0}, "roughnessFactor": 1.5}}],
                    images=[{"uri": "a.png"}], textures=[{"source": 0}])
    assert "OPBR301" in codes(write(tmp_path, document))


@pytest.mark.parametrize("material", [
    {"alphaMode": 1}, {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1]}}, {"emissiveFactor": "red"},
])
def test_values_of_the_wrong_json_type_are_unparsable(tmp_path, material):
    assert "OPBR202" in codes(write(tmp_path, gltf([material])))


def test_an_alpha_mode_string_outside_the_enum_is_an_enum_error_not_unparsable(tmp_path):
    # glTF 2.0 schema material.alphaMode: anyOf "OPAQUE", "MASK", "BLEND".
    assert codes(write(tmp_path, gltf([{"alphaMode": "CUTOUT"}]))) == ["OPBR303"]


def test_a_clean_gltf_has_no_findings(tmp_path):
    (tmp_path / "a.png").write_bytes(png())
    document = gltf([{"name": "Clean", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}}],
                    images=[{"uri": "a.png"}], textures=[{"source": 0}])
    assert codes(write(tmp_path, document)) == []


def test_gltf_suffixes_are_available():
    assert ".gltf" in available_suffixes() and ".glb" in available_suffixes()


def test_constants_are_linear_rec709(tmp_path):
    found = only(read_asset(write(tmp_path, gltf([{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1]}}]))))
    assert found.inputs["base_color"].colorspace == "lin_rec709" and isinstance(found.inputs["base_color"].value, Constant)


# -- hostile documents -----------------------------------------------------------------------------

def _json_values():
    from hypothesis import strategies as st

    scalars = st.one_of(st.none(), st.booleans(), st.integers(-3, 10), st.floats(allow_nan=True, allow_infinity=True),
                        st.sampled_from(["", "a.png", "data:image/png;base64,@@", "OPAQUE", "../x.png", "http://h/x.png"]))
    return st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                         st.dictionaries(st.sampled_from(KEYS), inner, max_size=5)),
                        max_leaves=12)


KEYS = ["index", "texCoord", "scale", "strength", "source", "sampler", "uri", "bufferView", "buffer", "byteLength",
        "byteOffset", "mimeType", "extensions", "KHR_texture_transform", "KHR_materials_clearcoat", "KHR_materials_volume",
        "KHR_materials_iridescence", "KHR_materials_anisotropy", "KHR_materials_emissive_strength", "EXT_texture_webp",
        "pbrMetallicRoughness", "baseColorTexture", "baseColorFactor", "metallicRoughnessTexture", "normalTexture",
        "occlusionTexture", "emissiveFactor", "alphaMode", "offset", "rotation", "wrapS", "attributes", "primitives",
        "material", "TEXCOORD_1", "name", "doubleSided", "clearcoatTexture", "iridescenceThicknessMinimum"]


def test_hostile_documents_never_raise_anything_but_read_errors(tmp_path):
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    (tmp_path / "a.png").write_bytes(png())
    anything = _json_values()
    info = st.one_of(anything, st.fixed_dictionaries({"index": st.one_of(st.integers(-1, 3), anything)}, optional={
        "texCoord": anything, "scale": anything, "strength": anything,
        "extensions": st.one_of(anything, st.fixed_dictionaries({}, optional={"KHR_texture_transform": st.one_of(
            anything, st.fixed_dictionaries({}, optional={"offset": anything, "rotation": anything, "scale": anything,
                                                          "texCoord": anything}))}))}))
    extension = st.dictionaries(st.sampled_from(["clearcoatFactor", "clearcoatTexture", "thicknessTexture", "attenuationDistance",
                                                 "iridescenceThicknessTexture", "iridescenceThicknessMinimum",
                                                 "anisotropyTexture", "emissiveStrength", "sheenColorFactor"]),
                                st.one_of(info, anything), max_size=4)
    material = st.fixed_dictionaries({}, optional={
        "pbrMetallicRoughness": st.one_of(anything, st.dictionaries(
            st.sampled_from(["baseColorTexture", "baseColorFactor", "metallicRoughnessTexture", "roughnessFactor"]),
            st.one_of(info, anything), max_size=4)),
        "normalTexture": info, "occlusionTexture": info, "emissiveTexture": info, "emissiveFactor": anything,
        "alphaMode": anything, "name": anything, "extras": anything,
        "extensions": st.one_of(anything, st.dictionaries(st.sampled_from(
            ["KHR_materials_clearcoat", "KHR_materials_volume", "KHR_materials_iridescence", "KHR_materials_anisotropy",
             "KHR_materials_emissive_strength", "KHR_materials_unlit", "KHR_materials_sheen", "VENDOR_x"]),
            st.one_of(extension, anything), max_size=3)),
    })
    texture = st.fixed_dictionaries({}, optional={"source": st.one_of(st.integers(-1, 3), anything),
                                                  "sampler": st.one_of(st.integers(-1, 2), anything), "extensions": anything})
    image = st.fixed_dictionaries({}, optional={"uri": anything, "bufferView": st.one_of(st.integers(-1, 2), anything),
                                                "mimeType": anything})
    sampler = st.fixed_dictionaries({}, optional={"wrapS": st.one_of(st.sampled_from([10497, 33071, 33648, 1]), anything),
                                                  "wrapT": anything})
    buffer = st.fixed_dictionaries({}, optional={"uri": anything, "byteLength": st.one_of(st.integers(-1, 8), anything)})
    view = st.fixed_dictionaries({}, optional={"buffer": st.one_of(st.integers(-1, 2), anything),
                                               "byteOffset": st.one_of(st.integers(-1, 8), anything),
                                               "byteLength": st.one_of(st.integers(-1, 8), anything)})
    primitive = st.fixed_dictionaries({}, optional={"attributes": st.one_of(anything, st.dictionaries(
        st.sampled_from(["POSITION", "TEXCOORD_0", "TEXCOORD_1", "TEXCOORD_x"]), anything, max_size=3)),
        "material": st.one_of(st.integers(-1, 3), anything)})
    mesh = st.fixed_dictionaries({}, optional={"primitives": st.one_of(anything, st.lists(primitive, max_size=2))})
    listed = {"materials": material, "textures": texture, "images": image, "samplers": sampler, "buffers": buffer,
              "bufferViews": view, "meshes": mesh}
    members = st.fixed_dictionaries({}, optional={
        **{name: st.one_of(anything, st.lists(st.one_of(item, anything), max_size=3)) for name, item in listed.items()},
        "extensionsUsed": anything, "extensionsRequired": anything,
    })

    @settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck), database=None)
    @given(members)
    def check(document):
        path = tmp_path / "fuzz.gltf"
        path.write_text(json.dumps({"asset": {"version": "2.0"}, **document}), encoding="utf-8")
        try:
            read_asset(path)
        except ReadError:
            return
        validate_paths([str(path)])  # the rules must cope with whatever the reader recorded

    check()


def test_corrupted_glb_bytes_never_raise_anything_but_read_errors(tmp_path):
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    from openpbr_tools.io.gltf.writer import write_gltf
    from openpbr_tools.model import Texture

    from gltf_support import gltf_pbr_material

    (tmp_path / "a.png").write_bytes(png())
    material = gltf_pbr_material("G", base_color=Texture("a.png", channels=(0, 1, 2), colorspace="srgb_texture"), roughness=0.5)
    original = tmp_path / "good.glb"
    write_gltf([material], original, mesh="sphere", source=str(tmp_path / "a.mtlx"))
    data = original.read_bytes()

    @settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck), database=None)
    @given(st.integers(0, len(data)), st.lists(st.tuples(st.integers(0, len(data) - 1), st.integers(0, 255)), max_size=6))
    def check(cut, flips):
        mutated = bytearray(data[:cut] if cut < len(data) else data)
        for position, value in flips:
            if position < len(mutated):
                mutated[position] = value
        path = tmp_path / "mutated.glb"
        path.write_bytes(bytes(mutated))
        try:
            read_asset(path)
        except ReadError:
            return
        validate_paths([str(path)])

    check()


def test_info_says_how_each_diffuse_transmission_is_read(tmp_path):
    """`openpbr info`: KHR_materials_diffuse_transmission with factors only on a material without a volume
    is read as OpenPBR's thin-walled subsurface; with a texture it is kept as data (the reader reports it)."""
    (tmp_path / "a.png").write_bytes(png())
    materials = [{"name": "F", "extensions": {"KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.5}}},
                 {"name": "T", "extensions": {"KHR_materials_diffuse_transmission": {
                     "diffuseTransmissionFactor": 0.5, "diffuseTransmissionTexture": {"index": 0}}}}]
    path = write(tmp_path, gltf(materials, extensionsUsed=["KHR_materials_diffuse_transmission"],
                                images=[{"uri": "a.png"}], textures=[{"source": 0}]))
    statuses = {m["name"]: m["extensions"][0]["status"] for m in describe(read_asset(path))["materials"]}
    assert statuses == {"F": "read as thin-walled subsurface", "T": "not converted"}


def test_diffuse_transmission_factors_outside_the_schema_range_are_errors(tmp_path):
    """KHR_materials_diffuse_transmission's ratified schema (material.KHR_materials_diffuse_transmission.schema.json)
    keeps diffuseTransmissionFactor and every diffuseTransmissionColorFactor component in [0, 1]. No gltf_pbr
    parameter holds them (they travel as JSON), so the range rule reads them there: OPBR301 at each property
    outside, nothing for one inside (the validator in CI, 2.0.0-dev.3.10, does not check the extension)."""
    extension = "KHR_materials_diffuse_transmission"
    materials = [{"name": "M", "extensions": {extension: {"diffuseTransmissionFactor": 1.5,
                                                          "diffuseTransmissionColorFactor": [2, 0, 0.5]}}},
                 {"name": "N", "extensions": {extension: {"diffuseTransmissionFactor": 0.5,
                                                          "diffuseTransmissionColorFactor": [1, 0, 0.5]}}}]
    path = write(tmp_path, gltf(materials, extensionsUsed=[extension]))
    found = [(d.location.path, d.location.input) for d in validate_paths([str(path)]).diagnostics if d.code == "OPBR301"]
    assert sorted(found) == [(f"/materials/0/extensions/{extension}", "diffuseTransmissionColorFactor"),
                             (f"/materials/0/extensions/{extension}", "diffuseTransmissionFactor")]
