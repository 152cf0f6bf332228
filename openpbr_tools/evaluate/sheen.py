"""Sheen lobes for fabrics and dust: Conty-Kulla ("Charlie") and Zeltner's LTC sheen.

Directions are unit vectors in the local frame (last axis xyz), ``wo`` above the surface.
Values are BSDF values per unit colour, without the incident cosine.
"""

from __future__ import annotations

import numpy as np

_EPS = 1e-7

#: Minimum Charlie roughness: the NDF exponent 1/r is capped at 200 (MaterialX clamps r at 0.005).
CHARLIE_MIN_ROUGHNESS = 0.005
#: Zeltner's fits cover roughness in [0.01, 1] (MaterialX clamps to this range).
ZELTNER_MIN_ROUGHNESS = 0.01


def charlie_ndf(cos_h, roughness):
    """"Charlie" sheen microfibre distribution D(h) = (2 + 1/r) sin(theta_h)^(1/r) / (2 pi).

    Normalised so that int D(h) cos(theta_h) dh = 1 over the hemisphere.
    Reference: Conty Estevez & Kulla, "Production Friendly Microfacet Sheen BRDF", SIGGRAPH 2017
    course notes, eq. 2.
    """
    inv_r = 1.0 / np.maximum(np.asarray(roughness, dtype=float), CHARLIE_MIN_ROUGHNESS)
    sin2 = np.clip(1.0 - np.asarray(cos_h) ** 2, 0.0, 1.0)
    return (2.0 + inv_r) * sin2 ** (0.5 * inv_r) / (2.0 * np.pi)


def ashikhmin_visibility(cos_i, cos_o):
    """Smooth visibility term V = 1 / (4 (cos_i + cos_o - cos_i cos_o)) replacing
    G / (4 cos_i cos_o). Reference: Neubelt & Pettineo, "Crafting a Next-Gen Material Pipeline
    for The Order: 1886", SIGGRAPH 2013 course notes, section 3.3.1 (after Ashikhmin & Premoze
    2007)."""
    return 1.0 / (4.0 * np.maximum(cos_i + cos_o - cos_i * cos_o, _EPS))


def _charlie_l(x, r):
    t = (1.0 - r) ** 2
    a = 21.5473 + (25.3245 - 21.5473) * t
    b = 3.82987 + (3.32435 - 3.82987) * t
    c = 0.19823 + (0.16801 - 0.19823) * t
    d = -1.97760 + (-1.27393 + 1.97760) * t
    e = -4.32054 + (-4.85967 + 4.32054) * t
    return a / (1.0 + b * np.power(np.maximum(x, 0.0), c)) + d * x + e


def charlie_lambda(cos_theta, roughness):
    """Conty-Kulla's fitted Smith Lambda for the Charlie distribution.

    Lambda(mu) = exp(L(mu)) for mu < 0.5, exp(2 L(0.5) - L(1 - mu)) otherwise, with the
    five-coefficient fit L interpolated in (1 - r)^2. References: Conty Estevez & Kulla 2017,
    section 3 and table 1; KHR_materials_sheen, "Sheen visibility".
    """
    mu = np.abs(cos_theta)
    r = np.clip(np.asarray(roughness, dtype=float), CHARLIE_MIN_ROUGHNESS, 1.0)
    low = np.exp(_charlie_l(mu, r))
    high = np.exp(2.0 * _charlie_l(0.5, r) - _charlie_l(1.0 - mu, r))
    return np.where(mu < 0.5, low, high)


def conty_kulla_sheen(wi, wo, roughness, visibility="ashikhmin"):
    """Conty-Kulla ("Charlie") sheen BRDF per unit colour: D(h) V(wi, wo), no Fresnel.

    ``visibility="ashikhmin"`` uses :func:`ashikhmin_visibility` (MaterialX's
    ``sheen_bsdf`` mode ``conty_kulla``); ``"charlie"`` uses the shadowing of
    :func:`charlie_lambda`, V = 1 / ((1 + L(wi) + L(wo)) 4 cos_i cos_o) (KHR_materials_sheen).
    Both are reciprocal. Reference: Conty Estevez & Kulla, SIGGRAPH 2017, eq. 1-2.
    """
    cos_i = wi[..., 2]
    cos_o = wo[..., 2]
    h = wi + wo
    h = h / np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), _EPS)
    d = charlie_ndf(h[..., 2], roughness)
    if visibility == "ashikhmin":
        v = ashikhmin_visibility(cos_i, cos_o)
    else:
        lam = charlie_lambda(cos_i, roughness) + charlie_lambda(cos_o, roughness)
        v = 1.0 / ((1.0 + lam) * 4.0 * np.maximum(cos_i * cos_o, _EPS))
    return np.where((cos_i > 0.0) & (cos_o > 0.0), d * v, 0.0)


def zeltner_sheen_albedo(cos_o, roughness):
    """Directional albedo R(mu_o, r) of Zeltner's sheen (Gaussian fit in mu_o).

    Reference: Zeltner, Burley, Chiang, "Practical Multiple-Scattering Sheen Using Linearly
    Transformed Cosines", SIGGRAPH 2022 talk; analytic fits to its tabulated reflectance as used
    by the OpenPBR Surface reference implementation and MaterialX (``mx_zeltner_sheen_dir_albedo``).
    """
    x = np.asarray(cos_o, dtype=float)
    y = np.clip(np.asarray(roughness, dtype=float), ZELTNER_MIN_ROUGHNESS, 1.0)
    s = y * (0.0206607 + 1.58491 * y) / (0.0379424 + y * (1.32227 + y))
    m = y * (-0.193854 + y * (-1.14885 + y * (1.7932 - 0.95943 * y * y))) / (0.046391 + y)
    o = y * (0.000654023 + (-0.0207818 + 0.119681 * y) * y) / (1.26264 + y * (-1.92021 + y))
    return np.exp(-0.5 * ((x - m) / s) ** 2) / (s * np.sqrt(2.0 * np.pi)) + o


def zeltner_ltc_coefficients(cos_o, roughness):
    """Inverse-LTC coefficients (a_inv, b_inv) of Zeltner's sheen (rational fits, same source as
    :func:`zeltner_sheen_albedo`). The inverse transform is [[a, 0, b], [0, a, 0], [0, 0, 1]]."""
    x = np.asarray(cos_o, dtype=float)
    y = np.clip(np.asarray(roughness, dtype=float), ZELTNER_MIN_ROUGHNESS, 1.0)
    a_inv = (2.58126 * x + 0.813703 * y) * y / (1.0 + 0.310327 * x * x + 2.60994 * x * y)
    b_inv = np.sqrt(np.maximum(1.0 - x, 0.0)) * (y - 1.0) * y**3 / (
        0.0000254053 + 1.71228 * x - 1.71506 * x * y + 1.34174 * y * y
    )
    return a_inv, b_inv


def zeltner_ltc_distribution(wi, wo, roughness):
    """The LTC-transformed clamped-cosine distribution D(wi) of Zeltner's sheen for view ``wo``,
    normalised over the sphere (int D dw = 1); its part above the horizon is the lobe's shape.

    The frame's x axis lies in the plane of ``wo`` and the normal. With w' = M^-1 w,
    D(w) = (w'_z / pi) |M^-1| / |w'|^4, |M^-1| = a_inv^2 (Heitz, Dupuy, Hill, Neubelt,
    "Real-Time Polygonal-Light Shading with Linearly Transformed Cosines", SIGGRAPH 2016, eq. 1).
    """
    cos_o = np.clip(wo[..., 2], 0.0, 1.0)
    tx, ty = wo[..., 0], wo[..., 1]
    t_len = np.sqrt(tx * tx + ty * ty)
    has_t = t_len > 1e-9
    tx = np.where(has_t, tx / np.where(has_t, t_len, 1.0), 1.0)
    ty = np.where(has_t, ty / np.where(has_t, t_len, 1.0), 0.0)
    x = wi[..., 0] * tx + wi[..., 1] * ty
    y = -wi[..., 0] * ty + wi[..., 1] * tx
    z = wi[..., 2]
    a_inv, b_inv = zeltner_ltc_coefficients(cos_o, roughness)
    px = a_inv * x + b_inv * z
    py = a_inv * y
    len2 = px * px + py * py + z * z
    return np.maximum(z, 0.0) / np.pi * (a_inv / len2) ** 2


def zeltner_sheen(wi, wo, roughness):
    """Zeltner's LTC sheen BRDF per unit colour: f = R(mu_o, r) D(wi) / cos_i.

    Not reciprocal (the LTC is fitted per view direction), which the reference accepts.
    Reference: Zeltner, Burley, Chiang 2022 (see :func:`zeltner_sheen_albedo`); OpenPBR Surface
    1.1, section "Fuzz".
    """
    cos_i = wi[..., 2]
    r = zeltner_sheen_albedo(np.clip(wo[..., 2], 0.0, 1.0), roughness)
    d = zeltner_ltc_distribution(wi, wo, roughness)
    return np.where((cos_i > 0.0) & (wo[..., 2] > 0.0), r * d / np.maximum(cos_i, _EPS), 0.0)
