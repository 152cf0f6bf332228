"""Tabulated directional albedos against integrals of the published BSDF formulas, written out
here independently and integrated with a product Gauss-Legendre rule (the tables were built by
visible-normal quadrature of the package's own lobes)."""

import numpy as np
import pytest

from openpbr_tools.evaluate import albedo
from test_evaluate_fresnel import snell_fresnel
from test_evaluate_lobes import from_angles, sphere_rule


def ggx_d(cos_h, alpha):
    cos_h = np.clip(cos_h, 1e-9, 1)
    t2 = (1 - cos_h**2) / cos_h**2
    return alpha**2 / (np.pi * cos_h**4 * (alpha**2 + t2) ** 2)


def ggx_lambda(cos, alpha):
    t2 = (1 - cos**2) / np.maximum(cos**2, 1e-18)
    return (-1 + np.sqrt(1 + alpha**2 * t2)) / 2


def reflection_albedo(mu, alpha, fresnel=lambda c: 1.0, order=200):
    wo = np.array([np.sqrt(1 - mu * mu), 0, mu])
    wi, w = sphere_rule(order)
    h = wi + wo
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    g2 = 1 / (1 + ggx_lambda(wi[:, 2], alpha) + ggx_lambda(mu, alpha))
    f = ggx_d(h[:, 2], alpha) * g2 / (4 * wi[:, 2] * mu) * fresnel(np.sum(wi * h, axis=1))
    return np.sum(f * wi[:, 2] * w)


def transmission_energy(mu, alpha, eta, order=240):
    """Energy transmittance from air (index 1) into a medium of index eta: integral over the
    transmitted hemisphere of Walter et al. 2007 eq. 21 (written here) times |cos_t|."""
    wi = np.array([np.sqrt(1 - mu * mu), 0, mu])
    wt, w = sphere_rule(order, lower=True)
    h = -(wi + eta * wt)
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    h *= np.sign(h[:, 2])[:, None]
    i_h, t_h = h @ wi, np.sum(wt * h, axis=1)
    valid = (i_h > 0) & (t_h < 0)
    g2 = 1 / (1 + ggx_lambda(mu, alpha) + ggx_lambda(np.abs(wt[:, 2]), alpha))
    fr = snell_fresnel(np.abs(i_h), 1.0, eta)
    f = np.abs(i_h * t_h) / (mu * np.abs(wt[:, 2])) * eta**2 * (1 - fr) * ggx_d(h[:, 2], alpha) * g2 / (i_h + eta * t_h) ** 2
    return np.sum(np.where(valid, f, 0.0) * np.abs(wt[:, 2]) * w)


@pytest.mark.parametrize("mu,roughness", [(1.0, 0.4), (0.5, 0.6), (0.2, 0.8), (0.85, 1.0), (0.35, 0.3)])
def test_ggx_single_scattering_albedo_table(mu, roughness):
    alpha = roughness**2
    assert albedo.ggx_albedo(mu, alpha) == pytest.approx(reflection_albedo(mu, alpha), abs=4e-3)


@pytest.mark.parametrize("mu,roughness", [(0.9, 0.5), (0.3, 0.7)])
def test_schlick_albedo_table(mu, roughness):
    alpha = roughness**2
    f0 = np.array([0.9, 0.5, 0.04])
    expected = [reflection_albedo(mu, alpha, lambda c, f=f: f + (1 - f) * (1 - c) ** 5) for f in f0]
    np.testing.assert_allclose(albedo.ggx_schlick_albedo(mu, alpha, f0), expected, atol=4e-3)


def test_f82_albedo_table():
    mu, alpha = 0.6, 0.3**2
    f0, tint = 0.8, 0.5
    mu_bar = 1 / 7
    a = (f0 + (1 - f0) * (1 - mu_bar) ** 5) * (1 - tint) / (mu_bar * (1 - mu_bar) ** 6)
    expected = reflection_albedo(mu, alpha, lambda c: f0 + (1 - f0) * (1 - c) ** 5 - a * c * (1 - c) ** 6)
    assert albedo.ggx_schlick_albedo(mu, alpha, np.full(3, f0), 1.0, np.full(3, tint))[0] == pytest.approx(expected, abs=4e-3)


@pytest.mark.parametrize("node", [1, 6, 11, 13, 16, 20, 24])
def test_smooth_dielectric_reflectance_table_is_the_fresnel_equations(node):
    eta = albedo.eta_nodes()[node]
    mus = np.linspace(0.0, 1.0, albedo.MU_NODES)[1:]  # grid nodes (mu = 0 is evaluated at a floor)
    if eta < 1:  # the step at the critical angle is smeared by the alpha floor of 1e-4
        mus = mus[np.abs(mus - np.sqrt(1 - eta**2)) > 0.01]
    r, t = albedo.dielectric_albedo(mus, 0.0, eta)
    np.testing.assert_allclose(r, snell_fresnel(mus, 1.0, eta), atol=2e-4)
    if eta > 1:
        np.testing.assert_allclose(r + t, 1.0, atol=2e-4)


@pytest.mark.parametrize("eta", [1.33, 1.5, 1.6, 2.0, 1 / 1.5])
def test_dielectric_table_interpolates_between_iors(eta):
    """Between grid IORs the tables interpolate linearly in the normal-incidence reflectance,
    in which Fresnel reflectance is close to linear away from grazing and critical angles."""
    mus = np.linspace(0.3, 1.0, 15)
    if eta < 1:
        mus = mus[mus > np.sqrt(1 - eta**2) + 0.05]
    r, _ = albedo.dielectric_albedo(mus, 0.0, eta)
    np.testing.assert_allclose(r, snell_fresnel(mus, 1.0, eta), atol=1e-3)


@pytest.mark.parametrize("mu,roughness,eta", [(0.9, 0.5, 1.5), (0.4, 0.7, 1.5), (0.6, 0.4, 2.0)])
def test_rough_dielectric_tables(mu, roughness, eta):
    alpha = roughness**2
    r, t = albedo.dielectric_albedo(mu, alpha, eta)
    assert r == pytest.approx(reflection_albedo(mu, alpha, lambda c: snell_fresnel(c, 1.0, eta)), abs=3e-3)
    assert t == pytest.approx(transmission_energy(mu, alpha, eta), abs=6e-3)


@pytest.mark.parametrize("mu,r", [(0.8, 0.3), (0.4, 0.6), (0.2, 1.0)])
def test_charlie_sheen_albedo_table(mu, r):
    wo = from_angles(np.arccos(mu))
    wi, w = sphere_rule(160)
    h = wi + wo
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    d = (2 + 1 / r) * (1 - h[:, 2] ** 2) ** (0.5 / r) / (2 * np.pi)
    v = 1 / (4 * (wi[:, 2] + mu - wi[:, 2] * mu))
    expected = np.sum(d * v * wi[:, 2] * w)
    assert albedo.charlie_albedo(mu, r) == pytest.approx(expected, abs=3e-3)


@pytest.mark.parametrize("roughness", [0.0, 0.3, 0.7, 1.0])
def test_turquin_compensation_makes_a_white_ggx_conductor_lossless(roughness):
    mu = np.linspace(0.05, 1, 12)
    alpha = roughness**2
    compensated = albedo.ggx_albedo(mu, alpha)[:, None] * albedo.ggx_compensation(mu, alpha, np.ones(3))
    np.testing.assert_allclose(compensated, 1.0, atol=1e-9)
