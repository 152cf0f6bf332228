"""Writing glTF: every gltf_pbr parameter survives write-then-read, output is byte-identical for the
same input, channels are packed texel-exactly, source images pass through unchanged, and nothing is
read from outside the source asset's folder unless allowed.

Expected values are the test's own inputs (round trips), texels of images generated here, and
closed forms (the sRGB decoding curve of IEC 61966-2-1).
"""

from __future__ import annotations

import io
import json
import math

import numpy as np
import pytest
from PIL import Image

from openpbr_tools.io import read_asset
from openpbr_tools.io.gltf.writer import GltfWriteError, write_gltf
from openpbr_tools.model import Texture, UVTransform

from gltf_support import gltf_pbr_material, place2d

CONSTANTS = {
    "base_color": (0.9, 0.6, 0.2), "alpha": 0.5, "metallic": 0.25, "roughness": 0.3, "emissive": (0.1, 0.2, 0.3),
    "alpha_mode": 2, "alpha_cutoff": 0.25, "clearcoat": 0.7, "clearcoat_roughness": 0.1,
    "sheen_color": (0.2, 0.3, 0.4), "sheen_roughness": 0.6, "specular": 0.8, "specular_color": (1.0, 0.9, 0.8),
    "transmission": 0.4, "thickness": 0.02, "attenuation_distance": 0.5, "attenuation_color": (0.9, 0.8, 0.7),
    "ior": 1.45, "iridescence": 1.0, "iridescence_ior": 1.8, "iridescence_thickness": 550.0,
    "anisotropy_strength": 0.6, "anisotropy_rotation": 1.2, "emissive_strength": 4.0, "dispersion": 0.4,
}


def save_png(path, array) -> None:
    array = np.asarray(array, dtype=np.uint8)
    mode = {2: "L", 3: {1: "L", 3: "RGB", 4: "RGBA"}.get(array.shape[-1] if array.ndim == 3 else 1)}[array.ndim]
    Image.fromarray(array[:, :, 0] if array.ndim == 3 and array.shape[-1] == 1 else array, mode=mode).save(path)


def texels(path_or_bytes) -> np.ndarray:
    source = io.BytesIO(path_or_bytes) if isinstance(path_or_bytes, bytes) else path_or_bytes
    with Image.open(source) as image:
        return np.asarray(image.convert("RGBA"))


def image_of(asset, texture: Texture) -> np.ndarray:
    """Texels (RGBA) of the image a texture read from a written glTF names."""
    from openpbr_tools.io.gltf.document import load_document

    if texture.packaged:
        data, _ = load_document(asset.path).image_bytes(int(texture.file.rsplit("/", 1)[1]))
        return texels(data)
    import os

    return texels(os.path.join(os.path.dirname(asset.path), texture.file))


def only(asset):
    assert len(asset.materials) == 1
    return asset.materials[0]


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_every_constant_survives_a_round_trip(tmp_path, suffix):
    out = tmp_path / f"all{suffix}"
    notes = write_gltf([gltf_pbr_material("All", **CONSTANTS)], out)
    found = only(read_asset(out))
    assert {n: e.constant for n, e in found.inputs.items()} == CONSTANTS, notes
    assert notes == []


@pytest.fixture
def images(tmp_path):
    """Source images with distinct texels per channel, in a source folder."""
    folder = tmp_path / "source"
    folder.mkdir()
    rng = np.random.default_rng(7)
    for name, channels in (("base.png", 4), ("mr.png", 3), ("sheen.png", 4), ("grey.png", 1), ("normal.png", 3),
                           ("aniso.png", 3), ("spec.png", 4)):
        save_png(folder / name, rng.integers(0, 256, size=(4, 4, channels)))
    return folder


def tex(file, channels, colorspace="none", **fields):
    return Texture(file=file, channels=channels, colorspace=colorspace, **fields)


TRANSFORM = UVTransform(scale=(2.0, 0.5), rotate=30.0, offset=(0.25, -0.1), pivot=(0.0, 1.0))


def textured_material():
    material = gltf_pbr_material(
        "Tex",
        base_color=tex("base.png", (0, 1, 2), "srgb_texture", scale=(0.5, 0.6, 0.7), uv=TRANSFORM, wrap=("clamp", "mirror")),
        alpha=tex("base.png", (3,), scale=0.9, uv=TRANSFORM, wrap=("clamp", "mirror")), alpha_mode=1,
        metallic=tex("mr.png", (2,), texcoord=1), roughness=tex("mr.png", (1,), scale=0.5, texcoord=1),
        normal=tex("normal.png", None, normal_map=0.8, image_type="vector3"),
        occlusion=tex("mr.png", (0,), scale=0.25, bias=0.75),
        emissive=tex("base.png", (0, 1, 2), "srgb_texture", scale=(1.0, 0.5, 0.25)),
        clearcoat=tex("grey.png", (0,), scale=0.7), clearcoat_roughness=tex("mr.png", (1,), scale=0.2),
        clearcoat_normal=tex("normal.png", None, normal_map=0.5, image_type="vector3"),
        sheen_color=tex("sheen.png", (0, 1, 2), "srgb_texture", scale=(0.2, 0.3, 0.4)),
        sheen_roughness=tex("sheen.png", (3,), scale=0.6),
        specular=tex("spec.png", (3,), scale=0.8), specular_color=tex("spec.png", (0, 1, 2), "srgb_texture"),
        transmission=tex("grey.png", (0,), scale=0.4), thickness=tex("mr.png", (1,), scale=0.1),
        iridescence=tex("mr.png", (0,), scale=0.9), iridescence_thickness=tex("mr.png", (1,), scale=600.0, bias=200.0),
        anisotropy_strength=tex("aniso.png", (2,), scale=0.5),
    )
    material.extra["gltf"] = {"anisotropy_direction": tex("aniso.png", (0, 1))}
    return material


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_every_texture_survives_a_round_trip(images, tmp_path, suffix):
    material = textured_material()
    out = tmp_path / "out" / f"tex{suffix}"
    out.parent.mkdir()
    notes = write_gltf([material], out, source=str(images / "doc.mtlx"))
    asset = read_asset(out)
    found = only(asset)
    assert notes == []
    assert found.inputs["alpha_mode"].constant == 1
    for name, entry in material.inputs.items():
        if name == "alpha_mode":
            continue
        written, read = entry.value, found.inputs[name].texture
        assert read is not None, name
        assert (read.channels, read.colorspace) == (written.channels, written.colorspace), name
        assert read.scale == written.scale and read.bias == written.bias, name
        assert read.normal_map == written.normal_map and read.texcoord == written.texcoord, name
        assert read.wrap == written.wrap, name
        source = texels(images / written.file)
        assert np.array_equal(image_of(asset, read), source), f"{name}: image changed"
    assert found.extra["gltf"]["anisotropy_direction"].channels == (0, 1)
    for corner in ((0.0, 0.0), (1.0, 0.0), (0.3, 0.7)):
        expected = place2d(corner, TRANSFORM)
        assert place2d(corner, found.inputs["base_color"].texture.uv) == pytest.approx(expected, abs=1e-12)


def test_a_transform_with_any_pivot_maps_uvs_identically(images, tmp_path):
    transform = UVTransform(scale=(3.0, 1.5), rotate=-45.0, offset=(0.1, 0.2), pivot=(0.5, 0.5))
    material = gltf_pbr_material("P", base_color=tex("base.png", (0, 1, 2), "srgb_texture", uv=transform))
    out = tmp_path / "p.gltf"
    write_gltf([material], out, source=str(images / "doc.mtlx"), allow_outside=[str(images)])
    read = only(read_asset(out)).inputs["base_color"].texture.uv
    for corner in ((0.0, 0.0), (1.0, 1.0), (0.25, 0.8)):
        assert place2d(corner, read) == pytest.approx(place2d(corner, transform), abs=1e-12)


@pytest.mark.parametrize("suffix,mesh", [(".gltf", "sphere"), (".glb", "sphere"), (".gltf", None), (".glb", None)])
def test_output_is_byte_identical_for_the_same_input(images, tmp_path, suffix, mesh):
    first, second = tmp_path / "a", tmp_path / "b"
    first.mkdir(), second.mkdir()
    for folder in (first, second):
        write_gltf([textured_material(), gltf_pbr_material("C", **CONSTANTS)], folder / f"x{suffix}", mesh=mesh,
                   source=str(images / "doc.mtlx"))
    names = sorted(p.name for p in first.iterdir())
    assert names == sorted(p.name for p in second.iterdir())
    for name in names:
        assert (first / name).read_bytes() == (second / name).read_bytes(), name


def test_separate_metallic_and_roughness_images_are_packed_texel_exactly(tmp_path):
    metal = np.array([[0, 51], [102, 255]], dtype=np.uint8)
    rough = np.zeros((2, 2, 3), dtype=np.uint8)
    rough[:, :, 1] = [[10, 20], [30, 40]]
    rough[:, :, 0] = 99  # R and B of the roughness image must not leak into the packed image
    save_png(tmp_path / "metal.png", metal)
    save_png(tmp_path / "rough.png", rough)
    material = gltf_pbr_material("Pack", metallic=tex("metal.png", None), roughness=tex("rough.png", (1,)))
    out = tmp_path / "pack.gltf"
    notes = write_gltf([material], out, source=str(tmp_path / "doc.mtlx"))
    asset = read_asset(out)
    found = only(asset)
    metallic, roughness = found.inputs["metallic"].texture, found.inputs["roughness"].texture
    assert metallic.file == roughness.file and metallic.file not in ("metal.png", "rough.png")
    packed = image_of(asset, metallic)
    assert np.array_equal(packed[:, :, 2], metal)  # glTF: metallic is B
    assert np.array_equal(packed[:, :, 1], rough[:, :, 1])  # roughness is G
    assert any("baked" in note.message for note in notes)


def test_a_lone_roughness_texture_leaves_metallic_to_its_factor(tmp_path):
    save_png(tmp_path / "rough.png", np.full((2, 2), 77, dtype=np.uint8))
    material = gltf_pbr_material("R", roughness=tex("rough.png", None), metallic=0.3)
    out = tmp_path / "r.glb"
    write_gltf([material], out, source=str(tmp_path / "doc.mtlx"))
    asset = read_asset(out)
    found = only(asset)
    packed = image_of(asset, found.inputs["roughness"].texture)
    assert np.all(packed[:, :, 1] == 77) and np.all(packed[:, :, 2] == 255)  # B = 1: metallic = metallicFactor
    assert found.inputs["metallic"].texture.scale == 0.3


def test_anisotropy_strength_without_a_direction_gets_glTFs_default_direction(tmp_path):
    save_png(tmp_path / "strength.png", np.full((2, 2), 200, dtype=np.uint8))
    out = tmp_path / "a.glb"
    write_gltf([gltf_pbr_material("A", anisotropy_strength=tex("strength.png", None))], out, source=str(tmp_path / "d.mtlx"))
    asset = read_asset(out)
    packed = image_of(asset, only(asset).inputs["anisotropy_strength"].texture)
    # KHR_materials_anisotropy: RG holds the direction (1, 0) as (d + 1) / 2, B the strength
    assert np.all(packed[:, :, 0] == 255) and np.all(np.abs(packed[:, :, 1] / 255 * 2 - 1) <= 1 / 255)
    assert np.all(packed[:, :, 2] == 200)


def test_an_image_already_in_gltf_shape_passes_through_unchanged(tmp_path):
    source = np.arange(3 * 5 * 3, dtype=np.uint8).reshape(3, 5, 3)
    save_png(tmp_path / "orm.png", source)
    material = gltf_pbr_material("Orm", metallic=tex("orm.png", (2,)), roughness=tex("orm.png", (1,)))
    out_folder = tmp_path / "out"
    out_folder.mkdir()
    write_gltf([material], out_folder / "orm.gltf", source=str(tmp_path / "doc.mtlx"))
    assert (out_folder / "orm.png").read_bytes() == (tmp_path / "orm.png").read_bytes()
    document = json.loads((out_folder / "orm.gltf").read_text())
    assert document["images"] == [{"uri": "orm.png"}]


def test_images_outside_the_source_folder_need_allow_outside(tmp_path):
    shared = tmp_path / "shared"
    shared.mkdir()
    save_png(shared / "albedo.png", np.zeros((2, 2, 3), dtype=np.uint8))
    (tmp_path / "asset").mkdir()
    material = gltf_pbr_material("O", base_color=tex("../shared/albedo.png", (0, 1, 2), "srgb_texture"))
    out = tmp_path / "out.gltf"
    with pytest.raises(GltfWriteError, match="outside the source asset's folder"):
        write_gltf([material], out, source=str(tmp_path / "asset" / "doc.mtlx"))
    assert not out.exists()
    write_gltf([material], out, source=str(tmp_path / "asset" / "doc.mtlx"), allow_outside=[str(shared)])
    assert json.loads(out.read_text())["images"] == [{"uri": "textures/albedo.png"}]
    assert (tmp_path / "textures" / "albedo.png").is_file()


def test_urls_are_never_fetched(tmp_path):
    material = gltf_pbr_material("U", base_color=tex("https://example.com/a.png", (0, 1, 2), "srgb_texture"))
    with pytest.raises(GltfWriteError, match="URL"):
        write_gltf([material], tmp_path / "u.gltf")


def test_embedded_images_move_between_glb_and_gltf(images, tmp_path):
    glb = tmp_path / "a.glb"
    write_gltf([textured_material()], glb, source=str(images / "doc.mtlx"))
    asset = read_asset(glb)
    out = tmp_path / "back" / "b.gltf"
    out.parent.mkdir()
    write_gltf(asset.materials, out, source=asset)
    again = read_asset(out)
    texture = only(again).inputs["clearcoat"].texture
    assert not texture.packaged and (out.parent / texture.file).is_file()
    assert np.array_equal(image_of(again, texture), texels(images / "grey.png"))
    inline = tmp_path / "c.gltf"
    write_gltf(asset.materials, inline, source=asset, embed=True)
    assert all(image["uri"].startswith("data:image/png;base64,") for image in json.loads(inline.read_text())["images"])


def test_colour_constants_are_converted_to_linear_rec709(tmp_path):
    material = gltf_pbr_material("S", base_color=(0.5, 0.5, 0.5))
    material.inputs["base_color"].colorspace = "srgb_texture"
    write_gltf([material], tmp_path / "s.gltf")
    factor = json.loads((tmp_path / "s.gltf").read_text())["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"]
    expected = ((0.5 + 0.055) / 1.055) ** 2.4  # IEC 61966-2-1 decoding
    assert factor[:3] == pytest.approx([expected] * 3, abs=1e-9) and factor[3] == 1.0


def test_emission_above_one_moves_into_emissive_strength(tmp_path):
    material = gltf_pbr_material("E", emissive=(2.0, 1.0, 0.5), emissive_strength=3.0)
    notes = write_gltf([material], tmp_path / "e.gltf")
    written = json.loads((tmp_path / "e.gltf").read_text())["materials"][0]
    assert written["emissiveFactor"] == [1.0, 0.5, 0.25]
    assert written["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] == 6.0
    assert notes


def test_factors_outside_glTF_ranges_are_clamped_with_a_note(tmp_path):
    notes = write_gltf([gltf_pbr_material("R", roughness=1.5)], tmp_path / "r.gltf")
    written = json.loads((tmp_path / "r.gltf").read_text())["materials"][0]
    assert written["pbrMetallicRoughness"]["roughnessFactor"] == 1.0 and any("clamped" in n.message for n in notes)


def test_every_extension_written_is_declared(tmp_path):
    material = gltf_pbr_material("X", **CONSTANTS)
    write_gltf([material], tmp_path / "x.gltf")
    document = json.loads((tmp_path / "x.gltf").read_text())
    written = set(document["materials"][0]["extensions"])
    assert written == {"KHR_materials_clearcoat", "KHR_materials_sheen", "KHR_materials_specular",
                       "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
                       "KHR_materials_iridescence", "KHR_materials_anisotropy", "KHR_materials_emissive_strength",
                       "KHR_materials_dispersion"}
    assert set(document["extensionsUsed"]) == written


def test_other_models_are_not_written(tmp_path):
    material = gltf_pbr_material("O", roughness=0.5)
    material.model = "open_pbr_surface"
    notes = write_gltf([material], tmp_path / "o.gltf")
    assert "materials" not in json.loads((tmp_path / "o.gltf").read_text()) and "translate" in notes[0].message


def test_sphere_mesh_has_unit_normals_and_tangents_and_one_primitive_per_material(tmp_path):
    write_gltf([gltf_pbr_material("A", roughness=0.2), gltf_pbr_material("B", roughness=0.8)], tmp_path / "s.glb", mesh="sphere")
    asset = read_asset(tmp_path / "s.glb")
    primitives = asset.extra["gltf"]["primitives"]
    assert [p["material"] for p in primitives] == [0, 1]
    from openpbr_tools.io.gltf.mesh import uv_sphere

    sphere = uv_sphere()
    assert np.allclose(np.linalg.norm(sphere["NORMAL"], axis=1), 1.0, atol=1e-6)
    assert np.allclose(np.linalg.norm(sphere["TANGENT"][:, :3], axis=1), 1.0, atol=1e-6)
    assert np.allclose(np.einsum("ij,ij->i", sphere["NORMAL"], sphere["TANGENT"][:, :3]), 0.0, atol=1e-6)
    # the north pole (+Y) carries v = 0: glTF's top of the image (specification 3.8.4.4)
    top = sphere["POSITION"][:, 1] > 0.999
    assert np.all(sphere["TEXCOORD_0"][top][:, 1] == 0.0)
    assert math.isclose(float(sphere["POSITION"][:, 0].max()), 1.0, rel_tol=1e-6)


def test_a_different_file_beside_the_output_is_never_overwritten(tmp_path):
    (tmp_path / "src").mkdir()
    (tmp_path / "out").mkdir()
    save_png(tmp_path / "src" / "wood.png", np.full((2, 2, 3), 10, dtype=np.uint8))
    save_png(tmp_path / "out" / "wood.png", np.full((2, 2, 3), 200, dtype=np.uint8))
    theirs = (tmp_path / "out" / "wood.png").read_bytes()
    material = gltf_pbr_material("W", base_color=tex("wood.png", (0, 1, 2), "srgb_texture"))
    for _ in range(2):  # the second run finds its own copy and reuses it
        write_gltf([material], tmp_path / "out" / "w.gltf", source=str(tmp_path / "src" / "w.mtlx"))
        assert json.loads((tmp_path / "out" / "w.gltf").read_text())["images"] == [{"uri": "wood_2.png"}]
    assert (tmp_path / "out" / "wood.png").read_bytes() == theirs
    assert (tmp_path / "out" / "wood_2.png").read_bytes() == (tmp_path / "src" / "wood.png").read_bytes()


def srgb_encode(x):
    """IEC 61966-2-1 encoding."""
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def srgb_decode(v):
    """IEC 61966-2-1 decoding."""
    return np.where(v <= 0.04045, v / 12.92, np.power((v + 0.055) / 1.055, 2.4))


def test_textures_are_re_encoded_to_the_encoding_glTF_reads(tmp_path):
    values = np.array([[0, 16], [64, 200]], dtype=np.uint8)
    save_png(tmp_path / "linear.png", np.stack([values] * 3, axis=-1))
    save_png(tmp_path / "bent.png", values)
    material = gltf_pbr_material(
        "C", base_color=tex("linear.png", (0, 1, 2), "lin_rec709"),  # glTF colour textures are sRGB-encoded
        clearcoat=tex("bent.png", None, "srgb_texture"),  # glTF data textures are linear
    )
    out = tmp_path / "c.glb"
    write_gltf([material], out, source=str(tmp_path / "c.mtlx"))
    asset = read_asset(out)
    found = only(asset)
    colour = image_of(asset, found.inputs["base_color"].texture)[:, :, 0] / 255.0
    data = image_of(asset, found.inputs["clearcoat"].texture)[:, :, 0] / 255.0
    assert np.allclose(colour, srgb_encode(values / 255.0), atol=0.5 / 255 + 1e-9)
    assert np.allclose(data, srgb_decode(values / 255.0), atol=0.5 / 255 + 1e-9)


def test_inert_volume_and_dispersion_are_omitted(tmp_path):
    """KHR_materials_volume needs transmission, KHR_materials_dispersion a volume (their READMEs)."""
    opaque = gltf_pbr_material("Opaque", thickness=0.02, attenuation_distance=0.5, dispersion=0.4)
    glass = gltf_pbr_material("Glass", transmission=1.0, thickness=0.02, attenuation_distance=0.5, dispersion=0.4)
    out = tmp_path / "v.gltf"
    notes = write_gltf([opaque, glass], out)
    document = json.loads(out.read_text())
    by_name = {m["name"]: m.get("extensions", {}) for m in document["materials"]}
    assert "KHR_materials_volume" not in by_name["Opaque"] and "KHR_materials_dispersion" not in by_name["Opaque"]
    assert by_name["Glass"]["KHR_materials_volume"]["thicknessFactor"] == 0.02
    assert by_name["Glass"]["KHR_materials_dispersion"]["dispersion"] == 0.4
    assert any("omitted" in note.message and "Opaque" in note.message for note in notes)
