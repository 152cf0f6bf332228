"""Lobes against integrals computed here with other methods (adaptive quadrature, product
Gauss-Legendre rules), normalisation identities from the papers, and reciprocity."""

import numpy as np
import pytest
from scipy import integrate

from openpbr_tools.evaluate import diffuse, microfacet, sheen


def sphere_rule(order=96, lower=False):
    """Gauss-Legendre in cos(theta) x midpoint in phi over a hemisphere (the lower one when
    ``lower``): directions and solid-angle weights."""
    x, w = np.polynomial.legendre.leggauss(order)
    mu = 0.5 * (x + 1)
    phi = (np.arange(2 * order) + 0.5) * np.pi / order
    m, p = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - m * m)
    z = -m if lower else m
    dirs = np.stack([s * np.cos(p), s * np.sin(p), z], -1).reshape(-1, 3)
    weights = (0.5 * w[:, None] * np.full(2 * order, np.pi / order)).reshape(-1)
    return dirs, weights


def random_directions(rng, n, upper=True):
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    if upper:
        v[:, 2] = np.abs(v[:, 2])
    return v


def from_angles(theta, phi=0.0):
    return np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])


# ---------------------------------------------------------------- GGX


@pytest.mark.parametrize("alpha", [0.02, 0.1, 0.5, 1.0])
def test_ggx_projected_microfacet_area_integrates_to_one(alpha):
    def integrand(theta):
        h = from_angles(theta)[None, :]
        return microfacet.ggx_ndf(h, alpha, alpha)[0] * np.cos(theta) * np.sin(theta) * 2 * np.pi

    value, _ = integrate.quad(integrand, 0, np.pi / 2, points=[np.arctan(alpha)], limit=200)
    assert value == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize("ax,ay", [(0.1, 0.4), (0.6, 0.2)])
def test_anisotropic_ggx_projected_area_integrates_to_one(ax, ay):
    value, _ = integrate.dblquad(
        lambda theta, phi: microfacet.ggx_ndf(from_angles(theta, phi)[None, :], ax, ay)[0] * np.cos(theta) * np.sin(theta),
        0, 2 * np.pi, 0, np.pi / 2, epsabs=1e-8,
    )
    assert value == pytest.approx(1.0, abs=1e-5)


@pytest.mark.parametrize("alpha", [(0.2, 0.2), (0.5, 0.5), (0.3, 0.8)])
@pytest.mark.parametrize("theta_o", [0.0, 0.8, 1.4])
def test_smith_g1_normalises_the_distribution_of_visible_normals(alpha, theta_o):
    """Heitz 2014, eq. 13/17: int G1(wo) max(0, wo.h) D(h) dh = cos(theta_o)."""
    wo = from_angles(theta_o, 0.3)
    h, w = sphere_rule(160)
    visible = np.sum(np.maximum(h @ wo, 0.0) * microfacet.ggx_ndf(h, *alpha) * w)
    g1 = microfacet.smith_g1(wo[None, :], *alpha)[0]
    assert g1 * visible == pytest.approx(np.cos(theta_o), rel=2e-3)


def test_height_correlated_g2_lies_between_uncorrelated_and_min():
    rng = np.random.default_rng(3)
    wi, wo = random_directions(rng, 500), random_directions(rng, 500)
    g2 = microfacet.smith_g2_height_correlated(wi, wo, 0.4, 0.4)
    g1i, g1o = microfacet.smith_g1(wi, 0.4, 0.4), microfacet.smith_g1(wo, 0.4, 0.4)
    assert np.all(g2 >= g1i * g1o - 1e-12)
    assert np.all(g2 <= np.minimum(g1i, g1o) + 1e-12)


def test_ggx_reflection_matches_the_cook_torrance_form_with_an_independent_ndf():
    rng = np.random.default_rng(4)
    wi, wo = random_directions(rng, 200), random_directions(rng, 200)
    ax, ay = 0.3, 0.6
    h = wi + wo
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    # Walter et al. 2007 eq. 33 written in angles, anisotropic form of Burley 2012 B.2 eq. 13.
    cos_h = h[:, 2]
    tan2 = (1 - cos_h**2) / cos_h**2
    cphi2 = h[:, 0] ** 2 / np.maximum(h[:, 0] ** 2 + h[:, 1] ** 2, 1e-30)
    d = 1 / (np.pi * ax * ay * cos_h**4 * (1 + tan2 * (cphi2 / ax**2 + (1 - cphi2) / ay**2)) ** 2)

    def lam(w):
        c2 = w[:, 2] ** 2
        a2 = (w[:, 0] ** 2 * ax**2 + w[:, 1] ** 2 * ay**2) / (1 - c2)
        return (-1 + np.sqrt(1 + a2 * (1 - c2) / c2)) / 2

    g2 = 1 / (1 + lam(wi) + lam(wo))
    expected = d * g2 / (4 * wi[:, 2] * wo[:, 2])
    value, cos_hv = microfacet.ggx_reflection(wi, wo, ax, ay)
    np.testing.assert_allclose(value, expected, rtol=1e-9)
    np.testing.assert_allclose(cos_hv, np.sum(wo * h, axis=1), rtol=1e-12)


# ---------------------------------------------------------------- reciprocity


def _pairs(seed=7, n=300):
    rng = np.random.default_rng(seed)
    return random_directions(rng, n), random_directions(rng, n)


@pytest.mark.parametrize(
    "lobe",
    [
        lambda a, b: microfacet.ggx_reflection(a, b, 0.3, 0.7)[0],
        lambda a, b: diffuse.lambert(a[:, 2], b[:, 2]),
        lambda a, b: diffuse.oren_nayar(a[:, 2], b[:, 2], np.sum(a * b, 1), 0.8),
        lambda a, b: diffuse.fujii_oren_nayar(a[:, 2], b[:, 2], np.sum(a * b, 1), 0.6),
        lambda a, b: diffuse.eon_diffuse(a[:, 2], b[:, 2], np.sum(a * b, 1), 0.6, np.array([0.9, 0.5, 0.2])),
        lambda a, b: sheen.conty_kulla_sheen(a, b, 0.4, "ashikhmin"),
        lambda a, b: sheen.conty_kulla_sheen(a, b, 0.4, "charlie"),
    ],
    ids=["ggx", "lambert", "oren_nayar", "fujii_oren_nayar", "eon", "charlie_ashikhmin", "charlie_lambda"],
)
def test_reciprocal_lobes_are_symmetric(lobe):
    a, b = _pairs()
    np.testing.assert_allclose(lobe(a, b), lobe(b, a), rtol=1e-10, atol=1e-14)


def test_ggx_transmission_obeys_generalised_reciprocity():
    rng = np.random.default_rng(8)
    wo = random_directions(rng, 2000)
    wi = random_directions(rng, 2000) * np.array([1, 1, -1])
    eta_i, eta_o = 1.5, 1.0  # wi inside glass, wo in air
    forward, _ = microfacet.ggx_transmission(wi, wo, 0.3, 0.3, eta_i, eta_o)
    backward, _ = microfacet.ggx_transmission(wo, wi, 0.3, 0.3, eta_o, eta_i)
    assert np.count_nonzero(forward) > 200  # valid refraction pairs exist
    np.testing.assert_allclose(forward / eta_o**2, backward / eta_i**2, rtol=1e-9)


@pytest.mark.parametrize("theta", [0.0, 0.7, 1.2])
def test_nearly_smooth_transmission_carries_one_minus_fresnel(theta):
    """Energy through a near-mirror interface from air into glass: int f_t |cos_t| dw_t = 1 - F
    (Fresnel computed independently), up to the small shadowing loss of alpha = 0.05."""
    eta = 1.5
    wi = from_angles(theta)
    below, w = sphere_rule(400, lower=True)
    f, cos_h = microfacet.ggx_transmission(np.broadcast_to(wi, below.shape), below, 0.05, 0.05, 1.0, eta)
    from test_evaluate_fresnel import snell_fresnel

    expected = 1 - snell_fresnel(np.cos(theta), 1.0, eta)
    fresnel_h = snell_fresnel(cos_h, eta, 1.0)  # cos_h is measured on the glass side
    energy = np.sum(f * (1 - fresnel_h) * np.abs(below[:, 2]) * w)
    assert energy == pytest.approx(expected, rel=0.01)


# ---------------------------------------------------------------- diffuse


def test_lambert_albedo_equals_its_colour():
    dirs, w = sphere_rule(32)
    colour = np.array([0.9, 0.4, 0.1])
    wo = from_angles(0.9)
    albedo = np.sum(diffuse.lambert(dirs[:, 2], wo[2])[:, None] * colour * (dirs[:, 2] * w)[:, None], axis=0)
    np.testing.assert_allclose(albedo, colour, rtol=1e-12)


@pytest.mark.parametrize("sigma", [0.0, 0.3, 0.7, 1.0])
@pytest.mark.parametrize("theta_o", [0.0, 1.0, 1.45])
def test_eon_white_furnace_reflects_everything(sigma, theta_o):
    dirs, w = sphere_rule(128)
    wo = from_angles(theta_o)
    f = diffuse.eon_diffuse(dirs[:, 2], wo[2], dirs @ wo, sigma, np.ones(3))
    assert np.sum(f[:, 0] * dirs[:, 2] * w) == pytest.approx(1.0, abs=2e-3)


@pytest.mark.parametrize("sigma", [0.25, 1.0])
def test_fon_directional_albedo_closed_form_matches_quadrature(sigma):
    dirs, w = sphere_rule(128)
    for theta_o in (0.0, 0.6, 1.2, 1.5):
        wo = from_angles(theta_o)
        quad = np.sum(diffuse.fujii_oren_nayar(dirs[:, 2], wo[2], dirs @ wo, sigma) * dirs[:, 2] * w)
        assert diffuse.fujii_oren_nayar_albedo(np.cos(theta_o), sigma) == pytest.approx(quad, abs=2e-3)


def test_eon_albedo_of_a_coloured_surface_matches_quadrature():
    dirs, w = sphere_rule(128)
    rho = np.array([0.8, 0.4, 0.05])
    wo = from_angles(1.0)
    quad = np.sum(diffuse.eon_diffuse(dirs[:, 2], wo[2], dirs @ wo, 0.8, rho) * (dirs[:, 2] * w)[:, None], axis=0)
    np.testing.assert_allclose(diffuse.eon_albedo(np.cos(1.0), 0.8, rho), quad, atol=2e-3)


def test_oren_nayar_loses_energy_at_high_roughness_and_is_lambert_when_smooth():
    dirs, w = sphere_rule(96)
    wo = from_angles(0.0)
    smooth = diffuse.oren_nayar(dirs[:, 2], wo[2], dirs @ wo, 0.0)
    np.testing.assert_allclose(smooth, 1 / np.pi)
    rough = np.sum(diffuse.oren_nayar(dirs[:, 2], wo[2], dirs @ wo, 1.0) * dirs[:, 2] * w)
    # At normal view the angular term vanishes (s = 0): albedo = A = 1 - 0.5 s2 / (s2 + 0.33).
    assert rough == pytest.approx(1 - 0.5 / 1.33, abs=1e-6)


# ---------------------------------------------------------------- sheen


@pytest.mark.parametrize("r", [0.1, 0.3, 0.6, 1.0])
def test_charlie_distribution_projected_area_integrates_to_one(r):
    value, _ = integrate.quad(
        lambda t: sheen.charlie_ndf(np.cos(t), r) * np.cos(t) * np.sin(t) * 2 * np.pi, 0, np.pi / 2, limit=200
    )
    assert value == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize("r", [0.1, 0.5, 1.0])
@pytest.mark.parametrize("theta_o", [0.2, 1.0, 1.4])
def test_zeltner_ltc_distribution_integrates_to_one_over_the_sphere(r, theta_o):
    wo = from_angles(theta_o, 0.4)
    up, w = sphere_rule(160)
    down, _ = sphere_rule(160, lower=True)
    total = np.sum(sheen.zeltner_ltc_distribution(up, wo[None, :], r) * w)
    total += np.sum(sheen.zeltner_ltc_distribution(down, wo[None, :], r) * w)
    assert total == pytest.approx(1.0, abs=5e-3)


@pytest.mark.parametrize("r", [0.2, 0.7])
def test_zeltner_sheen_albedo_is_its_fitted_reflectance_times_the_visible_lobe(r):
    wo = from_angles(0.9)
    dirs, w = sphere_rule(160)
    f = sheen.zeltner_sheen(dirs, wo[None, :], r)
    albedo = np.sum(f * dirs[:, 2] * w)
    fraction = np.sum(sheen.zeltner_ltc_distribution(dirs, wo[None, :], r) * w)
    assert albedo == pytest.approx(sheen.zeltner_sheen_albedo(np.cos(0.9), r) * fraction, rel=1e-6)
    assert fraction <= 1.0 + 1e-6
