"""Model behaviours the specifications state in closed form, checked at normal incidence on
near-mirror or black configurations where the albedo is the Fresnel factor itself."""

from pathlib import Path

import numpy as np
import pytest

from openpbr_tools.evaluate import build_model
from openpbr_tools.evaluate.openpbr import openpbr_anisotropy

NORMAL = np.array([0.0, 0.0, 1.0])


def albedo_at_normal(model, values):
    return build_model(model, values).albedo(NORMAL).total


# ---------------------------------------------------------------- OpenPBR 1.1.1


def test_openpbr_specular_weight_scales_the_dielectric_f0():
    """OpenPBR 1.1.1: the modulated IOR gives F0 = specular_weight * F0(specular_ior)."""
    values = {"base_color": [0, 0, 0], "specular_roughness": 0.0, "specular_ior": 1.5, "specular_weight": 0.5}
    f0 = 0.5 * ((1.5 - 1) / (1.5 + 1)) ** 2
    np.testing.assert_allclose(albedo_at_normal("open_pbr_surface", values), f0, rtol=2e-3)


@pytest.mark.parametrize("ior", [1.33, 1.5, 2.0])
def test_openpbr_smooth_dielectric_reflects_the_exact_fresnel_factor_at_every_angle(ior):
    from test_evaluate_fresnel import snell_fresnel

    model = build_model("open_pbr_surface", {"base_color": [0, 0, 0], "specular_roughness": 0.0, "specular_ior": ior})
    mu = np.linspace(0.1, 1.0, 19)  # up to 84 degrees; closer to grazing the tables interpolate
    wo = np.stack([np.sqrt(1 - mu * mu), np.zeros_like(mu), mu], -1)
    np.testing.assert_allclose(model.albedo(wo).total[:, 0], snell_fresnel(mu, 1.0, ior), atol=2e-3)


def test_openpbr_specular_weight_zero_leaves_no_reflection():
    values = {"base_color": [0, 0, 0], "specular_weight": 0.0}
    np.testing.assert_allclose(albedo_at_normal("open_pbr_surface", values), 0.0, atol=1e-9)


def test_openpbr_specular_color_tints_dielectric_reflection():
    values = {"base_color": [0, 0, 0], "specular_roughness": 0.0, "specular_color": [1.0, 0.5, 0.25]}
    np.testing.assert_allclose(albedo_at_normal("open_pbr_surface", values), 0.04 * np.array([1.0, 0.5, 0.25]), rtol=2e-3)


def test_openpbr_smooth_metal_reflects_its_base_color_at_normal_incidence():
    colour = np.array([0.95, 0.64, 0.54])
    values = {"base_metalness": 1.0, "base_color": colour, "specular_roughness": 0.0, "specular_color": [0.3, 0.6, 0.9]}
    np.testing.assert_allclose(albedo_at_normal("open_pbr_surface", values), colour, rtol=2e-3)


def test_openpbr_metal_edge_tint_is_not_scaled_by_specular_weight_in_1_1_1():
    base = {"base_metalness": 1.0, "base_color": [0.9, 0.9, 0.9], "specular_roughness": 0.0, "specular_color": [0.5, 0.5, 0.5]}
    grazing = np.array([np.sqrt(1 - (1 / 7) ** 2), 0.0, 1 / 7])
    full = build_model("open_pbr_surface", base).albedo(grazing).total
    half = build_model("open_pbr_surface", dict(base, specular_weight=0.5)).albedo(grazing).total
    np.testing.assert_allclose(half, 0.5 * full, rtol=1e-6)  # the weight scales the lobe, not the tint


def test_openpbr_anisotropy_mapping():
    r, a = 0.6, 0.5
    alpha_t = r * r * np.sqrt(2 / (1 + (1 - a) ** 2))
    np.testing.assert_allclose(openpbr_anisotropy(r, a), (alpha_t, (1 - a) * alpha_t))
    np.testing.assert_allclose(openpbr_anisotropy(r, 0.0), (r * r, r * r))


def test_openpbr_coat_darkening_follows_the_spec_formula():
    """Base darkening (1 - K) / (1 - E_base K), K = 1 - (1 - F0_coat) / coat_ior^2, for a white
    Lambertian base under a clear, non-reflecting-at-normal... coat: compare coated base albedo
    with darkening on and off at normal incidence."""
    base = {"base_color": [0.6, 0.6, 0.6], "specular_weight": 0.0, "coat_weight": 1.0, "coat_roughness": 0.0, "coat_ior": 1.6}
    on = albedo_at_normal("open_pbr_surface", dict(base, coat_darkening=1.0))
    off = albedo_at_normal("open_pbr_surface", dict(base, coat_darkening=0.0))
    f0 = ((1.6 - 1) / 2.6) ** 2
    k = 1 - (1 - f0) / 1.6**2
    darkening = (1 - k) / (1 - 0.6 * k)
    np.testing.assert_allclose(on - f0, (off - f0) * darkening, rtol=2e-3)


def test_openpbr_coat_color_absorbs_the_base_but_not_the_coat_reflection():
    base = {"base_color": [1, 1, 1], "specular_weight": 0.0, "coat_weight": 1.0, "coat_roughness": 0.0, "coat_darkening": 0.0}
    tinted = albedo_at_normal("open_pbr_surface", dict(base, coat_color=[1.0, 0.5, 0.0]))
    f0 = ((1.6 - 1) / 2.6) ** 2
    np.testing.assert_allclose(tinted, f0 + (1 - f0) * np.array([1.0, 0.5, 0.0]), rtol=2e-3)


def test_openpbr_emission_is_luminance_times_colour_and_dimmed_by_a_coat():
    values = {"emission_luminance": 2.0, "emission_color": [1.0, 0.5, 0.25]}
    np.testing.assert_allclose(build_model("open_pbr_surface", values).emission(NORMAL), [2.0, 1.0, 0.5])
    coated = build_model("open_pbr_surface", dict(values, coat_weight=1.0, coat_color=[0.5, 1, 1])).emission(NORMAL)
    f0 = ((1.6 - 1) / 2.6) ** 2
    np.testing.assert_allclose(coated, np.array([2.0, 1.0, 0.5]) * [0.5, 1, 1] * (1 - f0))


def test_openpbr_fuzz_over_black_reflects_the_zeltner_albedo():
    from openpbr_tools.evaluate.sheen import zeltner_sheen_albedo

    values = {"base_color": [0, 0, 0], "specular_weight": 0.0, "fuzz_weight": 1.0, "fuzz_color": [1.0, 0.5, 0.2], "fuzz_roughness": 0.4}
    np.testing.assert_allclose(albedo_at_normal("open_pbr_surface", values), zeltner_sheen_albedo(1.0, 0.4) * np.array([1, 0.5, 0.2]))


def test_openpbr_opacity_is_the_coverage():
    assert build_model("open_pbr_surface", {"geometry_opacity": 0.3}).opacity == pytest.approx(0.3)


def test_openpbr_transmission_depth_turns_the_colour_into_absorption():
    model = build_model("open_pbr_surface", {"transmission_weight": 1.0, "transmission_color": [0.5, 0.25, 1.0], "transmission_depth": 2.0})
    # Beer-Lambert: after transmission_depth the light has the transmission colour.
    np.testing.assert_allclose(np.exp(-model.volume_absorption * 2.0), [0.5, 0.25, 1.0], rtol=1e-9)


# ---------------------------------------------------------------- glTF


def test_gltf_specular_extension_sets_f0():
    values = {"metallic": 0.0, "base_color": [0, 0, 0], "roughness": 0.0, "ior": 1.5, "specular": 0.5, "specular_color": [1.0, 0.5, 0.2]}
    expected = 0.04 * np.array([1.0, 0.5, 0.2]) * 0.5
    np.testing.assert_allclose(albedo_at_normal("gltf_pbr", values), expected, rtol=2e-3)


def test_gltf_clearcoat_reflects_four_percent_at_normal_incidence():
    values = {"metallic": 0.0, "base_color": [0, 0, 0], "specular": 0.0, "clearcoat": 1.0, "clearcoat_roughness": 0.0}
    np.testing.assert_allclose(albedo_at_normal("gltf_pbr", values), 0.04, rtol=2e-3)


def test_gltf_emission_strength_multiplies_emissive():
    model = build_model("gltf_pbr", {"emissive": [1.0, 0.5, 0.0], "emissive_strength": 4.0})
    np.testing.assert_allclose(model.emission(NORMAL), [4.0, 2.0, 0.0])


@pytest.mark.parametrize("mode,alpha,expected", [(0, 0.2, 1.0), (1, 0.4, 0.0), (1, 0.6, 1.0), (2, 0.3, 0.3)])
def test_gltf_alpha_modes(mode, alpha, expected):
    model = build_model("gltf_pbr", {"alpha_mode": mode, "alpha": alpha, "alpha_cutoff": 0.5})
    assert float(model.opacity) == pytest.approx(expected)


def test_gltf_smooth_metal_reflects_its_base_color():
    np.testing.assert_allclose(
        albedo_at_normal("gltf_pbr", {"metallic": 1.0, "base_color": [1.0, 0.77, 0.34], "roughness": 0.0}), [1.0, 0.77, 0.34], rtol=2e-3
    )


# ---------------------------------------------------------------- UsdPreviewSurface


def test_usd_metallic_workflow_interpolates_f0_and_diffuse():
    values = {"diffuseColor": [1.0, 0.0, 0.0], "metallic": 0.5, "roughness": 0.0, "ior": 1.5}
    f0 = 0.04 + (np.array([1.0, 0.0, 0.0]) - 0.04) * 0.5
    # Specular F0 plus the diffuse (weight 1 - metallic) under it.
    expected = f0 + (1 - np.mean(f0)) * 0.5 * np.array([1.0, 0.0, 0.0])
    np.testing.assert_allclose(albedo_at_normal("UsdPreviewSurface", values), expected, rtol=3e-3)


def test_usd_specular_workflow_uses_specular_color_as_f0():
    values = {"useSpecularWorkflow": 1, "diffuseColor": [0, 0, 0], "specularColor": [0.5, 0.3, 0.1], "roughness": 0.0}
    np.testing.assert_allclose(albedo_at_normal("UsdPreviewSurface", values), [0.5, 0.3, 0.1], rtol=2e-3)


def test_usd_opacity_threshold_cuts_out():
    assert float(build_model("UsdPreviewSurface", {"opacity": 0.3, "opacityThreshold": 0.5}).opacity) == 0.0
    assert float(build_model("UsdPreviewSurface", {"opacity": 0.7, "opacityThreshold": 0.5}).opacity) == 1.0


# ---------------------------------------------------------------- Standard Surface


def test_standard_surface_coat_affect_color_raises_the_base_colour_to_a_power():
    values = {"base_color": [0.5, 0.5, 0.5], "specular": 0.0, "coat": 1.0, "coat_IOR": 1.0, "coat_affect_color": 1.0}
    np.testing.assert_allclose(albedo_at_normal("standard_surface", values), 0.5**2, rtol=2e-3)


def test_standard_surface_thin_film_colours_the_specular_reflection():
    plain = albedo_at_normal("standard_surface", {"base_color": [0, 0, 0], "specular_roughness": 0.2})
    film = albedo_at_normal("standard_surface", {"base_color": [0, 0, 0], "specular_roughness": 0.2, "thin_film_thickness": 400.0, "thin_film_IOR": 1.4})
    assert np.ptp(plain) < 1e-9
    assert np.ptp(film) > 0.01


def test_models_evaluate_from_a_material():
    from openpbr_tools.evaluate import model_for_material
    from openpbr_tools.model import Constant, Input, Location, Material

    loc = Location("memory.mtlx")
    material = Material("m", "open_pbr_surface", loc, {"base_metalness": Input("base_metalness", "float", Constant(1.0), loc)})
    model, resolved = model_for_material(material)
    assert resolved.values["base_metalness"] == 1.0
    assert model.evaluate(np.array([[0.0, 0.6, 0.8]]), np.array([[0.0, -0.6, 0.8]])).shape == (1, 3)


#: Per model, lobe weights that are no longer stacking switches (preview.STACK_SWITCHES): materials with
#: and without the lobe are stacked together, so the test must see both in one stack.
STACKED_ACROSS = {"gltf_pbr": ("transmission",),
                  "open_pbr_surface": ("transmission_weight", "transmission_depth", "subsurface_weight"),
                  "standard_surface": ("transmission", "transmission_depth", "subsurface"),
                  "UsdPreviewSurface": ("opacity",)}


def test_stacked_spheres_are_the_spheres_rendered_one_by_one(tmp_path):
    """preview.shade_sphere_many (the candidate search's one evaluation for several materials) gives
    each material's own shade_sphere image, for every model and generated parameter sets that share
    their switches (preview.stack_key: films, coats, metals, glass, fuzz, emission among them), among
    them sets with and without a transmission, a volume, a subsurface or a preview's opacity (exact
    no-ops at weight 0, stacked together: STACKED_ACROSS, seen both ways in one stack); sets whose
    switches differ are refused (None), not mixed. judging.render_many, which groups any materials by
    those switches, gives every material's own image: glTF's thickness (thin-walled or a volume for the
    whole render) made a material stacked with others differ by up to 0.02 mean ΔE before it was a
    switch, and an OpenPBR film's transmission rescaling does where the film is off."""
    import sys

    sys.path.insert(0, str(Path(__file__).parent))
    from generated_materials import archetype_document, document
    from openpbr_tools.evaluate import model_for_material, resolve
    from openpbr_tools.evaluate.preview import Rig, shade_sphere, shade_sphere_many, stack_key
    from openpbr_tools.evaluate.thinfilm import coarse_films
    from openpbr_tools.io import read_asset
    from openpbr_tools.translate.common import Settings
    from openpbr_tools.translate.convert import convert
    from openpbr_tools.translate.judging import render_many

    rig = Rig(size=12)
    archetypes = tmp_path / "archetypes.mtlx"  # the kinds artists author: many lobes exactly off
    archetypes.write_text(archetype_document("acescg", 3, 60)[0])
    for model in ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface"):
        path = tmp_path / f"{model}.mtlx"
        path.write_text(document(model, "acescg", 3, 40))
        materials = read_asset(str(path)).materials + [
            convert(m, model, Settings(candidates=False)).material if model != m.model else m
            for m in read_asset(str(archetypes)).materials]
        groups = {}
        for material in materials:
            groups.setdefault(stack_key(model, resolve(material).values), []).append(material)
        for name in STACKED_ACROSS[model]:  # a stack holds the lobe both on and off
            assert any(len({bool(np.any(resolve(m).values[name] != 0)) for m in members}) == 2
                       for members in groups.values()), (model, name)
        group = max(groups.values(), key=len)
        assert len(group) >= 2, model
        stacked = shade_sphere_many(model, [resolve(m).values for m in group], rig)
        for material, image in zip(group, stacked):
            np.testing.assert_allclose(image, shade_sphere(model_for_material(material)[0], rig)[0], atol=1e-9)
        others = [m for key, members in groups.items() if members is not group for m in members]
        if others:
            mixed = [resolve(group[0]).values, resolve(others[0]).values]
            assert shade_sphere_many(model, mixed, rig) is None
        everything = render_many([(model, resolve(m).values) for m in materials], rig)  # films on the coarse table
        with coarse_films():
            for material, image in zip(materials, everything):
                np.testing.assert_allclose(image, shade_sphere(model_for_material(material)[0], rig)[0], atol=1e-9)


def test_a_gltf_volume_stacked_with_a_length_that_is_not_one_is_each_alone():
    """A glTF attenuation distance that is not a positive length (0, negative: an invalid file read as
    it is) means no attenuation; stacked with a real volume it stays none, pixel by pixel."""
    from openpbr_tools.evaluate import build_model
    from openpbr_tools.evaluate.parameters import with_values
    from openpbr_tools.evaluate.preview import Rig, shade_sphere, shade_sphere_many

    rig = Rig(size=12)
    volume = {"metallic": 0.0, "transmission": 1.0, "thickness": 1.0, "attenuation_color": (0.8, 0.3, 0.2),
              "attenuation_distance": 0.5}
    sets = [volume] + [dict(volume, attenuation_distance=d) for d in (0.0, -1.0, float("inf"))]
    stacked = shade_sphere_many("gltf_pbr", [with_values("gltf_pbr", values).values for values in sets], rig)
    for values, image in zip(sets, stacked):
        np.testing.assert_allclose(image, shade_sphere(build_model("gltf_pbr", values), rig)[0], atol=1e-9)
    assert not np.allclose(stacked[0], stacked[1], atol=1e-3)  # (the volume did attenuate)
    np.testing.assert_allclose(stacked[1], stacked[3], atol=1e-12)


def test_one_pass_gives_the_values_and_albedos_of_the_two_calls(tmp_path):
    """BSDFModel.evaluate_and_albedo (what a render lit by one light calls) gives what evaluate and
    albedo give apart, for generated materials of every model, seen from above and below the surface,
    with and without a coat frame of its own, and for more directions than evaluate takes in one chunk."""
    import sys

    sys.path.insert(0, str(Path(__file__).parent))
    from generated_materials import document
    from openpbr_tools.evaluate import model_for_material
    from openpbr_tools.io import read_asset

    rng = np.random.default_rng(5)
    wi = rng.normal(size=(64, 3))
    wo = rng.normal(size=(64, 3))
    wi /= np.linalg.norm(wi, axis=1, keepdims=True)
    wo /= np.linalg.norm(wo, axis=1, keepdims=True)
    coat_wi, coat_wo = wi[:, [1, 0, 2]], wo[:, [1, 0, 2]]
    checked = 0
    for model in ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface"):
        path = tmp_path / f"{model}.mtlx"
        path.write_text(document(model, "acescg", 8, 25))
        for material in read_asset(str(path)).materials:
            bsdf = model_for_material(material)[0]
            for frame in (False, True):
                if frame:
                    with bsdf.coat_frame(coat_wi, coat_wo):
                        value, albedo = bsdf.evaluate_and_albedo(wi, wo)
                        apart = bsdf.evaluate(wi, wo)
                    with bsdf.coat_frame(None, coat_wo):
                        alone = bsdf.albedo(wo)
                else:
                    value, albedo = bsdf.evaluate_and_albedo(wi, wo)
                    apart, alone = bsdf.evaluate(wi, wo), bsdf.albedo(wo)
                np.testing.assert_allclose(value, apart, rtol=0, atol=1e-12)
                np.testing.assert_allclose(albedo.reflect, alone.reflect, rtol=0, atol=1e-12)
                np.testing.assert_allclose(albedo.transmit, alone.transmit, rtol=0, atol=1e-12)
                checked += 1
        # more directions than a chunk (evaluate works in chunks there): the same
        bsdf = model_for_material(read_asset(str(path)).materials[0])[0]
        many_wi, many_wo = np.tile(wi, (700, 1)), np.roll(np.tile(wo, (700, 1)), 3, axis=0)
        assert len(many_wi) > bsdf.chunk_size
        value, albedo = bsdf.evaluate_and_albedo(many_wi, many_wo)
        np.testing.assert_allclose(value, bsdf.evaluate(many_wi, many_wo), rtol=0, atol=1e-12)
        np.testing.assert_allclose(albedo.reflect, bsdf.albedo(many_wo).reflect, rtol=0, atol=1e-12)
    assert checked == 200
