"""glTF's anisotropy convention (KHR_materials_anisotropy, and KHR_materials_coat's coat anisotropy)
and OpenPBR's, both ways, exactly.

glTF: alpha_t = mix(alpha, 1, s^2), alpha_b = alpha, alpha = r_g^2 (the extension's README).
OpenPBR: alpha_t = r^2 sqrt(2 / (1 + (1 - a)^2)), alpha_b = (1 - a) alpha_t (the specification's
"Specular" section). So r_g = sqrt(alpha_b) and s = sqrt((alpha_t - alpha_b) / (1 - alpha_b)); back,
a = 1 - alpha_b / alpha_t and r = sqrt(alpha_t sqrt((1 + (1 - a)^2) / 2)). glTF caps alpha_t at 1.
"""

from __future__ import annotations

import numpy as np

from ..evaluate.microfacet import gltf_anisotropic_alpha, openpbr_alphas

def gltf_roughness(r, a):
    _, alpha_b = openpbr_alphas(r, a)
    return np.sqrt(alpha_b)


def gltf_anisotropy_strength(r, a):
    alpha_t, alpha_b = openpbr_alphas(r, a)
    with np.errstate(divide="ignore", invalid="ignore"):
        s2 = np.where(alpha_b < 1.0, (np.minimum(alpha_t, 1.0) - alpha_b) / np.where(alpha_b < 1.0, 1.0 - alpha_b, 1.0), 0.0)
    return np.sqrt(np.clip(s2, 0.0, 1.0))


def openpbr_roughness(r_g, s):
    alpha_b = r_g ** 2
    alpha_t = gltf_anisotropic_alpha(alpha_b, s)
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(alpha_t > 0, 1.0 - alpha_b / np.where(alpha_t > 0, alpha_t, 1.0), 0.0)
    return np.sqrt(alpha_t * np.sqrt((1.0 + (1.0 - a) ** 2) / 2.0))


def openpbr_anisotropy(r_g, s):
    alpha_b = r_g ** 2
    alpha_t = gltf_anisotropic_alpha(alpha_b, s)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(alpha_t > 0, 1.0 - alpha_b / np.where(alpha_t > 0, alpha_t, 1.0), 0.0)
