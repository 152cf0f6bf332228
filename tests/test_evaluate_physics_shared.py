"""The physical formulas the evaluator and the translators share (evaluate.coat, evaluate.fresnel,
evaluate.microfacet), checked against closed forms written out here from their published sources
(OpenPBR Surface 1.1, "Coat" and "Specular anisotropy"; Born & Wolf; Gulbrandsen 2014;
KHR_materials_anisotropy). Expected numbers never come from the code under test."""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

from openpbr_tools.evaluate import build_model, coat, fresnel, microfacet
from openpbr_tools.translate import fit
from openpbr_tools.translate import gltf as gltf_translate
from openpbr_tools.translate import standard_surface as ss_translate
from openpbr_tools.translate import usd_preview as usd_translate


def normal_incidence_reflectance(n1, n2, k2=0.0):
    """|(n1 - N2) / (n1 + N2)|^2 with N2 = n2 + i k2 (Born & Wolf, section 1.5.2 / 14.2)."""
    r = (n1 - complex(n2, k2)) / (n1 + complex(n2, k2))
    return abs(r) ** 2


def conductor_fresnel(cos_i, n, k):
    """Unpolarised reflectance of a conductor n + ik from air: complex Snell and Fresnel amplitudes."""
    eta = complex(n, k)
    sin2 = 1.0 - cos_i * cos_i
    cos_t = cmath.sqrt(1.0 - sin2 / (eta * eta))
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return 0.5 * (abs(rs) ** 2 + abs(rp) ** 2)


# ------------------------------------------------------------------------------ F0 and IOR

@pytest.mark.parametrize("eta", [1.0, 1.33, 1.5, 2.4, 0.75, 3.0])
def test_ior_to_f0_is_the_normal_incidence_fresnel_reflectance(eta):
    assert float(fresnel.ior_to_f0(eta)) == pytest.approx(((1.0 - eta) / (1.0 + eta)) ** 2, rel=1e-14, abs=1e-16)
    assert float(fresnel.ior_to_f0(eta)) == pytest.approx(normal_incidence_reflectance(1.0, eta), rel=1e-12, abs=1e-16)


def test_ior_to_f0_of_a_ratio_is_the_reflectance_between_the_two_media():
    n1, n2 = 1.6, 1.5
    assert float(fresnel.ior_to_f0(n2 / n1)) == pytest.approx(((n1 - n2) / (n1 + n2)) ** 2, rel=1e-12)


def test_ior_to_f0_is_vectorised():
    eta = np.array([[1.5, 2.0], [1.2, 1.0]])
    expected = np.array([[0.04, 1.0 / 9.0], [(0.2 / 2.2) ** 2, 0.0]])
    np.testing.assert_allclose(fresnel.ior_to_f0(eta), expected, rtol=1e-14, atol=1e-18)


@pytest.mark.parametrize("f0, ior", [(0.04, 1.5), (1.0 / 9.0, 2.0), (0.0, 1.0)])
def test_f0_to_ior_inverts_the_closed_form(f0, ior):
    assert float(fresnel.f0_to_ior(f0)) == pytest.approx(ior, rel=1e-12)
    assert float(fit.ior_from_f0(f0)) == pytest.approx(ior, rel=1e-12)


def test_f0_to_ior_clamps_below_one():
    s = math.sqrt(0.9999)
    assert float(fresnel.f0_to_ior(1.0)) == pytest.approx((1.0 + s) / (1.0 - s), rel=1e-12)
    s = math.sqrt(0.999999)
    assert float(fit.ior_from_f0(1.0)) == pytest.approx((1.0 + s) / (1.0 - s), rel=1e-12)
    assert float(fresnel.f0_to_ior(0.5, max_f0=0.25)) == pytest.approx(3.0, rel=1e-12)


# --------------------------------------------------------------------------- conductors

@pytest.mark.parametrize("n, k", [(0.2, 3.0), (1.1, 2.5), (2.9, 0.3), (1.5, 0.0)])
@pytest.mark.parametrize("cos_i", [1.0, 0.8, 0.5, 1.0 / 7.0, 0.05])
def test_real_arithmetic_conductor_fresnel_is_the_complex_one(n, k, cos_i):
    expected = conductor_fresnel(cos_i, n, k)
    assert float(fresnel.fresnel_conductor_real(cos_i, n, k)) == pytest.approx(expected, rel=1e-10, abs=1e-14)


def test_real_arithmetic_conductor_fresnel_at_normal_incidence():
    n, k = 0.27, 2.78
    expected = ((n - 1.0) ** 2 + k * k) / ((n + 1.0) ** 2 + k * k)
    assert float(fresnel.fresnel_conductor_real(1.0, n, k)) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("r", [0.04, 0.3, 0.9])
@pytest.mark.parametrize("g", [0.0, 0.4, 1.0])
def test_artistic_ior_follows_gulbrandsen(r, g):
    n, k = fresnel.artistic_ior(r, g)
    n_min = (1.0 - r) / (1.0 + r)
    n_max = (1.0 + math.sqrt(r)) / (1.0 - math.sqrt(r))
    assert float(n) == pytest.approx(g * n_min + (1.0 - g) * n_max, rel=1e-12)
    k2 = ((n_min * g + n_max * (1.0 - g) + 1.0) ** 2 * r - (n_min * g + n_max * (1.0 - g) - 1.0) ** 2) / (1.0 - r)
    assert float(k) == pytest.approx(math.sqrt(max(k2, 0.0)), rel=1e-9, abs=1e-12)
    # ... and the conductor reflects r at normal incidence.
    assert normal_incidence_reflectance(1.0, float(n), float(k)) == pytest.approx(r, rel=1e-9)


# ---------------------------------------------------------------------------------- coat

@pytest.mark.parametrize("r, w, r_c", [(0.0, 1.0, 1.0), (0.5, 1.0, 0.5), (0.3, 0.0, 0.9), (0.2, 0.5, 0.4),
                                       (0.9, 1.0, 0.9), (0.6, 0.25, 0.0)])
def test_coat_roughening_is_the_specifications(r, w, r_c):
    roughened = min(1.0, (r ** 4 + 2.0 * r_c ** 4) ** 0.25)
    expected = (1.0 - w) * r + w * roughened
    assert float(coat.coat_roughened(r, w, r_c)) == pytest.approx(expected, rel=1e-12, abs=1e-15)


def test_coat_roughening_known_values():
    assert float(coat.coat_roughened(0.5, 1.0, 0.5)) == pytest.approx(0.5 * 3.0 ** 0.25, rel=1e-14)
    assert float(coat.coat_roughened(0.0, 1.0, 1.0)) == 1.0  # 2^(1/4) > 1 is clamped
    assert float(coat.coat_roughened(0.3, 0.0, 1.0)) == pytest.approx(0.3, rel=1e-15)


def test_coat_roughening_is_vectorised_and_inverted_by_the_translators_solver():
    r = np.array([[0.1, 0.4, 0.8]])
    w = np.array([[0.5], [1.0]])
    expected = (1.0 - w) * r + w * np.minimum(1.0, (r ** 4 + 2.0 * 0.3 ** 4) ** 0.25)
    got = coat.coat_roughened(r, w, 0.3)
    np.testing.assert_allclose(got, expected, rtol=1e-12)
    np.testing.assert_allclose(fit.coat_unroughened(got, w, 0.3), np.broadcast_to(r, got.shape), atol=1e-9)


@pytest.mark.parametrize("n_b, n_c, w", [(1.5, 1.6, 1.0), (1.8, 1.5, 1.0), (1.5, 1.5, 0.5), (1.5, 1.6, 0.0),
                                         (1.4, 1.6, 0.3)])
def test_base_ior_under_a_coat_is_the_inverted_ratio_mixed_by_weight(n_b, n_c, w):
    ratio = n_b / n_c if n_b > n_c else n_c / n_b
    expected = (1.0 - w) * n_b + w * ratio
    assert float(coat.coat_relative_ior(n_b, n_c, w)) == pytest.approx(expected, rel=1e-12)
    assert float(fit.base_ior_under_coat(n_b, n_c, w)) == pytest.approx(expected, rel=1e-12)


def _darkening(e_base, n_c, amount):
    """OpenPBR 1.1 "Coat darkening": K = 1 - (1 - F0(n_c)) / n_c^2, (1 - K) / (1 - E K), mixed with 1."""
    f0 = ((n_c - 1.0) / (n_c + 1.0)) ** 2
    k = 1.0 - (1.0 - f0) / n_c ** 2
    return 1.0 + amount * ((1.0 - k) / (1.0 - e_base * k) - 1.0)


def test_coat_darkening_of_a_black_and_a_white_base():
    # n_c = 1.5: F0 = 0.04, K = 1 - 0.96 / 2.25; a black base keeps 1 - K = 0.42666..., a white one all.
    black = coat.coat_darkening_factor(np.zeros(3), 0.0, 1.0, 0.0, np.zeros(3), 1.0, 1.0, 1.5)
    np.testing.assert_allclose(black, np.full(3, 0.96 / 2.25), rtol=1e-12)
    white = coat.coat_darkening_factor(np.ones(3), 0.0, 1.0, 0.0, np.zeros(3), 1.0, 1.0, 1.5)
    np.testing.assert_allclose(white, np.ones(3), rtol=1e-12)


@pytest.mark.parametrize("metalness, specular_weight, sss, w, d, n_c",
                         [(0.0, 1.0, 0.0, 1.0, 1.0, 1.5), (1.0, 0.6, 0.0, 1.0, 1.0, 1.8), (0.5, 0.8, 0.3, 0.7, 0.5, 1.4),
                          (0.0, 1.0, 1.0, 1.0, 0.0, 1.6), (0.2, 1.0, 0.0, 0.0, 1.0, 2.0)])
def test_coat_darkening_is_the_specifications(metalness, specular_weight, sss, w, d, n_c):
    base, sss_colour = np.array([0.8, 0.3, 0.05]), np.array([0.2, 0.9, 0.5])
    dielectric = (1.0 - sss) * base + sss * sss_colour
    e_base = (1.0 - metalness) * dielectric + metalness * specular_weight * base
    expected = _darkening(e_base, n_c, w * d)
    got = coat.coat_darkening_factor(base, metalness, specular_weight, sss, sss_colour, w, d, n_c)
    np.testing.assert_allclose(got, expected, rtol=1e-12)


def test_coat_absorption_mixes_one_and_the_coat_colour():
    colour = np.array([0.9, 0.5, 0.1])
    np.testing.assert_allclose(coat.coat_absorption(colour, 0.25), 0.75 + 0.25 * colour, rtol=1e-15)
    np.testing.assert_allclose(coat.coat_absorption(colour, 1.0), colour, rtol=1e-15)
    np.testing.assert_allclose(coat.coat_absorption(colour, 0.0), np.ones(3), rtol=1e-15)


def test_evaluator_base_factor_is_darkening_times_absorption():
    values = {"base_color": (0.2, 0.5, 0.7), "coat_weight": 0.8, "coat_ior": 1.7, "coat_darkening": 0.9,
              "coat_color": (0.9, 0.8, 1.0)}
    model = build_model("open_pbr_surface", values)
    expected = _darkening(np.array(values["base_color"]), 1.7, 0.8 * 0.9) * (0.2 + 0.8 * np.array(values["coat_color"]))
    np.testing.assert_allclose(np.reshape(model.base_factor, -1), expected, rtol=1e-12)


# ------------------------------------------------------------------------- anisotropy

@pytest.mark.parametrize("r, a", [(0.5, 0.0), (0.5, 1.0), (0.3, 0.5), (1.0, 0.8), (0.7, 1.5)])
def test_openpbr_alphas_are_the_specifications(r, a):
    a_c = min(max(a, 0.0), 1.0)
    alpha_t = r * r * math.sqrt(2.0 / (1.0 + (1.0 - a_c) ** 2))
    t, b = microfacet.openpbr_alphas(np.asarray(r), np.asarray(a))
    assert float(t) == pytest.approx(alpha_t, rel=1e-14)
    assert float(b) == pytest.approx((1.0 - a_c) * alpha_t, rel=1e-14, abs=1e-300)
    # Isotropic: r^2 both ways; alpha_t alpha_b is what the Standard Surface translation keeps.
    if a == 0.0:
        assert float(t) == float(b) == pytest.approx(r * r, rel=1e-15)


@pytest.mark.parametrize("alpha, s", [(0.09, 0.0), (0.09, 1.0), (0.25, 0.5), (0.0, 0.3)])
def test_gltf_anisotropic_alpha_is_the_extensions(alpha, s):
    assert float(microfacet.gltf_anisotropic_alpha(alpha, s)) == pytest.approx(alpha * (1.0 - s * s) + s * s, rel=1e-14)


# ---------------------------------------------------------------- one place, called by both

def test_translators_call_the_evaluators_functions():
    assert fit.coat_roughened is coat.coat_roughened
    assert ss_translate.coat_roughened is coat.coat_roughened
    assert gltf_translate.coat_darkening_factor is coat.coat_darkening_factor
    assert usd_translate.coat_darkening_factor is coat.coat_darkening_factor
    assert ss_translate.coat_darkening_factor is coat.coat_darkening_factor
    assert fit.conductor_reflectance is fresnel.fresnel_conductor_real
    assert gltf_translate.openpbr_alphas is microfacet.openpbr_alphas
