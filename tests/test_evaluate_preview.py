"""Lit-sphere previews against closed forms, and CIEDE2000 against Sharma et al.'s published test
data."""

import warnings

import numpy as np
import pytest

from openpbr_tools.evaluate import build_model
from openpbr_tools.evaluate.difference import compare_images, delta_e_2000, linear_rec709_to_lab
from openpbr_tools.evaluate.preview import Rig, contact_sheet, encode_srgb, shade_sphere

RIG = Rig(size=64)


def _colour():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import colour
    return colour


def pixel_normals(rig):
    c = -rig.extent + (np.arange(rig.size) + 0.5) * 2 * rig.extent / rig.size
    x, y = np.meshgrid(c, -c)
    z = np.sqrt(np.maximum(0.0, 1 - x * x - y * y))
    return np.stack([x, y, z], -1), x * x + y * y < 1


def test_lambertian_sphere_matches_the_closed_form():
    rho = np.array([0.6, 0.3, 0.1])
    # glTF with specular 0 is a pure Lambertian reflector.
    model = build_model("gltf_pbr", {"metallic": 0.0, "specular": 0.0, "base_color": rho})
    image, mask = shade_sphere(model, RIG)
    normals, inside = pixel_normals(RIG)
    np.testing.assert_array_equal(mask, inside)
    cos = np.clip(normals @ RIG.key, 0, None)
    expected = rho * (RIG.environment_radiance + RIG.key_irradiance * cos[..., None] / np.pi)
    np.testing.assert_allclose(image[mask], expected[mask], rtol=1e-9)
    np.testing.assert_allclose(image[~mask], RIG.environment_radiance)


def test_white_energy_preserving_sphere_vanishes_in_a_furnace():
    furnace = Rig(size=32, key_irradiance=0.0, environment_radiance=0.7)
    for model, values in [
        ("open_pbr_surface", {"base_color": [1, 1, 1], "base_diffuse_roughness": 0.6}),
        ("open_pbr_surface", {"base_metalness": 1.0, "base_color": [1, 1, 1], "specular_roughness": 0.7}),
        ("open_pbr_surface", {"transmission_weight": 1.0, "specular_roughness": 0.4}),
    ]:
        image, _ = shade_sphere(build_model(model, values), furnace)
        np.testing.assert_allclose(image, 0.7, atol=0.7 * 2e-3)


def test_emission_adds_and_opacity_shows_the_environment():
    emitting = build_model("gltf_pbr", {"metallic": 0.0, "specular": 0.0, "base_color": [0, 0, 0], "emissive": [0.3, 0.2, 0.1]})
    image, mask = shade_sphere(emitting, RIG)
    np.testing.assert_allclose(image[mask], np.broadcast_to([0.3, 0.2, 0.1], image[mask].shape))
    transparent = build_model("open_pbr_surface", {"geometry_opacity": 0.0})
    image, _ = shade_sphere(transparent, RIG)
    np.testing.assert_allclose(image, RIG.environment_radiance)


def test_preview_is_deterministic():
    model = build_model("open_pbr_surface", {"fuzz_weight": 1.0, "coat_weight": 0.5, "thin_film_weight": 1.0})
    a, _ = shade_sphere(model, RIG)
    b, _ = shade_sphere(model, RIG)
    np.testing.assert_array_equal(a, b)


def test_contact_sheet_layout_and_srgb_encoding():
    assert encode_srgb(np.array([0.0, 0.5, 1.0, 2.0])).tolist() == [0, 188, 255, 255]  # sRGB(0.5) = 0.7354
    image = np.full((32, 32, 3), 0.5)
    sheet = contact_sheet([("a", image), ("b", image), ("c", image)], columns=2, label_height=18)
    assert sheet.size == (64, 2 * (32 + 18))
    assert sheet.getpixel((5, 5)) == (188, 188, 188)


# ---------------------------------------------------------------- colour difference

# Sharma, Wu, Dalal (2005), table 1: pairs 1, 7, 17 and 25 and their CIEDE2000.
SHARMA = [
    ((50.0000, 2.6772, -79.7751), (50.0000, 0.0000, -82.7485), 2.0425),
    ((50.0000, 0.0000, 0.0000), (50.0000, -1.0000, 2.0000), 2.3669),
    ((50.0000, 2.5000, 0.0000), (73.0000, 25.0000, -18.0000), 27.1492),
    ((60.2574, -34.0099, 36.2677), (60.4626, -34.1751, 39.4387), 1.2644),
]


@pytest.mark.parametrize("lab1,lab2,expected", SHARMA)
def test_ciede2000_matches_sharma_test_data(lab1, lab2, expected):
    colour = _colour()
    to_xyz = np.asarray(colour.RGB_COLOURSPACES["sRGB"].matrix_RGB_to_XYZ)
    white = colour.XYZ_to_xy(to_xyz @ np.ones(3))  # D65 as the Rec.709 primaries realise it

    def rgb(lab):
        return np.linalg.solve(to_xyz, colour.Lab_to_XYZ(np.array(lab), white))

    assert float(delta_e_2000(rgb(lab1), rgb(lab2))) == pytest.approx(expected, abs=1e-4)


def test_reference_white_has_lightness_100():
    white = RIG.white()
    np.testing.assert_allclose(linear_rec709_to_lab(np.full(3, white), white), [100.0, 0.0, 0.0], atol=1e-6)


def test_image_difference_summarises_pixels():
    a = np.zeros((4, 4, 3))
    b = np.zeros((4, 4, 3))
    b[0, 0] = 1.0
    d = compare_images(a, b)
    assert d.samples == 16
    assert d.max == pytest.approx(100.0, abs=1e-6)  # black vs white: lightness 0 vs 100
    assert d.mean == pytest.approx(100.0 / 16, abs=1e-6)
