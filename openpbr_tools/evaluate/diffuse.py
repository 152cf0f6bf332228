"""Diffuse lobes: Lambert, qualitative Oren-Nayar, Fujii's Oren-Nayar (FON), the
energy-preserving EON and translucency.

Inputs are cosines ``cos_i = wi.z``, ``cos_o = wo.z`` and ``cos_io = wi.wo`` (arrays, any
broadcastable shapes) plus colours with a trailing RGB axis. Returned values are BSDF values
without the cosine of the incident direction, per unit colour where the name says so.
"""

from __future__ import annotations

import numpy as np

#: Constants of Fujii's Oren-Nayar, as used by EON: c1 = 1/2 - 2/(3 pi), c2 = 2/3 - 28/(15 pi).
FON_C1 = 0.5 - 2.0 / (3.0 * np.pi)
FON_C2 = 2.0 / 3.0 - 28.0 / (15.0 * np.pi)
_EPS = 1e-7


def lambert(cos_i, cos_o):
    """Lambertian BRDF per unit albedo: 1/pi for both directions above the surface, else 0.

    Reference: Lambert, *Photometria*, 1760; glTF 2.0 specification, Appendix B.3.5
    (``diffuse_brdf = (1/pi) * color``).
    """
    return np.where((np.asarray(cos_i) > 0.0) & (np.asarray(cos_o) > 0.0), 1.0 / np.pi, 0.0)


def oren_nayar(cos_i, cos_o, cos_io, sigma):
    """Qualitative Oren-Nayar BRDF per unit albedo, sigma = roughness in radians.

    f = (A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta)) / pi with
    A = 1 - 0.5 s2/(s2 + 0.33), B = 0.45 s2/(s2 + 0.09), s2 = sigma^2; the angular term equals
    s / max(cos_i, cos_o) with s = wi.wo - cos_i cos_o.

    Reference: Oren & Nayar, "Generalization of Lambert's Reflectance Model", SIGGRAPH 1994,
    eq. 30 (the qualitative model). Used by Standard Surface through MaterialX's
    ``oren_nayar_diffuse_bsdf`` (energy_compensation = false). Reciprocal.
    """
    s2 = np.asarray(sigma, dtype=float) ** 2
    a = 1.0 - 0.5 * s2 / (s2 + 0.33)
    b = 0.45 * s2 / (s2 + 0.09)
    s = cos_io - cos_i * cos_o
    t = np.maximum(np.maximum(cos_i, cos_o), _EPS)
    angular = np.where(s > 0.0, s / t, 0.0)
    return lambert(cos_i, cos_o) * (a + b * angular)


def fujii_oren_nayar(cos_i, cos_o, cos_io, sigma):
    """Fujii's improved Oren-Nayar ("FON") BRDF per unit albedo, sigma in [0, 1].

    f = A (1 + sigma s / t) / pi, A = 1 / (1 + c1 sigma), s = wi.wo - cos_i cos_o,
    t = max(cos_i, cos_o) if s > 0 else 1.

    References: Fujii, "A tiny improvement of Oren-Nayar reflectance model", 2013
    (mimosa-pudica.net/improved-oren-nayar.html); Portsmouth, Kutz, Hill, "EON: A practical
    energy-preserving rough diffuse BRDF", JCGT 14(1), 2025, eq. 3-4.
    """
    sigma = np.asarray(sigma, dtype=float)
    a = 1.0 / (1.0 + FON_C1 * sigma)
    s = cos_io - cos_i * cos_o
    t = np.where(s > 0.0, np.maximum(np.maximum(cos_i, cos_o), _EPS), 1.0)
    return lambert(cos_i, cos_o) * a * (1.0 + sigma * s / t)


def fujii_oren_nayar_albedo(cos_theta, sigma):
    """Exact directional albedo E_FON(mu) of :func:`fujii_oren_nayar` (unit albedo).

    E = A (1 + sigma G(theta) / pi), G = sin(t)(t - sin(t) cos(t)) + (2/3) tan(t)(1 - sin^3 t)
    - (2/3) sin t. Reference: Fujii 2013; EON paper (JCGT 2025), eq. 8.
    """
    sigma = np.asarray(sigma, dtype=float)
    mu = np.clip(cos_theta, _EPS, 1.0)
    sin_t = np.sqrt(np.maximum(0.0, 1.0 - mu * mu))
    theta = np.arccos(mu)
    g = sin_t * (theta - sin_t * mu) + (2.0 / 3.0) * ((sin_t / mu) * (1.0 - sin_t**3) - sin_t)
    a = 1.0 / (1.0 + FON_C1 * sigma)
    return a * (1.0 + sigma * g / np.pi)


def fujii_oren_nayar_average_albedo(sigma):
    """Cosine-weighted average of E_FON over the hemisphere: A (1 + c2 sigma) (EON eq. 9)."""
    sigma = np.asarray(sigma, dtype=float)
    return (1.0 + FON_C2 * sigma) / (1.0 + FON_C1 * sigma)


def eon_diffuse(cos_i, cos_o, cos_io, sigma, albedo):
    """Energy-preserving Oren-Nayar (EON): FON plus a Kelemen-Szirmay-Kalos multiple-scattering
    lobe, so a white surface reflects all light at every roughness.

    f = rho f_FON + rho_ms (1 - E(mu_i)) (1 - E(mu_o)) / (pi (1 - E_avg)),
    rho_ms = rho^2 E_avg / (1 - rho (1 - E_avg)). ``albedo`` is an RGB colour (last axis); the
    result has the broadcast shape of the cosines plus the RGB axis. Reciprocal.

    References: Portsmouth, Kutz, Hill, "EON: A practical energy-preserving rough diffuse BRDF",
    JCGT 14(1), 2025, eq. 10-12; OpenPBR Surface 1.1, section "Glossy-diffuse".
    """
    rho = np.asarray(albedo, dtype=float)
    sigma = np.asarray(sigma, dtype=float)
    single = fujii_oren_nayar(cos_i, cos_o, cos_io, sigma)
    e_i = fujii_oren_nayar_albedo(cos_i, sigma)
    e_o = fujii_oren_nayar_albedo(cos_o, sigma)
    e_avg = fujii_oren_nayar_average_albedo(sigma)
    shape = lambert(cos_i, cos_o) * np.maximum(1.0 - e_i, 0.0) * np.maximum(1.0 - e_o, 0.0)
    shape = shape / np.maximum(1.0 - e_avg, _EPS)
    e_avg_c = e_avg[..., None] if e_avg.ndim else e_avg
    rho_ms = rho * rho * e_avg_c / (1.0 - rho * (1.0 - e_avg_c))
    return single[..., None] * rho + shape[..., None] * rho_ms


def eon_albedo(cos_theta, sigma, albedo):
    """Directional albedo of :func:`eon_diffuse`: rho E_FON(mu) + rho_ms (1 - E_FON(mu))."""
    rho = np.asarray(albedo, dtype=float)
    e = fujii_oren_nayar_albedo(cos_theta, sigma)
    e_avg = np.asarray(fujii_oren_nayar_average_albedo(sigma))
    e_avg_c = e_avg[..., None] if e_avg.ndim else e_avg
    rho_ms = rho * rho * e_avg_c / (1.0 - rho * (1.0 - e_avg_c))
    return rho * e[..., None] + rho_ms * (1.0 - e[..., None])


def translucent(cos_i, cos_o):
    """Diffuse transmission per unit colour: 1/pi for directions on opposite sides, else 0.

    Reference: MaterialX PBS nodes 1.39, ``translucent_bsdf`` (Lambertian transmission).
    """
    return np.where(np.asarray(cos_i) * np.asarray(cos_o) < 0.0, 1.0 / np.pi, 0.0)
