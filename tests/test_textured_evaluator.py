"""The texture-aware evaluator: textures read per pixel in previews, with expectations computed here
independently (texel colours decoded by hand with the sRGB curve of IEC 61966-2-1, closed-form
Lambertian shading under the rig, UV conventions from the MaterialX and glTF specifications)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from PIL import Image

from openpbr_tools.evaluate import build_model
from openpbr_tools.evaluate.preview import Environment, Rig, shade, swatch_geometry
from openpbr_tools.evaluate.textures import TextureSampler, UVs
from openpbr_tools.evaluate.verify import render_material
from openpbr_tools.io import read_asset
from openpbr_tools.model import Texture, UVTransform

CHECKER = np.array([  # 4 x 4 sRGB texels, row 0 = top of the file
    [[230, 40, 30], [20, 20, 20], [40, 200, 60], [250, 250, 250]],
    [[20, 20, 20], [30, 60, 220], [250, 250, 250], [200, 180, 40]],
    [[128, 0, 128], [250, 250, 250], [10, 10, 10], [90, 90, 200]],
    [[250, 250, 250], [60, 160, 160], [200, 100, 20], [0, 0, 0]],
], dtype=np.uint8)


def srgb_decode(c8):
    """IEC 61966-2-1 sRGB EOTF, written here (not the code under test)."""
    c = np.asarray(c8, dtype=float) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def write_png(path, pixels):
    Image.fromarray(np.asarray(pixels, dtype=np.uint8)).save(path)
    return path


def checker_mtlx(folder, place2d: str = ""):
    write_png(folder / "checker.png", CHECKER)
    texcoord = '<input name="texcoord" type="vector2" nodename="uv" />' if place2d else ""
    (folder / "checker.mtlx").write_text(f"""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  {place2d}
  <image name="tex" type="color3">
    <input name="file" type="filename" value="checker.png" colorspace="srgb_texture" />
    {texcoord}
  </image>
  <open_pbr_surface name="Checker" type="surfaceshader">
    <input name="base_color" type="color3" nodename="tex" />
    <input name="specular_weight" type="float" value="0" />
    <input name="base_diffuse_roughness" type="float" value="0" />
  </open_pbr_surface>
  <surfacematerial name="Checker_material" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="Checker" />
  </surfacematerial>
</materialx>
""")
    return folder / "checker.mtlx"


def lambert(albedo, normal, rig=Rig()):
    """Radiance of a Lambertian surface of ``albedo`` (linear) with world ``normal`` under the rig,
    seen head-on: albedo (ambient + E cos / pi); the uniform environment's reflection is albedo
    times its radiance."""
    cos = max(0.0, float(np.dot(normal, rig.key)))
    return np.asarray(albedo) * (rig.environment_radiance + rig.key_irradiance * cos / math.pi)


def test_swatch_shows_each_texel_decoded_by_hand(tmp_path):
    asset = read_asset(str(checker_mtlx(tmp_path)))
    rig = Rig(size=4)  # one pixel per texel: pixel centres are texel centres
    swatch = render_material(asset.materials[0], rig, TextureSampler.for_asset(asset.path), "swatch")
    assert swatch.textured and not any("not evaluated" in n for n in swatch.notes)
    expected = np.array([[lambert(srgb_decode(CHECKER[r, c]), (0, 0, 1)) for c in range(4)] for r in range(4)])
    assert np.allclose(swatch.image, expected, atol=2e-5)


def test_without_a_sampler_the_texture_is_not_evaluated(tmp_path):
    asset = read_asset(str(checker_mtlx(tmp_path)))
    swatch = render_material(asset.materials[0], Rig(size=4), None, "swatch")
    assert not swatch.textured and any("base_color: textured (not evaluated" in n for n in swatch.notes)
    assert np.ptp(swatch.image.reshape(-1, 3), axis=0).max() < 1e-9


def test_place2d_scale_tiles_the_texture(tmp_path):
    # place2d divides by scale: 0.5 shows the texture twice across [0, 1] (MaterialX NG_place2d_vector2).
    path = checker_mtlx(tmp_path, '<place2d name="uv" type="vector2"><input name="scale" type="vector2" value="0.5, 0.5" /></place2d>')
    asset = read_asset(str(path))
    swatch = render_material(asset.materials[0], Rig(size=8), TextureSampler.for_asset(asset.path), "swatch")
    expected = np.array([[lambert(srgb_decode(CHECKER[r % 4, c % 4]), (0, 0, 1)) for c in range(8)] for r in range(8)])
    assert np.allclose(swatch.image, expected, atol=2e-5)


def test_gltf_texture_lands_where_the_mtlx_one_does(tmp_path):
    """glTF's UV origin is the image's top-left (glTF 2.0, 3.8.4.4); read through the glTF reader,
    the same image shows the same texel at the same place of the swatch."""
    write_png(tmp_path / "checker.png", CHECKER)
    document = {
        "asset": {"version": "2.0"},
        "images": [{"uri": "checker.png"}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987}],
        "textures": [{"source": 0, "sampler": 0}],
        "materials": [{"name": "Checker", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}}],
    }
    (tmp_path / "checker.gltf").write_text(json.dumps(document))
    gltf = read_asset(str(tmp_path / "checker.gltf"))
    mtlx = read_asset(str(checker_mtlx(tmp_path)))
    rig = Rig(size=4)
    a = render_material(gltf.materials[0], rig, TextureSampler.for_asset(gltf.path), "swatch").image
    b = render_material(mtlx.materials[0], rig, TextureSampler.for_asset(mtlx.path), "swatch").image
    # Same luminance ordering texel by texel (the models' diffuse and specular differ a little).
    lum_a, lum_b = a @ [0.2126, 0.7152, 0.0722], b @ [0.2126, 0.7152, 0.0722]
    assert np.array_equal(np.argsort(lum_a.ravel()), np.argsort(lum_b.ravel()))


def test_sphere_preview_shows_the_texture_at_its_uv(tmp_path):
    """The sphere's UVs: u = 1/2 + atan2(x, z) / 2 pi, v = 1/2 + asin(y) / pi (V up: texel row 0 of
    the file at v = 1, texel centres at (i + 1/2) / 4). At 64 pixels a 4 x 4 texture is magnified
    (under a texel per pixel: no mip level above 0), so each pixel is the bilinear blend of the
    four nearest hand-decoded texels (periodic wrap), shaded Lambertian with the pixel's normal."""
    asset = read_asset(str(checker_mtlx(tmp_path)))
    rig = Rig(size=64)
    sphere = render_material(asset.materials[0], rig, TextureSampler.for_asset(asset.path), "sphere")
    decoded = srgb_decode(CHECKER)
    c = -rig.extent + (np.arange(64) + 0.5) * (2 * rig.extent / 64)
    checked = 0
    for row_px in range(0, 64, 3):
        for col_px in range(0, 64, 3):
            x, y = c[col_px], -c[row_px]
            if x * x + y * y >= 0.9:
                continue
            z = math.sqrt(1 - x * x - y * y)
            u, v = 0.5 + math.atan2(x, z) / (2 * math.pi), 0.5 + math.asin(y) / math.pi
            tx, ty = u * 4 - 0.5, (1 - v) * 4 - 0.5
            x0, y0 = math.floor(tx), math.floor(ty)
            fx, fy = tx - x0, ty - y0
            texel = sum(w * decoded[yy % 4, xx % 4] for w, yy, xx in (
                ((1 - fx) * (1 - fy), y0, x0), (fx * (1 - fy), y0, x0 + 1),
                ((1 - fx) * fy, y0 + 1, x0), (fx * fy, y0 + 1, x0 + 1)))
            assert np.allclose(sphere.image[row_px, col_px], lambert(texel, (x, y, z)), rtol=1e-3, atol=1e-5), (row_px, col_px)
            checked += 1
    assert checked > 250


def _sampler_for(tmp_path, pixels, name="t.png"):
    write_png(tmp_path / name, pixels)
    return TextureSampler.for_asset(str(tmp_path / "asset.mtlx")), str(tmp_path / name)


def _at(uv):
    uv = np.asarray(uv, dtype=float)
    tiny = np.full_like(uv, 1e-6)
    return UVs(uv, tiny, tiny)


@pytest.mark.parametrize("mode, u, column", [
    ("periodic", 1.125, 0), ("periodic", -0.125, 3), ("clamp", 1.4, 3), ("clamp", -0.3, 0),
    ("mirror", 1.125, 3), ("mirror", -0.125, 0), ("mirror", 1.875, 0),
])
def test_wrap_modes_pick_the_texel_the_specification_names(tmp_path, mode, u, column):
    row = np.array([[[0, 0, 0], [80, 80, 80], [160, 160, 160], [240, 240, 240]]], dtype=np.uint8)
    sampler, file = _sampler_for(tmp_path, row)
    texture = Texture(file=file, colorspace="none", wrap=(mode, "periodic"))
    value = sampler.sample(texture, "float", _at([[u, 0.5]]), "m.p")
    assert value[0] == pytest.approx(row[0, column, 0] / 255.0, abs=1e-6)


def test_constant_wrap_is_zero_outside(tmp_path):
    sampler, file = _sampler_for(tmp_path, np.full((2, 2, 3), 200, dtype=np.uint8))
    texture = Texture(file=file, colorspace="none", wrap=("constant", "black"))
    values = sampler.sample(texture, "float", _at([[0.5, 0.5], [1.5, 0.5], [0.5, -0.2]]), "m.p")
    assert values.tolist() == pytest.approx([200 / 255.0, 0.0, 0.0])


def test_bilinear_between_texel_centres(tmp_path):
    sampler, file = _sampler_for(tmp_path, np.array([[[0, 0, 0], [200, 200, 200]]], dtype=np.uint8))
    texture = Texture(file=file, colorspace="none", wrap=("clamp", "clamp"))
    # texel centres at u = 0.25 and 0.75; a quarter of the way between them
    assert sampler.sample(texture, "float", _at([[0.375, 0.5]]), "m.p")[0] == pytest.approx(0.25 * 200 / 255.0)


def test_udim_tiles_are_read_by_tile_number(tmp_path):
    write_png(tmp_path / "t.1001.png", np.full((2, 2, 3), 50, dtype=np.uint8))
    write_png(tmp_path / "t.1002.png", np.full((2, 2, 3), 150, dtype=np.uint8))
    write_png(tmp_path / "t.1011.png", np.full((2, 2, 3), 250, dtype=np.uint8))
    sampler = TextureSampler.for_asset(str(tmp_path / "asset.mtlx"))
    texture = Texture(file=str(tmp_path / "t.<UDIM>.png"), colorspace="none")
    values = sampler.sample(texture, "float", _at([[0.5, 0.5], [1.5, 0.5], [0.5, 1.5], [2.5, 0.5]]), "m.p")
    assert values.tolist() == pytest.approx([50 / 255, 150 / 255, 250 / 255, 0.0])
    assert any("1003" in text for _, text in sampler.notes)  # the missing tile is reported


def test_normal_map_tilts_the_shading_normal(tmp_path):
    """A flat normal map of texel (t_x, 128, t_z): MaterialX normalmap decodes n = 2t - 1 and
    scales x, y by the strength; the swatch's frame is T = +x, B = +y, N = +z, so the world normal
    is normalize(s (2 t_x - 1), s (2 t_y - 1), 2 t_z - 1) and Lambertian shading follows its cosine."""
    texel = np.array([200, 128, 220], dtype=np.uint8)
    write_png(tmp_path / "n.png", np.tile(texel, (2, 2, 1)))
    strength = 0.7
    (tmp_path / "n.mtlx").write_text(f"""<?xml version="1.0"?>
<materialx version="1.39">
  <image name="nimg" type="vector3"><input name="file" type="filename" value="n.png" /></image>
  <normalmap name="nmap" type="vector3"><input name="in" type="vector3" nodename="nimg" />
    <input name="scale" type="float" value="{strength}" /></normalmap>
  <open_pbr_surface name="N" type="surfaceshader">
    <input name="base_color" type="color3" value="0.5, 0.5, 0.5" />
    <input name="specular_weight" type="float" value="0" />
    <input name="base_diffuse_roughness" type="float" value="0" />
    <input name="geometry_normal" type="vector3" nodename="nmap" />
  </open_pbr_surface>
</materialx>
""")
    asset = read_asset(str(tmp_path / "n.mtlx"))
    swatch = render_material(asset.materials[0], Rig(size=2), TextureSampler.for_asset(asset.path), "swatch")
    t = texel / 255.0
    n = np.array([strength * (2 * t[0] - 1), strength * (2 * t[1] - 1), 2 * t[2] - 1])
    n /= np.linalg.norm(n)
    assert np.allclose(swatch.image[0, 0], lambert([0.5] * 3, n), atol=2e-5)
    assert not np.allclose(swatch.image[0, 0], lambert([0.5] * 3, (0, 0, 1)), atol=1e-3)


def test_usd_normal_texture_uses_its_scale_and_bias(tmp_path):
    sampler, file = _sampler_for(tmp_path, np.tile(np.array([200, 128, 220], dtype=np.uint8), (2, 2, 1)))
    texture = Texture(file=file, colorspace="raw", normal_map=1.0, node_category="UsdUVTexture",
                      scale=(2.0, 2.0, 2.0), bias=(-1.0, -1.0, -1.0))
    value = sampler.sample(texture, "vector3", _at([[0.5, 0.5]]), "m.normal")[0]
    assert value == pytest.approx(2 * np.array([200, 128, 220]) / 255.0 - 1, abs=1e-6)
    bare = Texture(file=file, colorspace="raw", normal_map=1.0, node_category="UsdUVTexture")
    # no scale/bias: the texel is the normal as it is (UsdPreviewSurface applies no decode of its own)
    assert sampler.sample(bare, "vector3", _at([[0.5, 0.5]]), "m.normal")[0] == pytest.approx(
        np.array([200, 128, 220]) / 255.0, abs=1e-6)


def test_place2d_rotation_follows_materialx_rotate2d():
    from openpbr_tools.evaluate.textures import place2d

    # rotate2d turns (x, y) into (c x + s y, -s x + c y), degrees (MaterialX stdlib); pivot 0.
    out = place2d(np.array([[1.0, 0.0]]), UVTransform(rotate=90.0))
    assert out[0] == pytest.approx([0.0, -1.0], abs=1e-12)
    out = place2d(np.array([[0.75, 0.5]]), UVTransform(scale=(0.5, 2.0), offset=(0.1, 0.2), pivot=(0.5, 0.5)))
    assert out[0] == pytest.approx([(0.25 / 0.5) - 0.1 + 0.5, 0.0 - 0.2 + 0.5])


def test_uniform_environment_matches_the_rig_ambient():
    """A constant latitude-longitude map of radiance L is the rig's uniform environment with no key
    light: the reduction has no directional lights and its mean is L."""
    env = Environment.from_latlong(np.full((32, 64, 3), 0.35))
    assert env.lights == [] and env.mean == pytest.approx([0.35] * 3)
    model = build_model("open_pbr_surface", {"base_color": (0.5, 0.5, 0.5), "specular_weight": 0.0,
                                             "base_diffuse_roughness": 0.0})
    image, mask = shade(model, swatch_geometry(Rig(size=2)), Rig(size=2), environment=env)
    assert np.allclose(image[mask], 0.5 * 0.35, atol=1e-6)


def test_environment_sun_lights_from_its_direction():
    """One bright cell at MaterialX's latlong (u, v) = (0.5, 0.25): direction (0, cos(pi/4),
    -sin(pi/4))... i.e. up and towards -z; a swatch facing +z sees it at cos = 0 -> only ambient;
    one at u = 0 (towards +z) lights it."""
    radiance = np.zeros((16, 32, 3))
    radiance[4, 0] = 100.0  # u ~ 0: towards +z, v ~ 0.28: above the horizon
    env = Environment.from_latlong(radiance)
    direction, _ = env.lights[0]
    assert direction[2] > 0.5 and direction[1] > 0.5 and abs(direction[0]) < 0.2


def test_textured_preview_cli_shows_the_texture(tmp_path):
    from click.testing import CliRunner

    from cli.group import cli

    path = checker_mtlx(tmp_path)
    out = tmp_path / "p.png"
    result = CliRunner().invoke(cli, ["preview", str(path), "-o", str(out), "--shape", "swatch", "--size", "16"])
    assert result.exit_code == 0, result.output
    pixels = np.asarray(Image.open(out).convert("RGB"))[:16, :16]
    assert len({tuple(p) for p in pixels.reshape(-1, 3)}) >= 8  # the checker's colours, not one grey


def test_minified_texture_reads_its_average(tmp_path):
    """A 64 x 64 one-texel checker of 0 and 1 seen through 4 x 4 pixels (16 texels per pixel):
    mip-mapping gives each pixel the checker's box average, 1/2, where a single bilinear tap would
    give 0 or 1 (aliasing)."""
    checker = (np.indices((64, 64)).sum(axis=0) % 2 * 255).astype(np.uint8)
    sampler, file = _sampler_for(tmp_path, np.repeat(checker[:, :, None], 3, axis=2))
    texture = Texture(file=file, colorspace="none")
    from openpbr_tools.evaluate.preview import swatch_geometry

    uvs = swatch_geometry(Rig(size=4)).uvs
    assert sampler.sample(texture, "float", uvs, "m.p") == pytest.approx(np.full(16, 0.5), abs=1e-6)
    magnified = swatch_geometry(Rig(size=64)).uvs  # one pixel per texel: the texels themselves
    values = sampler.sample(texture, "float", magnified, "m.p")
    assert values == pytest.approx(checker.ravel() / 255.0, abs=1e-6)  # swatch row 0 is image row 0


def test_gltf_anisotropy_direction_texture_turns_the_highlight(tmp_path):
    """KHR_materials_anisotropy: the texture's R, G hold a tangent-space direction (2 t - 1), added to
    anisotropyRotation. A texture pointing along the bitangent (R 0.5, G 1) renders as rotation
    atan2(1, 0.0039) (about pi/2) without a texture; B = 1 keeps the strength factor."""
    import json

    write_png(tmp_path / "aniso.png", np.tile(np.array([128, 255, 255], dtype=np.uint8), (4, 4, 1)))
    def material(name, extension):
        return {"name": name, "pbrMetallicRoughness": {"metallicFactor": 1.0, "roughnessFactor": 0.3},
                "extensions": {"KHR_materials_anisotropy": extension}}
    document = {
        "asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_anisotropy"],
        "images": [{"uri": "aniso.png"}], "textures": [{"source": 0}],
        "materials": [material("Textured", {"anisotropyStrength": 0.8, "anisotropyTexture": {"index": 0}}),
                      material("Rotated", {"anisotropyStrength": 0.8,
                                           "anisotropyRotation": math.atan2(2 * 255 / 255 - 1, 2 * 128 / 255 - 1)}),
                      material("Plain", {"anisotropyStrength": 0.8})],
    }
    (tmp_path / "a.gltf").write_text(json.dumps(document))
    asset = read_asset(str(tmp_path / "a.gltf"))
    sampler = TextureSampler.for_asset(asset.path)
    rig = Rig(size=48)
    textured, rotated, plain = (render_material(m, rig, sampler).image for m in asset.materials)
    # G 255 encodes 2 * 255/255 - 1 = 1, R 128 encodes 2 * 128/255 - 1 = 0.0039: atan2(1, 0.0039)
    assert np.abs(textured - rotated).max() < 1e-5
    assert np.abs(textured - plain).max() > 0.05


def _textured_samples():
    from openpbr_tools.resources import data_dir

    here = __import__("pathlib").Path(__file__).parent
    paths = sorted(data_dir("samples").glob("*.mtlx")) + sorted((here / "data" / "translation_set").glob("textured_*"))
    return [p for p in paths if read_asset(str(p)).materials and any(m.textures() for m in read_asset(str(p)).materials)]


@pytest.mark.parametrize("path", _textured_samples(), ids=lambda p: p.name)
def test_every_textured_sample_preview_shows_its_textures(path):
    asset = read_asset(str(path))
    sampler = TextureSampler.for_asset(asset.path)
    for material in asset.materials:
        if not material.textures():
            continue
        swatch = render_material(material, Rig(size=32), sampler, "swatch")
        assert swatch.textured
        assert not any("textured (not evaluated" in note for note in swatch.notes), swatch.notes
        assert np.ptp(swatch.image.reshape(-1, 3), axis=0).max() > 1e-3  # the texture varies across the swatch


def test_preview_environment_from_an_hdr_file(tmp_path):
    """`preview --environment`: a Radiance .hdr (written with OpenImageIO) of uniform radiance 0.35
    lights a grey Lambertian swatch to albedo x 0.35 (no key light: the environment replaces the rig)."""
    import OpenImageIO as oiio
    from click.testing import CliRunner

    from cli.group import cli

    hdr = str(tmp_path / "sky.hdr")
    out = oiio.ImageOutput.create(hdr)
    assert out.open(hdr, oiio.ImageSpec(32, 16, 3, oiio.FLOAT))
    out.write_image(np.full((16, 32, 3), 0.35, dtype=np.float32))
    out.close()
    (tmp_path / "grey.mtlx").write_text("""<?xml version="1.0"?>
<materialx version="1.39"><open_pbr_surface name="G" type="surfaceshader">
  <input name="base_color" type="color3" value="0.5, 0.5, 0.5" /><input name="specular_weight" type="float" value="0" />
  <input name="base_diffuse_roughness" type="float" value="0" /></open_pbr_surface></materialx>""")
    png = tmp_path / "p.png"
    result = CliRunner().invoke(cli, ["preview", str(tmp_path / "grey.mtlx"), "-o", str(png), "--shape", "swatch",
                                      "--size", "16", "--environment", hdr])
    assert result.exit_code == 0, result.output
    pixel = np.asarray(Image.open(png).convert("RGB"))[8, 8]
    expected = 255 * (1.055 * (0.5 * 0.35) ** (1 / 2.4) - 0.055)  # sRGB encoding of 0.175 (IEC 61966-2-1)
    assert np.all(np.abs(pixel - expected) <= 1), (pixel, expected)
    bad = CliRunner().invoke(cli, ["preview", str(tmp_path / "grey.mtlx"), "-o", str(png), "--environment",
                                   str(tmp_path / "grey.mtlx")])
    assert bad.exit_code == 2 and "latitude-longitude" in bad.output


def test_tangent_map_turns_the_anisotropic_highlight(tmp_path):
    """An OpenPBR geometry_tangent read through a normalmap decode is a tangent-space direction: a
    texel (128, 255, 128) decodes to about +B, so on the swatch (T = +x, B = +y, N = +z) the
    tangent becomes +y and the bitangent n x t = -x. Expected: the same constant material shaded on
    a swatch whose frame is built that way by hand."""
    import dataclasses

    write_png(tmp_path / "t.png", np.tile(np.array([128, 255, 128], dtype=np.uint8), (2, 2, 1)))
    (tmp_path / "t.mtlx").write_text("""<?xml version="1.0"?>
<materialx version="1.39">
  <image name="timg" type="vector3"><input name="file" type="filename" value="t.png" /></image>
  <normalmap name="tdecode" type="vector3"><input name="in" type="vector3" nodename="timg" /></normalmap>
  <open_pbr_surface name="A" type="surfaceshader">
    <input name="base_metalness" type="float" value="1" />
    <input name="specular_roughness" type="float" value="0.4" />
    <input name="specular_roughness_anisotropy" type="float" value="0.9" />
    <input name="geometry_tangent" type="vector3" nodename="tdecode" />
  </open_pbr_surface>
</materialx>""")
    asset = read_asset(str(tmp_path / "t.mtlx"))
    rig = Rig(size=8, key_direction=(0.5, 0.2, 0.8))
    swatch = render_material(asset.materials[0], rig, TextureSampler.for_asset(asset.path), "swatch")
    assert swatch.textured and not swatch.notes
    d = 2 * 128 / 255 - 1  # the decoded x and z components (0.0039), y = 1
    t = np.array([d, 1.0, 0.0]) / np.hypot(d, 1.0)  # projected on the tangent plane (z dropped)
    geo = swatch_geometry(rig)
    by_hand = dataclasses.replace(geo, tangent=np.tile(t, (64, 1)), bitangent=np.tile(np.cross([0, 0, 1], t), (64, 1)))
    model = build_model("open_pbr_surface", {"base_metalness": 1.0, "specular_roughness": 0.4,
                                             "specular_roughness_anisotropy": 0.9})
    expected, _ = shade(model, by_hand, rig)
    plain, _ = shade(model, geo, rig)
    assert np.allclose(swatch.image, expected, atol=1e-9)
    assert np.abs(swatch.image - plain).max() > 1e-3  # the turn is visible
