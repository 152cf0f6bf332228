"""Thin-film interference against the characteristic-matrix method (Macleod, *Thin-Film Optical
Filters*, ch. 2; Born & Wolf 1.6.2), the quarter-wave anti-reflection coating, and
colour-science's own spectral integration."""

import numpy as np
import pytest

from openpbr_tools.evaluate import thinfilm
from test_evaluate_fresnel import snell_fresnel


def characteristic_matrix_reflectance(theta, thickness, n_film, n_sub, wavelength):
    """Unpolarised reflectance of one layer by the characteristic matrix, in Macleod's
    convention (absorbing media N = n - ik, tilted admittances n cos t (s) and n / cos t (p))."""
    n0 = 1.0
    n1 = complex(n_film)
    n2 = complex(n_sub.real, -n_sub.imag)
    s0 = np.sin(theta)
    c0 = np.cos(theta)
    c1 = np.sqrt(1 - (n0 * s0 / n1) ** 2)
    c2 = np.sqrt(1 - (n0 * s0 / n2) ** 2)
    if c2.imag > 0:
        c2 = np.conj(c2)
    delta = 2 * np.pi * n1 * thickness * c1 / wavelength
    total = 0.0
    for pol in ("s", "p"):
        y0, y1, y2 = (n0 * c0, n1 * c1, n2 * c2) if pol == "s" else (n0 / c0, n1 / c1, n2 / c2)
        m = np.array([[np.cos(delta), 1j * np.sin(delta) / y1], [1j * y1 * np.sin(delta), np.cos(delta)]])
        b, c = m @ np.array([1.0, y2])
        r = (y0 * b - c) / (y0 * b + c)
        total += abs(r) ** 2
    return total / 2


@pytest.mark.parametrize("theta", [0.0, 0.5, 1.0, 1.4])
@pytest.mark.parametrize("substrate", [1.5, 1.2, 2.4, 0.2 + 3.4j, 1.1 + 6.8j])
@pytest.mark.parametrize("thickness", [0.0, 120.0, 380.0, 900.0])
def test_airy_reflectance_equals_the_characteristic_matrix_method(theta, substrate, thickness):
    for wavelength in (420.0, 550.0, 690.0):
        expected = characteristic_matrix_reflectance(theta, thickness, 1.38, substrate, wavelength)
        got = thinfilm.airy_reflectance(np.cos(theta), thickness, 1.38, substrate, wavelength)
        assert got == pytest.approx(expected, abs=1e-10)


def test_quarter_wave_coating_cancels_reflection_at_its_design_wavelength():
    n_sub = 1.5
    n_film = np.sqrt(n_sub)
    design = 550.0
    thickness = design / (4 * n_film)
    assert thinfilm.airy_reflectance(1.0, thickness, n_film, n_sub, design) == pytest.approx(0.0, abs=1e-14)
    assert thinfilm.airy_reflectance(1.0, thickness, n_film, n_sub, 420.0) > 1e-3


def test_film_of_zero_thickness_or_index_one_leaves_the_substrate_fresnel():
    cos = np.linspace(0.05, 1, 20)
    expected = snell_fresnel(cos, 1.0, 1.6)
    np.testing.assert_allclose(thinfilm.airy_reflectance(cos, 0.0, 1.4, 1.6, 550.0), expected, atol=1e-12)
    np.testing.assert_allclose(thinfilm.airy_reflectance(cos, 700.0, 1.0, 1.6, 550.0), expected, atol=1e-12)


def test_spectrally_flat_reflectance_maps_to_equal_rgb():
    rgb = thinfilm.thin_film_rgb(np.array([1.0, 0.5]), 0.0, 1.4, np.full(3, 1.5))
    expected = snell_fresnel(np.array([1.0, 0.5]), 1.0, 1.5)
    np.testing.assert_allclose(rgb, np.repeat(expected[:, None], 3, axis=1), atol=1e-6)


def test_film_colour_matches_colour_science_spectral_integration():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import colour

    thickness, n_film, n_sub, theta = 400.0, 1.33, 1.5, 0.3
    wavelengths = np.arange(360.0, 781.0, 1.0)
    reflectance = np.array([characteristic_matrix_reflectance(theta, thickness, n_film, n_sub, w) for w in wavelengths])
    sd = colour.SpectralDistribution(dict(zip(wavelengths, reflectance)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # colour-science notes that it aligns D65 to the CMFs
        xyz = colour.sd_to_XYZ(sd, illuminant=colour.SDS_ILLUMINANTS["D65"]) / 100.0
    space = colour.RGB_COLOURSPACES["sRGB"]
    expected = colour.XYZ_to_RGB(xyz, space, illuminant=space.whitepoint, apply_cctf_encoding=False)
    got = thinfilm.thin_film_rgb(np.cos(theta), thickness, n_film, np.full(3, n_sub))
    np.testing.assert_allclose(got, expected, atol=3e-3)


@pytest.mark.parametrize("film, substrate", [(1.0, 1.0), (1.0, 1.5), (1.5, 1.0), (1.3, 0.2 + 3.0j)])
def test_grazing_incidence_with_index_one_layers_is_finite(film, substrate):
    # Born & Wolf: with no index step there is no reflection; at grazing incidence on any index step
    # the reflectance tends to 1. Neither limit may come out as 0/0.
    with np.errstate(all="raise"):
        reflectance = thinfilm.airy_reflectance(0.0, 500.0, film, substrate, 550.0)
    if film == 1.0 and substrate == 1.0:
        assert reflectance == pytest.approx(0.0, abs=1e-6)
    else:
        assert 0.99 < reflectance <= 1.0 + 1e-9
