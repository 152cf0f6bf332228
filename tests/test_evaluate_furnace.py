"""White furnace: materials that claim energy preservation reflect (and transmit) all light at
every roughness; the others lose exactly what single scattering loses.

Integrals are estimated here from the models' BSDF *values*, by importance sampling of the GGX
visible normals with Heitz's original algorithm ("Sampling the GGX Distribution of Visible
Normals", JCGT 7(4), 2018, listing 1) on a stratified grid, with the density written out from
the GGX formulas; rough transmissive cases use a product Gauss-Legendre rule. None of this uses
the evaluator's albedo tables.
"""

import numpy as np
import pytest

from openpbr_tools.evaluate import build_model
from test_evaluate_albedo import ggx_d, ggx_lambda, reflection_albedo
from test_evaluate_lobes import sphere_rule

ROUGHNESSES = [0.0, 0.1, 0.3, 0.6, 1.0]
COSINES = [1.0, 0.6, 0.25]


def heitz_vndf(wo, alpha, n=64):
    """Visible normals for view ``wo`` (isotropic alpha) on an n x n stratified grid."""
    u = (np.arange(n) + 0.5) / n
    u1, u2 = [g.ravel() for g in np.meshgrid(u, u, indexing="ij")]
    vh = np.array([alpha * wo[0], alpha * wo[1], wo[2]])
    vh /= np.linalg.norm(vh)
    lensq = vh[0] ** 2 + vh[1] ** 2
    t1 = np.array([-vh[1], vh[0], 0.0]) / np.sqrt(lensq) if lensq > 0 else np.array([1.0, 0.0, 0.0])
    t2 = np.cross(vh, t1)
    r = np.sqrt(u1)
    phi = 2 * np.pi * u2
    p1 = r * np.cos(phi)
    p2 = r * np.sin(phi)
    s = 0.5 * (1 + vh[2])
    p2 = (1 - s) * np.sqrt(1 - p1 * p1) + s * p2
    nh = p1[:, None] * t1 + p2[:, None] * t2 + np.sqrt(np.maximum(0, 1 - p1 * p1 - p2 * p2))[:, None] * vh
    h = np.stack([alpha * nh[:, 0], alpha * nh[:, 1], np.maximum(nh[:, 2], 0)], axis=1)
    return h / np.linalg.norm(h, axis=1, keepdims=True)


def reflection_pdf(wo, h, alpha):
    """Density of wi = reflect(wo, h) for h from the visible normals: D_wo(h) / (4 wo.h)."""
    g1 = 1 / (1 + ggx_lambda(wo[2], alpha))
    wo_h = h @ wo
    return g1 * np.maximum(wo_h, 0) * ggx_d(h[:, 2], alpha) / wo[2] / (4 * wo_h)


def sampled_albedo(model, mu, alpha, with_mirror=False):
    """E(wo) = int f(wi, wo) |cos_i| dwi over reflections (and their mirror images below the
    surface, for straight-through transmission) of visible-normal samples."""
    alpha = max(alpha, 1e-4)
    wo = np.array([np.sqrt(1 - mu * mu), 0.0, mu])
    h = heitz_vndf(wo, alpha)
    wi = 2 * (h @ wo)[:, None] * h - wo
    ok = wi[:, 2] > 0
    pdf = reflection_pdf(wo, h, alpha)
    f = model.evaluate(wi, wo[None, :])
    if with_mirror:
        f = f + model.evaluate(wi * np.array([1, 1, -1]), wo[None, :])
    weight = np.where(ok, wi[:, 2] / np.where(ok, pdf, 1.0), 0.0)
    return np.mean(f * weight[:, None], axis=0)


@pytest.mark.parametrize("roughness", ROUGHNESSES)
@pytest.mark.parametrize("model,values,alpha_of", [
    ("open_pbr_surface", {"base_metalness": 1.0, "base_color": [1, 1, 1], "specular_color": [1, 1, 1]}, lambda r: r * r),
    ("gltf_pbr", {"metallic": 1.0, "base_color": [1, 1, 1]}, lambda r: r * r),
    ("UsdPreviewSurface", {"metallic": 1.0, "diffuseColor": [1, 1, 1]}, lambda r: r * r),
], ids=["openpbr_f82_metal", "gltf_metal", "usd_metal"])
def test_white_conductor_reflects_everything(model, values, alpha_of, roughness):
    key = {"open_pbr_surface": "specular_roughness", "gltf_pbr": "roughness", "UsdPreviewSurface": "roughness"}[model]
    m = build_model(model, dict(values, **{key: roughness}))
    for mu in COSINES:
        np.testing.assert_allclose(sampled_albedo(m, mu, alpha_of(roughness)), 1.0, atol=0.01)


@pytest.mark.parametrize("roughness", ROUGHNESSES)
def test_white_thin_walled_dielectric_slab_reflects_plus_transmits_everything(roughness):
    m = build_model("open_pbr_surface", {"transmission_weight": 1.0, "geometry_thin_walled": True, "specular_roughness": roughness})
    for mu in COSINES:
        np.testing.assert_allclose(sampled_albedo(m, mu, roughness**2, with_mirror=True), 1.0, atol=0.01)


@pytest.mark.parametrize("roughness", [0.4, 0.7, 1.0])
@pytest.mark.parametrize("ior", [1.5, 2.2])
def test_white_closed_dielectric_is_in_equilibrium_with_a_furnace(roughness, ior):
    """Radiance leaving a clear dielectric in a furnace of radiance 1 outside (and eta^2 inside,
    the equilibrium radiance of a lossless medium) is 1 (n^2 law of radiance)."""
    m = build_model("open_pbr_surface", {"transmission_weight": 1.0, "specular_roughness": roughness, "specular_ior": ior})
    up, w = sphere_rule(128)
    down = up * np.array([1, 1, -1])
    for mu in COSINES:
        wo = np.array([np.sqrt(1 - mu * mu), 0.0, mu])
        reflected = np.sum(m.evaluate(up, wo[None, :])[:, 0] * up[:, 2] * w)
        transmitted = np.sum(m.evaluate(down, wo[None, :])[:, 0] * up[:, 2] * w) * ior**2
        assert reflected + transmitted == pytest.approx(1.0, abs=0.01)


@pytest.mark.parametrize("roughness", [0.3, 0.6, 1.0])
def test_uncompensated_gltf_metal_loses_what_single_scattering_loses(roughness, monkeypatch):
    from openpbr_tools.evaluate.gltf import GltfPbr

    monkeypatch.setattr(GltfPbr, "energy_compensation", False)
    m = build_model("gltf_pbr", {"metallic": 1.0, "base_color": [1, 1, 1], "roughness": roughness})
    for mu in COSINES:
        expected = reflection_albedo(mu, roughness**2)
        got = sampled_albedo(m, mu, roughness**2)
        np.testing.assert_allclose(got, expected, atol=0.01)
        if roughness >= 0.6:
            assert got[0] < 0.95  # a visible loss, not a rounding error


def test_standard_surface_white_metal_loses_the_one_percent_its_artistic_ior_clamp_removes():
    """MaterialX's artistic_ior clamps reflectivity at 0.99, so a white conductor reflects F >= 0.99."""
    m = build_model("standard_surface", {"metalness": 1.0, "base_color": [1, 1, 1], "specular_color": [1, 1, 1], "specular_roughness": 0.5})
    for mu in COSINES:
        e = sampled_albedo(m, mu, 0.25)
        assert np.all(e > 0.98) and np.all(e < 1.0)


@pytest.mark.parametrize("model,values", [
    ("open_pbr_surface", {"base_color": [1, 1, 1], "base_diffuse_roughness": 0.7, "specular_roughness": 0.5}),
    ("open_pbr_surface", {"base_color": [1, 1, 1], "coat_weight": 1.0, "coat_roughness": 0.5, "coat_darkening": 0.0, "fuzz_weight": 1.0, "fuzz_color": [1, 1, 1]}),
    ("UsdPreviewSurface", {"diffuseColor": [1, 1, 1], "roughness": 0.6, "clearcoat": 1.0, "clearcoatRoughness": 0.5}),
], ids=["openpbr_glossy_diffuse", "openpbr_coated_fuzz", "usd_coated"])
def test_white_layered_dielectrics_reflect_everything(model, values):
    m = build_model(model, values)
    up, w = sphere_rule(128)
    for mu in COSINES:
        wo = np.array([np.sqrt(1 - mu * mu), 0.0, mu])
        e = np.sum(m.evaluate(up, wo[None, :]) * (up[:, 2] * w)[:, None], axis=0)
        np.testing.assert_allclose(e, 1.0, atol=0.015)
