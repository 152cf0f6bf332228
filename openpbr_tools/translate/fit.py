"""Target parameters fitted where no closed form carries an OpenPBR feature across.

Every function here is vectorised: scalars arrive as arrays of shape ``()`` or ``(H, W, 1)``,
colours as ``(3,)`` or ``(H, W, 3)``, and results broadcast the same way, so the translation
formulas that call them serve constants and textures baked texel by texel alike. Fits are made
against this package's lobe evaluator (:mod:`openpbr_tools.evaluate`): its tabulated directional
albedos E(mu) of the GGX and sheen lobes, weighted over the view cosine mu. Each fit is affine or
monotone in the fitted parameter, so it has an exact inverse (where the target's range does not
clamp it), and it reduces to the identity where the target can represent the source.

* **Base under a coat** (:func:`dielectric_specular_scale`, :func:`preview_ior`). OpenPBR
  evaluates the base's dielectric Fresnel with its IOR relative to the coat's,
  eta = mix(n_b, n_b / n_c (inverted below 1), coat_weight) (OpenPBR 1.1, "Coat"; MaterialX's
  ``open_pbr_surface`` graph). Standard Surface and glTF keep the base's own IOR n_b (it also
  bends the refracted light, which a parallel coat does not change; and an IOR solved from eta
  would not invert: two base IORs, above and below the coat's, give the same eta) and scale the
  reflection by their specular weight so that F0 matches, F0(eta) / F0(n_b).
  UsdPreviewSurface has one ``ior`` for the base and its clear coat: it is solved so that the
  normal-incidence reflectance of coat plus base matches OpenPBR's.
* **Metal edge tint and weight** (:func:`schlick_metal_f0`, :func:`constant_metal_reflectance`,
  :func:`edge_color_for_f82_tint`): fitted in :mod:`.fit_metal` and re-exported here, so that the
  translation modules find every fit in this module.
* **Fuzz as sheen** (:func:`sheen_fit`). OpenPBR's fuzz (Zeltner's LTC sheen) and the
  Conty-Kulla "Charlie" sheen of glTF and Standard Surface have differently shaped albedos; for
  every fuzz roughness the Charlie roughness and the scale of its albedo that best match
  R_zeltner(mu), weighted by mu, are tabulated (a strictly increasing roughness map, so it
  inverts).

Measured effects (mean CIEDE2000 on the lit sphere) are in the translation modules' docstrings.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..evaluate import albedo as _albedo
from ..evaluate import diffuse as _diffuse
from ..evaluate import sheen as _sheen
from ..evaluate.coat import coat_relative_ior, coat_roughened
from ..evaluate.fresnel import f0_to_ior, ior_to_f0
from ..evaluate.volume import with_channel_axis
from .fit_metal import (  # re-exported: the translation modules call every fit as fit.NAME
    METAL_FIT_COSINE_POWER,
    conductor_reflectance,
    constant_metal_reflectance,
    edge_color_for_f82_tint,
    f82_tint_of_edge_color,
    fitted_metal,
    metal_from_schlick_clips,
    metal_from_schlick_out_of_range,
    openpbr_metal_from_constant,
    openpbr_metal_from_schlick,
    schlick_metal_f0,
    split_metal,
    ss_metal_tint,
)

#: Where a ratio's denominator is below this, the source value is kept instead.
_TINY = 1e-9
#: IORs are floored here: the schemas allow 0, which would divide by zero.
IOR_FLOOR = 1e-6


def positive_ior(ior):
    """An IOR floored at :data:`IOR_FLOOR` (an IOR of 0 is allowed by the tables, and meaningless)."""
    return np.maximum(np.asarray(ior, dtype=np.float64), IOR_FLOOR)


def ior_from_f0(f0):
    """The IOR >= 1 with normal-incidence reflectance ``f0`` (clamped below 1;
    :func:`~openpbr_tools.evaluate.fresnel.f0_to_ior`)."""
    return f0_to_ior(f0, max_f0=0.999999)


# ------------------------------------------------------------------------------------ coat


def base_ior_under_coat(specular_ior, coat_ior, coat_weight):
    """The IOR OpenPBR gives the base's specular interface under a coat: the ratio n_b / n_c,
    inverted when below 1 (the specification's fix against total internal reflection), mixed
    with n_b by the coat weight (:func:`~openpbr_tools.evaluate.coat.coat_relative_ior`, IORs
    floored at :data:`IOR_FLOOR`)."""
    return coat_relative_ior(positive_ior(specular_ior), positive_ior(coat_ior), coat_weight)


def coat_f0_ratio(specular_ior, coat_ior, coat_weight):
    """F0 of the base under the coat over F0 of the bare base, F0(eta) / F0(n_b) (1 where the
    bare base reflects nothing)."""
    bare = ior_to_f0(specular_ior)
    under = ior_to_f0(base_ior_under_coat(specular_ior, coat_ior, coat_weight))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(bare > _TINY, under / np.where(bare > _TINY, bare, 1.0), 1.0)


def dielectric_specular_scale(specular_ior, coat_ior, coat_weight, film_weight, darkening=1.0):
    """What a weight on the bare base's reflection (Standard Surface ``specular``, glTF
    ``KHR_materials_specular``) must be multiplied by to stand for OpenPBR's base under its coat:

    * F0(eta) / F0(n_b) (:func:`coat_f0_ratio`) makes F0 equal;
    * a thin film of weight f replaces that reflection with its own, which the targets compute on
      the bare base's IOR: the ratio applies to the remaining 1 - f. (A film on OpenPBR's
      index-matched base under a coat, rendered by glTF's ``1 - max(F)`` diffuse weight, gives
      fringes far stronger than OpenPBR's: on the car paints of the test set, keeping the bare F0
      under the film is closer);
    * ``darkening``: the largest channel of OpenPBR's view-independent darkening of the base under
      the coat, which dims the base's reflection too (the targets fold it into the base colour).
    """
    rho = coat_f0_ratio(specular_ior, coat_ior, coat_weight)
    return darkening * (rho + (1.0 - rho) * film_weight)


def specular_weight_under_coat(specular_weight, scale, metalness=0.0):
    """The target's specular weight: OpenPBR's times :func:`dielectric_specular_scale` on
    dielectrics; on metals the weight is kept (a metal's reflection is not under the base's
    dielectric interface). Not clipped to the targets' range [0, 1]: the translation clamps it there
    and reports the loss (a silent clip here hid it)."""
    return np.maximum(specular_weight * (scale + metalness * (1.0 - scale)), 0.0)


def specular_weight_from_coated(weight, scale, metalness=0.0):
    """Inverse of :func:`specular_weight_under_coat`. Where the scale is 0 (OpenPBR's base cannot
    reflect under the coat: its IOR equals the coat's), the weight is kept (that reflection is
    lost)."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # inf inputs from hostile files
        denominator = scale + metalness * (1.0 - scale)
        return np.where(denominator > _TINY, weight / np.where(denominator > _TINY, denominator, 1.0), weight)


def coated_reflectance(specular_weight, specular_ior, coat_ior, coat_weight):
    """Normal-incidence reflectance of OpenPBR's coat over its dielectric base, with the coat
    layered by albedo scaling: w F0(n_c) + (1 - w F0(n_c)) min(1, s_w F0(eta))."""
    f0_coat = ior_to_f0(coat_ior)
    f0_base = np.clip(specular_weight * ior_to_f0(base_ior_under_coat(specular_ior, coat_ior, coat_weight)), 0.0, 1.0)
    coat = coat_weight * f0_coat
    return coat + (1.0 - coat) * f0_base


def preview_ior(specular_weight, specular_ior, coat_ior, coat_weight):
    """UsdPreviewSurface's ``ior``, which sets the F0 of both its base and its clear coat, solved
    so that w F + (1 - w F) F equals OpenPBR's :func:`coated_reflectance` (the smaller root of
    the quadratic, in a form stable at w = 0, where it is s_w F0(n_b))."""
    reflectance = coated_reflectance(specular_weight, specular_ior, coat_ior, coat_weight)
    w = np.asarray(coat_weight, dtype=np.float64)
    discriminant = np.maximum((1.0 + w) ** 2 - 4.0 * w * reflectance, 0.0)
    f0 = 2.0 * reflectance / ((1.0 + w) + np.sqrt(discriminant))
    return ior_from_f0(f0)


def specular_ior_for_relative_ior(eta, coat_ior, coat_weight):
    """The base IOR n_b whose :func:`base_ior_under_coat` is ``eta``: the root n_b >= n_c when
    eta >= mix(n_c, 1, w) (always, under a full coat), else the root below n_c, else (eta below
    what any base reaches under that coat) the base closest to it."""
    eta = np.asarray(eta, dtype=np.float64)
    n_c = positive_ior(coat_ior)
    w = np.asarray(coat_weight, dtype=np.float64)
    above = eta / np.maximum((1.0 - w) + w / n_c, _TINY)
    # Below the coat's IOR: (1 - w) n^2 - eta n + w n_c = 0; the larger root is the one nearest n_c.
    a = np.maximum(1.0 - w, _TINY)
    discriminant = eta * eta - 4.0 * a * w * n_c
    root = (eta + np.sqrt(np.maximum(discriminant, 0.0))) / (2.0 * a)
    lowest = np.sqrt(w * n_c / a)  # where (1 - w) n + w n_c / n is smallest
    below = np.clip(np.where(discriminant >= 0.0, root, lowest), 1.0, n_c)
    return np.where(w > 0.0, np.where(eta >= n_c + (1.0 - n_c) * w, above, below), eta)


# ------------------------------------------------------------------------------------- fuzz

#: Fuzz roughness nodes of the sheen fit.
_FUZZ_NODES = 41


def _charlie_albedo(mu, roughness):
    """[mu, roughness] table of the evaluator's Charlie albedo (Ashikhmin visibility), clamped to
    [0, 1] as the evaluator's sheen layer clamps it."""
    r = np.maximum(roughness[None, :], _sheen.CHARLIE_MIN_ROUGHNESS)
    return np.clip(_albedo.charlie_albedo(mu[:, None], r), 0.0, 1.0)


@lru_cache(maxsize=1)
def sheen_fit():
    """``(fuzz_roughness, charlie_roughness, scale)`` nodes: for each fuzz roughness r, the
    Conty-Kulla roughness r_c (Ashikhmin visibility, the evaluator's table) and scale k minimising
    sum_mu mu (k E_charlie(mu, r_c) - R_zeltner(mu, r))^2. r_c is made strictly increasing (it
    saturates at 1 for rough fuzz and at 0 for smooth fuzz, whose albedo is nearly zero: the ends
    are stretched linearly), then k is refitted for it. Zeltner's albedo exceeds Charlie's at any
    r_c for rough fuzz (k > 1)."""
    mu = np.linspace(0.02, 1.0, 50)
    weight = mu[:, None]
    fuzz = np.linspace(0.0, 1.0, _FUZZ_NODES)
    candidates = np.linspace(0.0, 1.0, 2001)
    charlie = _charlie_albedo(mu, candidates)
    zeltner = np.clip(_sheen.zeltner_sheen_albedo(mu[:, None], np.maximum(fuzz[None, :], _sheen.ZELTNER_MIN_ROUGHNESS)),
                      0.0, 1.0)

    def scale(e, z):
        return np.sum(weight * e * z, axis=0) / np.maximum(np.sum(weight * e * e, axis=0), _TINY)

    best = np.empty(_FUZZ_NODES)
    for i in range(_FUZZ_NODES):
        k = scale(charlie, zeltner[:, i:i + 1])
        error = np.sum(weight * (k * charlie - zeltner[:, i:i + 1]) ** 2, axis=0)
        best[i] = candidates[np.argmin(error)]
    # Strictly increasing: keep the fitted span where the fit moves, stretch linearly outside it.
    moving = np.flatnonzero((best > 0.0) & (best < 1.0))
    first, last = moving[0], moving[-1]
    charlie_r = best.copy()
    charlie_r[:first] = best[first] * fuzz[:first] / fuzz[first]
    charlie_r[last + 1:] = best[last] + (1.0 - best[last]) * (fuzz[last + 1:] - fuzz[last]) / (1.0 - fuzz[last])
    charlie_r = np.maximum.accumulate(charlie_r) + np.arange(_FUZZ_NODES) * 1e-9  # strictly increasing
    charlie_r = charlie_r / charlie_r[-1]  # ... from 0 to exactly 1
    fitted = _charlie_albedo(mu, charlie_r)
    k = np.maximum(scale(fitted, zeltner), 1e-3)
    return fuzz, charlie_r, k


def charlie_roughness_for_fuzz(fuzz_roughness):
    """Conty-Kulla roughness r_c (Standard Surface ``sheen_roughness``; glTF's is sqrt(r_c))."""
    nodes, charlie, _ = sheen_fit()
    return np.interp(np.clip(fuzz_roughness, 0.0, 1.0), nodes, charlie)


def fuzz_roughness_for_charlie(charlie_roughness):
    """Inverse of :func:`charlie_roughness_for_fuzz`."""
    nodes, charlie, _ = sheen_fit()
    return np.interp(np.clip(charlie_roughness, 0.0, 1.0), charlie, nodes)


def fuzz_albedo_scale(fuzz_roughness):
    """k: Zeltner's fuzz albedo at this roughness over the fitted Charlie sheen's."""
    nodes, _, k = sheen_fit()
    return np.interp(np.clip(fuzz_roughness, 0.0, 1.0), nodes, k)


# -- the coat's roughening of the base (evaluate.coat.coat_roughened) -----------------------------
def coat_unroughened(roughened, coat_weight, coat_roughness, iterations: int = 48):
    """Inverse of :func:`~openpbr_tools.evaluate.coat.coat_roughened` in the base roughness (increasing in it; bisection, vectorised).
    A roughness below what the coat alone gives (:func:`smoother_than_the_coat_allows`) has no inverse: it
    becomes 0, the base whose roughened lobe comes closest (the caller reports the approximation), unless
    every base renders alike under that coat (a full coat rough enough that any base is roughened to 1: the
    roughness is kept, for whoever edits the coat later). Keeping it where it renders rougher than 0 roughens
    it further: MaterialX's tiled brass (Standard Surface) 3.7 -> 2.3 mean CIEDE2000 on the evaluator; 80
    random glTF clearcoat materials so smooth, median 2.06 -> 1.45, 27 closer by more than 0.3, none further."""
    roughened = np.asarray(roughened, dtype=np.float64)
    low = np.zeros(np.broadcast(roughened, coat_weight, coat_roughness).shape)
    high = np.ones_like(low)
    for _ in range(iterations):
        middle = 0.5 * (low + high)
        above = coat_roughened(middle, coat_weight, coat_roughness) > roughened
        high = np.where(above, middle, high)
        low = np.where(above, low, middle)
    solved = 0.5 * (low + high)
    smoothest = smoother_than_the_coat_allows(roughened, coat_weight, coat_roughness)
    alike = coat_roughened(roughened, coat_weight, coat_roughness) <= coat_roughened(0.0, coat_weight, coat_roughness) + 1e-9
    return np.where(np.asarray(coat_weight) > 0, np.where(smoothest, np.where(alike, roughened, 0.0), solved),
                    roughened + 0.0 * low)


def smoother_than_the_coat_allows(roughened, coat_weight, coat_roughness):
    """Whether a base roughness is below the least OpenPBR's coat leaves (that of a mirror base
    under it): no OpenPBR base roughness reproduces it."""
    return (np.asarray(coat_weight) > 0) & (np.asarray(roughened) < coat_roughened(0.0, coat_weight, coat_roughness) - 1e-9)


# Rough diffuse: Standard Surface's qualitative Oren-Nayar (QON) loses the light its single-scattering
# model does not return; OpenPBR's energy-preserving Oren-Nayar (EON) adds it back as a multiple-
# scattering lobe. At the same roughness EON is brighter (rough concrete, roughness 1: 5.8 mean
# CIEDE2000). The base colour is scaled so that the two hemispherical (cosine-weighted) albedos match:
# EON's is rho A / (1 - rho (1 - A)) in closed form (A = FON's average albedo, EON eq. 9; the
# multiple-scattering colour rho_ms = rho^2 A / (1 - rho (1 - A)), eq. 12, summed with rho A), QON's
# is integrated from its albedo table. The angular shapes still differ (QON is flatter at grazing).


def qon_average_albedo(sigma):
    """Cosine-weighted hemispherical average of the qualitative Oren-Nayar albedo per unit colour
    (32-point Gauss-Legendre over the evaluator's albedo table), the shape of ``sigma``."""
    nodes, weights = np.polynomial.legendre.leggauss(32)
    mu, weights = 0.5 * (nodes + 1.0), 0.5 * weights
    sigma = np.clip(np.asarray(sigma, dtype=float), 0.0, 1.0)
    values = _albedo.oren_nayar_albedo(mu, sigma[..., None] * np.ones_like(mu))
    return np.sum(2.0 * mu * values * weights, axis=-1)


def eon_average_albedo(rho, sigma):
    """EON's cosine-weighted hemispherical albedo for colour ``rho`` (last axis RGB) and roughness."""
    a = with_channel_axis(_diffuse.fujii_oren_nayar_average_albedo(np.clip(sigma, 0.0, 1.0)))
    rho = np.asarray(rho, dtype=float)
    return rho * a / (1.0 - rho * (1.0 - a))


def eon_colour_for_qon(rho, sigma):
    """The OpenPBR (EON) base colour whose hemispherical albedo is Standard Surface's (QON) for
    ``rho`` at roughness ``sigma``: rho' A / (1 - rho' (1 - A)) = t = A_QON rho, so
    rho' = t / (A + t (1 - A))."""
    a = with_channel_axis(_diffuse.fujii_oren_nayar_average_albedo(np.clip(sigma, 0.0, 1.0)))
    target = with_channel_axis(qon_average_albedo(sigma)) * np.asarray(rho, dtype=float)
    return target / (a + target * (1.0 - a))


def qon_colour_for_eon(rho, sigma):
    """The Standard Surface (QON) base colour whose hemispherical albedo is OpenPBR's (EON) for
    ``rho`` at roughness ``sigma``; the inverse of :func:`eon_colour_for_qon` (may exceed 1)."""
    return eon_average_albedo(rho, sigma) / with_channel_axis(qon_average_albedo(sigma))


def eon_colour_for_qon_dielectric(rho, sigma, metalness):
    """:func:`eon_colour_for_qon` where the base is a dielectric (metalness 0); a base with any metal
    keeps its colour (a metal's colour is its F0, which the diffuse model does not touch, and one
    colour cannot serve a diffuse and a metal that need different corrections; the metal floor of
    :func:`~.standard_surface.openpbr_specular_weight` needs the colour as it is)."""
    rho = np.asarray(rho, dtype=float)
    return np.where(with_channel_axis(metalness) > 0.0, rho, eon_colour_for_qon(rho, sigma))


def qon_colour_for_eon_dielectric(rho, sigma, metalness):
    """The inverse of :func:`eon_colour_for_qon_dielectric`."""
    rho = np.asarray(rho, dtype=float)
    return np.where(with_channel_axis(metalness) > 0.0, rho, qon_colour_for_eon(rho, sigma))
