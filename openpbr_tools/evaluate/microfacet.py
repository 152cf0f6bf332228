"""GGX (Trowbridge-Reitz) microfacet lobes: NDF, Smith masking-shadowing, reflection and
transmission, and sampling of visible normals (used to build the albedo tables).

Conventions: directions are unit vectors in the local shading frame (normal +z, tangent +x,
bitangent +y), stored in arrays whose last axis is xyz; any leading shape broadcasts. ``wi``
points towards the light, ``wo`` towards the viewer; both point away from the surface.
Roughness is given as GGX alphas ``alpha_x`` (along the tangent) and ``alpha_y``.
Lobe functions return the BSDF value *without* the cosine of the incident direction.
"""

from __future__ import annotations

import numpy as np

_TINY = 1e-12


def dot(a, b):
    """Dot product over the last axis."""
    return np.einsum("...i,...i->...", a, b) if a.shape == b.shape else np.sum(a * b, axis=-1)


def normalize(v):
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), _TINY)


def openpbr_alphas(roughness, anisotropy):
    """GGX alphas (along tangent, bitangent) of OpenPBR's roughness r and roughness anisotropy a,
    unclamped: alpha_t = r^2 sqrt(2 / (1 + (1 - a)^2)), alpha_b = (1 - a) alpha_t, with a clamped
    to [0, 1]. (``roughness ** 2`` as given: NumPy squares an array exactly as r * r.)

    Reference: OpenPBR Surface 1.1, section "Specular anisotropy" (MaterialX
    ``open_pbr_anisotropy``).
    """
    a = np.clip(anisotropy, 0.0, 1.0)
    alpha_t = roughness ** 2 * np.sqrt(2.0 / (1.0 + (1.0 - a) ** 2))
    return alpha_t, (1.0 - a) * alpha_t


def gltf_anisotropic_alpha(alpha, strength):
    """glTF's GGX alpha along the anisotropy direction, alpha_t = mix(alpha, 1, strength^2), from
    the isotropic alpha = roughness^2 (which stays the bitangent's alpha).

    Reference: KHR_materials_anisotropy (Khronos glTF extension registry), section "Individual
    Lights" (``alphaT = mix(alphaRoughness, 1.0, anisotropy^2)``).
    """
    return alpha + (1.0 - alpha) * strength ** 2


def ggx_ndf(h, alpha_x, alpha_y):
    """Anisotropic GGX normal distribution D(h) for a unit half vector ``h`` (local frame).

    D(h) = 1 / (pi ax ay ((hx/ax)^2 + (hy/ay)^2 + hz^2)^2) for hz > 0, else 0.
    Normalised so that the projected microfacet area integrates to 1: int D(h) hz dh = 1.

    References: Walter, Marschner, Li, Torrance, EGSR 2007, eq. 33 (isotropic);
    Burley, "Physically-Based Shading at Disney", SIGGRAPH 2012 course notes, appendix B.2 eq. 13
    (anisotropic).
    """
    hx, hy, hz = h[..., 0], h[..., 1], h[..., 2]
    ax = np.asarray(alpha_x, dtype=float)
    ay = np.asarray(alpha_y, dtype=float)
    d = (hx / ax) ** 2 + (hy / ay) ** 2 + hz * hz
    value = 1.0 / (np.pi * ax * ay * d * d)
    return np.where(hz > 0.0, value, 0.0)


def ggx_lambda(w, alpha_x, alpha_y):
    """Smith's auxiliary function Lambda(w) for the anisotropic GGX distribution.

    Lambda = (-1 + sqrt(1 + alpha_w^2 tan^2 theta)) / 2 with alpha_w^2 tan^2 theta =
    (wx^2 ax^2 + wy^2 ay^2) / wz^2.

    Reference: Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
    JCGT 3(2), 2014, eq. 72 and 86 (anisotropic form, section 5.2).
    """
    wz2 = np.maximum(w[..., 2] ** 2, _TINY)
    ax = np.asarray(alpha_x, dtype=float)
    ay = np.asarray(alpha_y, dtype=float)
    a2t2 = (w[..., 0] ** 2 * ax * ax + w[..., 1] ** 2 * ay * ay) / wz2
    return 0.5 * (np.sqrt(1.0 + a2t2) - 1.0)


def smith_g1(w, alpha_x, alpha_y):
    """Smith masking function G1(w) = 1 / (1 + Lambda(w)) (Heitz 2014, eq. 43)."""
    return 1.0 / (1.0 + ggx_lambda(w, alpha_x, alpha_y))


def smith_g2_height_correlated(wi, wo, alpha_x, alpha_y):
    """Height-correlated Smith masking-shadowing G2 = 1 / (1 + Lambda(wi) + Lambda(wo)).

    Reference: Heitz 2014 (JCGT 3(2)), eq. 99. Valid for reflection and, with the two
    directions on opposite sides, for transmission (eq. 100 uses the same form).
    """
    return 1.0 / (1.0 + ggx_lambda(wi, alpha_x, alpha_y) + ggx_lambda(wo, alpha_x, alpha_y))


def ggx_reflection(wi, wo, alpha_x, alpha_y):
    """Microfacet reflection lobe without Fresnel: D(h) G2 / (4 cos_i cos_o), and h.wo.

    Returns ``(value, cos_h)``: the lobe value (0 unless both directions are above the surface;
    callers viewing from below mirror both directions first) and the cosine between ``wo`` and
    the half vector, at which the caller evaluates its Fresnel factor.

    Reference: Walter et al., EGSR 2007, eq. 20 (Cook-Torrance form with the GGX D of eq. 33 and
    the height-correlated G2 of Heitz 2014 eq. 99). Reciprocal: f(wi, wo) = f(wo, wi).
    """
    hx = wi[..., 0] + wo[..., 0]
    hy = wi[..., 1] + wo[..., 1]
    hz = wi[..., 2] + wo[..., 2]
    inv = 1.0 / np.maximum(np.sqrt(hx * hx + hy * hy + hz * hz), _TINY)
    hx, hy, hz = hx * inv, hy * inv, hz * inv
    cos_i = wi[..., 2]
    cos_o = wo[..., 2]
    ax = np.asarray(alpha_x, dtype=float)
    ay = np.asarray(alpha_y, dtype=float)
    ax2, ay2 = ax * ax, ay * ay
    d = hx * hx / ax2 + hy * hy / ay2 + hz * hz
    ndf = 1.0 / (np.pi * ax * ay * d * d)
    ci2 = np.maximum(cos_i * cos_i, _TINY)
    co2 = np.maximum(cos_o * cos_o, _TINY)
    lam_i = np.sqrt(1.0 + (wi[..., 0] ** 2 * ax2 + wi[..., 1] ** 2 * ay2) / ci2)
    lam_o = np.sqrt(1.0 + (wo[..., 0] ** 2 * ax2 + wo[..., 1] ** 2 * ay2) / co2)
    # G2 / (4 cos_i cos_o) with G2 = 2 / (lam_i + lam_o) (Lambda = (lam - 1) / 2).
    value = ndf * 0.5 / ((lam_i + lam_o) * np.maximum(cos_i * cos_o, _TINY))
    cos_h = np.clip(wo[..., 0] * hx + wo[..., 1] * hy + wo[..., 2] * hz, 0.0, 1.0)
    return np.where((cos_i > 0.0) & (cos_o > 0.0), value, 0.0), cos_h


def refraction_half_vector(wi, wo, eta_i, eta_o):
    """Generalised half vector for refraction, h = -(eta_i wi + eta_o wo) normalised and
    oriented towards +z (Walter et al. 2007, eq. 16)."""
    h = -(np.asarray(eta_i)[..., None] * wi + np.asarray(eta_o)[..., None] * wo)
    h = normalize(h)
    return h * np.where(h[..., 2] < 0.0, -1.0, 1.0)[..., None]


def ggx_transmission(wi, wo, alpha_x, alpha_y, eta_i, eta_o):
    """Microfacet transmission lobe without the (1 - F) factor, for ``wi`` and ``wo`` on
    opposite sides; ``eta_i``/``eta_o`` are the refractive indices on the side of ``wi``/``wo``.

    f_t = |wi.h| |wo.h| / (|cos_i| |cos_o|) * eta_o^2 D(h) G2 / (eta_i wi.h + eta_o wo.h)^2.
    Returns ``(value, cos_h)`` with ``cos_h = |wo.h|`` (evaluate the Fresnel factor there, with
    relative index eta_i / eta_o). The eta_o^2 factor makes the lobe transport radiance, so it
    obeys the generalised reciprocity f(wi, wo) / eta_o^2 = f(wo, wi) / eta_i^2.

    Reference: Walter, Marschner, Li, Torrance, EGSR 2007, eq. 21, with G2 from Heitz 2014
    eq. 99.
    """
    opposite = wi[..., 2] * wo[..., 2] < 0.0
    h = refraction_half_vector(wi, wo, eta_i, eta_o)
    wi_h = dot(wi, h)
    wo_h = dot(wo, h)
    # Each direction must lie on the same side of the microfacet as of the macrosurface.
    valid = opposite & (wi_h * wi[..., 2] > 0.0) & (wo_h * wo[..., 2] > 0.0)
    denom = np.asarray(eta_i) * wi_h + np.asarray(eta_o) * wo_h
    cos_i = np.abs(wi[..., 2])
    cos_o = np.abs(wo[..., 2])
    d = ggx_ndf(h, alpha_x, alpha_y)
    g = smith_g2_height_correlated(wi, wo, alpha_x, alpha_y)
    value = (
        np.abs(wi_h * wo_h)
        / np.maximum(cos_i * cos_o, _TINY)
        * np.asarray(eta_o) ** 2
        * d
        * g
        / np.maximum(denom * denom, _TINY)
    )
    return np.where(valid, value, 0.0), np.abs(wo_h)


def sample_ggx_vnormal(wo, alpha_x, alpha_y, u1, u2):
    """Map uniform numbers ``(u1, u2)`` in [0, 1) to microfacet normals distributed as the GGX
    distribution of visible normals seen from ``wo`` (upper hemisphere).

    Reference: Dupuy & Benyoub, "Sampling Visible GGX Normals with Spherical Caps", HPG 2023
    (Listing 3), a reformulation of Heitz, "Sampling the GGX Distribution of Visible Normals",
    JCGT 7(4), 2018. The density is D_wo(h) = G1(wo) max(0, wo.h) D(h) / cos_o.
    """
    ax = np.asarray(alpha_x, dtype=float)
    ay = np.asarray(alpha_y, dtype=float)
    v = normalize(np.stack([wo[..., 0] * ax, wo[..., 1] * ay, wo[..., 2]], axis=-1))
    phi = 2.0 * np.pi * u1
    z = (1.0 - u2) * (1.0 + v[..., 2]) - v[..., 2]
    sin_t = np.sqrt(np.clip(1.0 - z * z, 0.0, 1.0))
    c = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), z], axis=-1)
    h = c + v
    h = np.stack([h[..., 0] * ax, h[..., 1] * ay, np.maximum(h[..., 2], 0.0)], axis=-1)
    return normalize(h)


def reflect(w, h):
    """Mirror ``w`` about ``h``: 2 (w.h) h - w."""
    return 2.0 * dot(w, h)[..., None] * h - w


def refract(w, h, eta):
    """Refract ``w`` (pointing away from the surface, on the side ``h`` points to) through a
    facet with normal ``h``; ``eta`` = n_other / n_w. Returns ``(direction, valid)`` where
    ``valid`` is False under total internal reflection."""
    cos_i = dot(w, h)
    eta = np.asarray(eta, dtype=float)
    sin2_t = (1.0 - cos_i * cos_i) / (eta * eta)
    valid = sin2_t < 1.0
    cos_t = np.sqrt(np.clip(1.0 - sin2_t, 0.0, 1.0))
    t = -w / eta[..., None] + (cos_i / eta - cos_t)[..., None] * h
    return normalize(t), valid
