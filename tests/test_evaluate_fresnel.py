"""Fresnel factors against the Fresnel equations computed independently (complex Snell's law,
Born & Wolf's real-arithmetic conductor formulas) and published values."""

import numpy as np
import pytest

from openpbr_tools.evaluate import fresnel


def snell_fresnel(cos_i, n1, n2):
    """Unpolarised reflectance from complex amplitudes r_s, r_p (Born & Wolf 1.5.2 eq. 21)."""
    cos_i = np.asarray(cos_i, dtype=complex)
    sin_t = n1 / n2 * np.sqrt(1 - cos_i**2)
    cos_t = np.sqrt(1 - sin_t**2)
    rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t)
    rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t)
    return 0.5 * (np.abs(rs) ** 2 + np.abs(rp) ** 2)


def conductor_reflectance_real(theta, n, k):
    """Born & Wolf section 14.2 in real arithmetic (the a^2 + b^2 form), unpolarised."""
    s2 = np.sin(theta) ** 2
    c = np.cos(theta)
    t = np.tan(theta)
    a2b2 = np.sqrt((n * n - k * k - s2) ** 2 + 4 * n * n * k * k)
    a = np.sqrt(0.5 * (a2b2 + n * n - k * k - s2))
    rs = (a2b2 - 2 * a * c + c * c) / (a2b2 + 2 * a * c + c * c)
    rp = rs * (a2b2 - 2 * a * np.sin(theta) * t + s2 * t * t) / (a2b2 + 2 * a * np.sin(theta) * t + s2 * t * t)
    return 0.5 * (rs + rp)


@pytest.mark.parametrize("eta", [1.33, 1.5, 2.4, 1 / 1.5, 1 / 2.4])
def test_dielectric_fresnel_equals_the_fresnel_equations(eta):
    cos = np.linspace(0.0, 1.0, 201)
    expected = snell_fresnel(cos, 1.0, eta)
    np.testing.assert_allclose(fresnel.fresnel_dielectric(cos, eta), expected, atol=1e-12)


def test_glass_reflects_four_percent_at_normal_incidence():
    assert fresnel.fresnel_dielectric(1.0, 1.5) == pytest.approx(0.04, abs=1e-12)


def test_total_internal_reflection_beyond_the_critical_angle():
    eta = 1 / 1.5
    critical = np.sqrt(1 - eta**2)  # cos of the critical angle: sin = eta
    cos = np.array([critical * 0.99, critical * 0.5, 0.01])
    np.testing.assert_array_equal(fresnel.fresnel_dielectric(cos, eta), 1.0)
    assert fresnel.fresnel_dielectric(critical * 1.01, eta) < 1.0


def test_p_polarised_reflectance_vanishes_at_brewsters_angle():
    theta_b = np.arctan(1.5)
    rs, rp = fresnel.fresnel_dielectric_polarized(np.cos(theta_b), 1.5)
    assert rp == pytest.approx(0.0, abs=1e-12)
    assert rs > 0.1


@pytest.mark.parametrize("n,k", [(0.18, 3.42), (1.1, 6.8), (2.9, 3.1)])
def test_conductor_fresnel_equals_born_and_wolf(n, k):
    theta = np.linspace(0.0, np.radians(89.0), 90)
    np.testing.assert_allclose(fresnel.fresnel_conductor(np.cos(theta), n, k), conductor_reflectance_real(theta, n, k), rtol=1e-10)
    normal = ((n - 1) ** 2 + k * k) / ((n + 1) ** 2 + k * k)
    assert fresnel.fresnel_conductor(1.0, n, k) == pytest.approx(normal, rel=1e-12)


def test_schlick_interpolates_between_f0_and_f90():
    assert fresnel.fresnel_schlick(1.0, 0.04) == pytest.approx(0.04)
    assert fresnel.fresnel_schlick(0.0, 0.04) == pytest.approx(1.0)
    assert fresnel.fresnel_schlick(0.0, 0.04, f90=0.5) == pytest.approx(0.5)
    # (1 - 0.5)^5 = 1/32 of the way from F0 to F90 at 60 degrees.
    assert fresnel.fresnel_schlick(0.5, 0.2) == pytest.approx(0.2 + 0.8 / 32)


def test_f82_tint_scales_schlick_by_the_tint_at_82_degrees():
    f0 = np.array([0.95, 0.64, 0.54])
    tint = np.array([0.9, 0.5, 0.2])
    mu_bar = 1 / 7
    schlick = f0 + (1 - f0) * (1 - mu_bar) ** 5
    np.testing.assert_allclose(fresnel.f82_tint(mu_bar, f0, tint), tint * schlick, rtol=1e-12)
    np.testing.assert_allclose(fresnel.f82_tint(1.0, f0, tint), f0, rtol=1e-12)
    np.testing.assert_allclose(fresnel.f82_tint(0.0, f0, tint), 1.0, rtol=1e-12)


def test_f82_tint_of_one_is_schlick():
    cos = np.linspace(0, 1, 11)[:, None]
    f0 = np.array([0.2, 0.5, 0.9])
    np.testing.assert_allclose(fresnel.f82_tint(cos, f0, 1.0), fresnel.fresnel_schlick(cos, f0), atol=1e-14)


@pytest.mark.parametrize("r,g", [(0.9, 0.5), (0.5, 0.9), (0.04, 1.0), (0.7, 0.0)])
def test_artistic_ior_reproduces_the_reflectivity_at_normal_incidence(r, g):
    n, k = fresnel.artistic_ior(r, g)
    normal = ((n - 1) ** 2 + k * k) / ((n + 1) ** 2 + k * k)
    assert normal == pytest.approx(r, rel=1e-9)


def test_ior_f0_round_trip():
    eta = np.array([1.0, 1.33, 1.5, 2.0, 3.0])
    np.testing.assert_allclose(fresnel.f0_to_ior(fresnel.ior_to_f0(eta)), eta, rtol=1e-9)


def test_an_ior_of_zero_reflects_everything_and_is_finite():
    """Standard Surface admits specular_IOR 0 (F0 = ((0 - 1) / (0 + 1))^2 = 1, as MaterialX's
    mx_ior_to_f0 gives); the exact formula is 0/0 at normal incidence and used to return NaN, which
    made a whole preview NaN and a NaN CIEDE2000 pass every threshold."""
    cosines = np.array([1.0, 0.7, 0.2, 0.0])
    assert fresnel.fresnel_dielectric(cosines, 0.0) == pytest.approx([1.0, 1.0, 1.0, 1.0])
    assert fresnel.fresnel_dielectric(np.array([1.0, 0.0]), 1.0) == pytest.approx([0.0, 0.0])  # no interface
    from openpbr_tools.evaluate.thinfilm import thin_film_rgb

    film = thin_film_rgb(np.linspace(0.0, 1.0, 7), 400.0, 1.5, np.zeros(3))
    assert np.isfinite(film).all()


def test_a_comparison_that_is_not_a_number_exceeds_every_threshold():
    from openpbr_tools.evaluate.difference import DeltaE

    assert DeltaE(float("nan"), float("nan"), float("nan"), 10).exceeds(1e9)
    assert not DeltaE(0.5, 1.0, 2.0, 10).exceeds(0.5) and DeltaE(0.51, 1.0, 2.0, 10).exceeds(0.5)


def test_coarse_films_rank_within_a_few_thousandths_of_the_exact_film():
    """translate.candidates renders its candidates inside coarse_films() (a 64-cosine table per
    distinct film): within 0.005 of the exact Airy evaluation, for films up to 2 um on the substrates
    the evaluators give films (indices >= 1: a dielectric, the dielectric of a metal's F0); outside the
    block the evaluation is exact again. (Below index 1 total internal reflection at the film's base
    makes a kink a 64-cosine table misses locally, by up to 0.28 at one direction.)"""
    from openpbr_tools.evaluate.thinfilm import coarse_films, thin_film_rgb

    cosines = np.random.default_rng(1).uniform(0.0, 1.0, 400)
    for thickness in (0.0, 150.0, 480.0, 1000.0, 2000.0):
        for substrate in ((1.5, 1.5, 1.5), (1.2, 2.0, 3.8)):
            args = (cosines, np.full(400, thickness), np.full(400, 1.4), np.tile(substrate, (400, 1)))
            exact = thin_film_rgb(*args)
            with coarse_films():
                coarse = thin_film_rgb(*args)
            assert np.abs(coarse - exact).max() < 0.005
            assert np.abs(coarse - exact).max() > 0.0  # (the table was used)
            assert np.array_equal(thin_film_rgb(*args), exact)
