"""Per-texel baking: converted textures hold the formula applied to every texel of the source.

Expected texels are computed here from the published formulas (OpenPBR 1.1 specular anisotropy,
KHR_materials_anisotropy, the OpenPBR coat darkening, the sRGB transfer of IEC 61966-2-1), not
from the translation modules, and compared with the images ``openpbr convert`` wrote.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from cli.group import cli


def srgb_decode(v):
    v = np.asarray(v, dtype=np.float64)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def srgb_encode(v):
    v = np.asarray(v, dtype=np.float64)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


def write_png(path, array):
    Image.fromarray(np.asarray(array, dtype=np.uint8)).save(path)


def document(body: str, images: str = "") -> str:
    return f"""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
{images}
  <open_pbr_surface name="S" type="surfaceshader">
{body}
  </open_pbr_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S"/></surfacematerial>
</materialx>
"""


def image_node(name: str, file: str, type_name: str = "float", colorspace: str = "", uv: str = "") -> str:
    space = f' colorspace="{colorspace}"' if colorspace else ""
    coords = f'<input name="texcoord" type="vector2" nodename="{uv}"/>' if uv else ""
    return f'  <image name="{name}" type="{type_name}"><input name="file" type="filename" value="{file}"{space}/>{coords}</image>'


def convert(*args):
    result = CliRunner().invoke(cli, ["convert", *map(str, args), "--format", "json"])
    assert "Traceback" not in result.output
    assert result.exit_code in (0, 1), result.output
    return [d for d in json.loads(result.stdout)["diagnostics"]]


def gltf_image(folder, gltf_path, prop_path):
    data = json.loads(Path(gltf_path).read_text())
    material = data["materials"][0]
    info = material
    for key in prop_path:
        info = info[key]
    uri = data["images"][data["textures"][info["index"]]["source"]]["uri"]
    return np.asarray(Image.open(os.path.join(folder, uri)), dtype=np.float64) / 255.0


@pytest.fixture
def roughness_asset(tmp_path):
    rng = np.random.default_rng(7)
    rough = rng.integers(0, 256, (8, 12), dtype=np.uint8)
    write_png(tmp_path / "rough.png", rough)
    path = tmp_path / "m.mtlx"
    path.write_text(document('    <input name="specular_roughness" type="float" nodename="r"/>\n'
                             '    <input name="specular_roughness_anisotropy" type="float" value="0.6"/>',
                             image_node("r", "rough.png")))
    return path, rough / 255.0


def test_gltf_roughness_and_anisotropy_are_baked_per_texel(tmp_path, roughness_asset):
    path, r = roughness_asset
    output = tmp_path / "out" / "m.gltf"
    output.parent.mkdir()
    diagnostics = convert(path, "-o", output)
    assert any("roughness: baked per texel" in d["message"] for d in diagnostics)
    a = 0.6
    # OpenPBR 1.1 "Specular anisotropy": alpha_t = r^2 sqrt(2 / (1 + (1 - a)^2)), alpha_b = (1 - a) alpha_t.
    alpha_t = r ** 2 * np.sqrt(2.0 / (1.0 + (1.0 - a) ** 2))
    alpha_b = (1.0 - a) * alpha_t
    # KHR_materials_anisotropy: alpha_b = roughness^2, alpha_t = mix(alpha_b, 1, strength^2).
    expected_roughness = np.sqrt(alpha_b)
    expected_strength = np.sqrt((np.minimum(alpha_t, 1) - alpha_b) / (1 - alpha_b))
    packed = gltf_image(output.parent, output, ("pbrMetallicRoughness", "metallicRoughnessTexture"))
    assert packed.shape[:2] == r.shape  # resolution kept
    # 16-bit intermediate, then 8-bit packing: within one 8-bit step.
    assert np.abs(packed[:, :, 1] - expected_roughness).max() <= 1 / 255 + 1e-9
    factors = json.loads(output.read_text())["materials"][0]["pbrMetallicRoughness"]
    assert np.all(packed[:, :, 2] * factors.get("metallicFactor", 1.0) == 0)  # metallic 0 everywhere
    anisotropy = gltf_image(output.parent, output, ("extensions", "KHR_materials_anisotropy", "anisotropyTexture"))
    assert np.abs(anisotropy[:, :, 2] - expected_strength).max() <= 1 / 255 + 1e-9
    data = json.loads(output.read_text())
    # glTF multiplies texels by their factors (default 1): the texture alone must carry the values.
    assert data["materials"][0]["extensions"]["KHR_materials_anisotropy"].get("anisotropyStrength", 1.0) == 1
    assert data["materials"][0]["pbrMetallicRoughness"].get("roughnessFactor", 1.0) == 1


def test_coat_darkening_is_baked_into_a_gltf_base_colour_texture(tmp_path):
    rng = np.random.default_rng(3)
    colour = rng.integers(0, 256, (6, 5, 3), dtype=np.uint8)
    write_png(tmp_path / "albedo.png", colour)
    path = tmp_path / "m.mtlx"
    path.write_text(document('    <input name="base_color" type="color3" nodename="c"/>\n'
                             '    <input name="coat_weight" type="float" value="1"/>\n'
                             '    <input name="coat_ior" type="float" value="1.5"/>',
                             image_node("c", "albedo.png", "color3", "srgb_texture")))
    output = tmp_path / "m.gltf"
    convert(path, "-o", output)
    base = srgb_decode(colour / 255.0)
    # OpenPBR 1.1 "Coat": the base under a coat of IOR n is darkened by (1 - K) / (1 - E K), with
    # K = 1 - (1 - F0(n)) / n^2 and E the base albedo (here the diffuse colour of a dielectric).
    n = 1.5
    k = 1 - (1 - ((n - 1) / (n + 1)) ** 2) / n ** 2
    expected = base * (1 - k) / (1 - base * k)
    written = gltf_image(tmp_path, output, ("pbrMetallicRoughness", "baseColorTexture"))[:, :, :3]
    assert written.shape[:2] == colour.shape[:2]
    assert np.abs(written - srgb_encode(expected)).max() <= 0.5 / 255 + 1e-9
    assert np.any(np.abs(written - colour / 255.0) > 2 / 255)  # the texture did change


def test_standard_surface_output_writes_baked_images_beside_it_with_16_bit_floats(tmp_path, roughness_asset):
    path, r = roughness_asset
    output = tmp_path / "ss.mtlx"
    convert(path, "-o", output, "--to", "standard_surface", "--force")
    folder = tmp_path / "ss_textures"
    baked = folder / "S_specular_roughness.png"
    assert baked.is_file()
    assert 'value="ss_textures/S_specular_roughness.png"' in output.read_text()
    with Image.open(baked) as image:
        assert image.mode.startswith("I;16") and image.size == (12, 8)
        texels = np.asarray(image, dtype=np.float64) / 65535.0
    # MaterialX's Standard Surface (mx_roughness_anisotropy): alpha_x = r^2 / k, alpha_y = r^2 k with
    # k = sqrt(1 - a), so alpha_x alpha_y = r^4 for any a; OpenPBR's alpha_t alpha_b = (1 - a) r^4 2 /
    # (1 + (1 - a)^2). The same anisotropy and the same alpha product is the same lobe.
    a = 0.6
    expected_product = (1 - a) * r ** 4 * 2 / (1 + (1 - a) ** 2)
    assert np.abs(texels ** 4 - expected_product).max() < 2e-4


def test_identity_mappings_pass_textures_through_untouched(tmp_path, roughness_asset):
    path, _ = roughness_asset
    text = path.read_text().replace('value="0.6"', 'value="0"')
    path.write_text(text)
    output = tmp_path / "out.mtlx"
    diagnostics = convert(path, "-o", output, "--to", "standard_surface")
    assert not (tmp_path / "out_textures").exists()
    assert 'value="rough.png"' in output.read_text()
    assert not any("baked" in d["message"] for d in diagnostics)


def test_textures_with_different_uv_transforms_are_reported_not_baked(tmp_path):
    write_png(tmp_path / "a.png", np.full((4, 4), 100))
    write_png(tmp_path / "b.png", np.full((4, 4), 200))
    images = "\n".join([
        '  <place2d name="p" type="vector2"><input name="scale" type="vector2" value="2, 2"/></place2d>',
        image_node("a", "a.png", uv="p"), image_node("b", "b.png")])
    path = tmp_path / "m.mtlx"
    path.write_text(document('    <input name="specular_roughness" type="float" nodename="a"/>\n'
                             '    <input name="specular_roughness_anisotropy" type="float" nodename="b"/>', images))
    diagnostics = convert(path, "-o", tmp_path / "m.gltf")
    lost = [d for d in diagnostics if d["code"] == "OPBR1104" and "roughness" in d["message"]]
    assert lost and "do not line up" in lost[0]["message"]


def test_a_factor_only_gltf_parameter_gets_the_mean_of_the_baked_values(tmp_path):
    write_png(tmp_path / "depth.png", np.array([[0, 255], [255, 0]]))
    path = tmp_path / "m.mtlx"
    path.write_text(document('    <input name="transmission_weight" type="float" value="1"/>\n'
                             '    <input name="transmission_color" type="color3" value="0.5, 0.8, 0.9"/>\n'
                             '    <input name="transmission_depth" type="float" nodename="d" unit="centimeter" unittype="distance"/>',
                             image_node("d", "depth.png")))
    output = tmp_path / "m.gltf"
    diagnostics = convert(path, "-o", output)
    volume = json.loads(output.read_text())["materials"][0]["extensions"]["KHR_materials_volume"]
    # depth texels 0 and 1 cm: the attenuation distance (metres) is the mean over texels where d > 0
    # is infinite... glTF takes one number; the mean of the per-texel values 0.01 m (d = 1) and inf
    # (d = 0) is infinite, so attenuation is absent: written as the mean, reported.
    assert any("takes a single value" in d["message"] for d in diagnostics)
    assert "attenuationDistance" not in volume or volume["attenuationDistance"] > 0


def test_a_texture_outside_the_asset_folder_is_not_read_unless_allowed(tmp_path):
    outside = tmp_path / "library"
    outside.mkdir()
    write_png(outside / "rough.png", np.arange(16).reshape(4, 4) * 16)
    asset = tmp_path / "asset"
    asset.mkdir()
    path = asset / "m.mtlx"
    path.write_text(document('    <input name="specular_roughness" type="float" nodename="r"/>\n'
                             '    <input name="specular_roughness_anisotropy" type="float" value="0.5"/>',
                             image_node("r", "../library/rough.png")))
    output = asset / "ss.mtlx"
    refused = convert(path, "-o", output, "--to", "standard_surface")
    # not read: no bake; the mapping (an affine scale of the roughness) is written as the kept texture's
    # scale, referencing the same file the source does (translate/expressed.scaled_texture)
    assert any(d["code"] == "OPBR1102" and "outside the source asset's folder" in d["message"]
               and "scale and bias" in d["message"] for d in refused)
    assert not (asset / "ss_textures").exists()
    assert "../library/rough.png" in output.read_text()
    allowed = convert(path, "-o", output, "--to", "standard_surface", "--force", "--allow-outside", outside)
    assert any("baked per texel" in d["message"] for d in allowed)
    assert (asset / "ss_textures" / "S_specular_roughness.png").is_file()


def test_a_texture_escaping_through_a_symlink_is_not_read(tmp_path):
    outside = tmp_path / "secret"
    outside.mkdir()
    write_png(outside / "rough.png", np.full((4, 4), 128))
    asset = tmp_path / "asset"
    asset.mkdir()
    os.symlink(outside / "rough.png", asset / "rough.png")
    path = asset / "m.mtlx"
    path.write_text(document('    <input name="specular_roughness" type="float" nodename="r"/>\n'
                             '    <input name="specular_roughness_anisotropy" type="float" value="0.5"/>',
                             image_node("r", "rough.png")))
    diagnostics = convert(path, "-o", asset / "ss.mtlx", "--to", "standard_surface")
    assert any(d["code"] in ("OPBR1102", "OPBR1104") and "outside the source asset's folder" in d["message"]
               for d in diagnostics)
    assert not (asset / "ss_textures").exists()  # not read, so nothing baked from it


def test_baking_is_deterministic(tmp_path, roughness_asset):
    path, _ = roughness_asset
    outputs = []
    for run in ("a", "b"):
        folder = tmp_path / run
        folder.mkdir()
        convert(path, "-o", folder / "m.glb")
        convert(path, "-o", folder / "ss.mtlx", "--to", "standard_surface")
        outputs.append({name: (folder / name).read_bytes() for name in ("m.glb", "ss_textures/S_specular_roughness.png")})
    assert outputs[0] == outputs[1]


def test_a_failed_write_leaves_no_baked_images(tmp_path, roughness_asset, monkeypatch):
    import openpbr_tools.io.mtlx.writer as writer

    def fail(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(writer, "write_mtlx", fail)
    from openpbr_tools.convert import convert_file

    path, _ = roughness_asset
    with pytest.raises(OSError):
        convert_file(str(path), str(tmp_path / "ss.mtlx"), "standard_surface")
    assert not (tmp_path / "ss.mtlx").exists()
    assert not (tmp_path / "ss_textures" / "S_specular_roughness.png").exists()


def test_values_beyond_one_are_baked_to_half_float_exr(tmp_path):
    pytest.importorskip("OpenImageIO", reason="OpenEXR output needs the images extra")
    import OpenImageIO as oiio

    from openpbr_tools import tables
    from openpbr_tools.model import Constant, Input, Location, Material, Texture
    from openpbr_tools.bake import Baker
    from openpbr_tools.translate.common import Mapping, Values

    write_png(tmp_path / "w.png", np.array([[0, 64], [128, 255]]))
    here = Location(str(tmp_path / "m.mtlx"))
    material = Material(name="S", model="open_pbr_surface", location=here, version="1.1.1")
    material.inputs["emission_luminance"] = Input("emission_luminance", "float", Texture("w.png", "float"), here)
    material.inputs["base_weight"] = Input("base_weight", "float", Constant(1.0), here)
    baker = Baker(str(tmp_path / "m.mtlx"), str(tmp_path / "baked"))
    mapping = Mapping("emission_luminance", ("emission_luminance", "base_weight"), lambda e, w: 1000.0 * e * w)
    baked = baker.bake(material, mapping, Values(material, tables.table("open_pbr_surface", "1.1.1")), "float", "test")
    assert baked.input.value.file.endswith(".exr")
    path = tmp_path / "read.exr"
    path.write_bytes(baker.images[baked.input.value.file])
    texels = np.asarray(oiio.ImageBuf(str(path)).get_pixels(oiio.FLOAT))[:, :, 0]
    expected = 1000.0 * np.array([[0, 64], [128, 255]]) / 255.0
    assert np.allclose(texels, expected, rtol=1e-3)  # half float: 11 significant bits


def test_a_baked_texture_falls_back_to_its_mean_so_verify_sees_it(tmp_path):
    """The image default is the mean baked value, encoded like the texels (MaterialX applies the
    file's colour space to the default as well): --verify then evaluates the texture at its mean."""
    # (mid colours, which the coat's darkening changes: pure primaries and white come out as they went in, and since
    # session 28 a formula that leaves every texel as it was keeps the source texture, no bake)
    colour = np.array([[[200, 30, 30], [30, 200, 30]], [[30, 30, 200], [128, 128, 128]]], dtype=np.uint8)
    write_png(tmp_path / "albedo.png", colour)
    path = tmp_path / "m.mtlx"
    path.write_text(document('    <input name="base_color" type="color3" nodename="c"/>\n'
                             '    <input name="coat_weight" type="float" value="1"/>',
                             image_node("c", "albedo.png", "color3", "srgb_texture")))
    from openpbr_tools.io import read_asset
    from openpbr_tools.convert import convert_file

    conversion = convert_file(str(path), str(tmp_path / "ss.mtlx"), "standard_surface")
    texture = read_asset(str(tmp_path / "ss.mtlx")).materials[0].inputs["base_color"].value
    with Image.open(tmp_path / texture.file) as image:
        texels = srgb_decode(np.asarray(image, dtype=np.float64) / 255.0)
    assert texture.colorspace == "srgb_texture"
    assert srgb_decode(np.asarray(texture.fallback)) == pytest.approx(texels.reshape(-1, 3).mean(axis=0), abs=2e-3)
    assert conversion.materials[0].inputs["base_color"].value.fallback == pytest.approx(texture.fallback, abs=1e-6)
