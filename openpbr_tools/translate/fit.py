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
  :func:`edge_color_for_f82_tint`). OpenPBR's metal has the F82-tint Fresnel (Hoffman 2023):
  Schlick's curve minus a(F0, tint) mu (1 - mu)^6, scaled by ``specular_weight``. Its albedo is
  s (F0 A0 + A90 - a T82) with the evaluator's tables A0, A90, T82 (per mu and roughness), so a
  least-squares fit of glTF's Schlick metal (E = F0' A0 + A90) or UsdPreviewSurface's metal
  (F0 = F90 = colour, E = F0' (A0 + A90)) over mu is affine in the base colour, per channel, and
  is inverted exactly. Standard Surface's conductor (Gulbrandsen's artistic IOR) has a closed-form
  reflectance at 82 degrees: its edge colour is solved so that it equals OpenPBR's (regula falsi
  on a monotone function), which the evaluator's conductor albedo then matches exactly.
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
from ..evaluate import sheen as _sheen
from ..evaluate.coat import coat_relative_ior, coat_roughened
from ..evaluate.fresnel import F82_COSINE, artistic_ior, f0_to_ior, fresnel_conductor_real, ior_to_f0

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
    dielectric interface). Within the targets' range [0, 1]."""
    return np.clip(specular_weight * (scale + metalness * (1.0 - scale)), 0.0, 1.0)


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


# ----------------------------------------------------------------------------------- metals

_F82_SCHLICK = (1.0 - F82_COSINE) ** 5  # (1 - mu_bar)^5: Schlick's weight of F90 at 82 degrees
_F82_SHAPE = F82_COSINE * (1.0 - F82_COSINE) ** 6  # mu_bar (1 - mu_bar)^6


#: The metal fits weight the view cosine mu by mu^4. The share of a lit sphere's pixels at mu is
#: proportional to mu, but a key light sees every pixel near normal incidence on the microfacets
#: (its half vector makes a constant, small angle with the view), where F is F0: weighting by mu
#: alone trades too much F0 for the grazing dip. Mean lit-sphere CIEDE2000 over 17 metals (those of
#: tests/data/translation_set and tinted or weighted ones): glTF 0.84 (mu^1), 0.76 (mu^2), 0.73
#: (mu^4); UsdPreviewSurface 1.15, 1.01, 0.98; mu^8 is no better.
METAL_FIT_COSINE_POWER = 4


@lru_cache(maxsize=1)
def _metal_fit_tables():
    """Per roughness node r = sqrt(alpha): the weighted least-squares moments of the evaluator's
    GGX albedo tables that the affine metal fits need."""
    t = _albedo.tables()
    weight = _albedo.mu_nodes()[:, None] ** METAL_FIT_COSINE_POWER
    a0, a90, t82 = t.schlick_f0, t.schlick_f90, t.f82_term
    a1 = a0 + a90

    def moment(x, y):
        return np.sum(weight * x * y, axis=0)

    return {
        "r": _albedo.roughness_nodes(),
        # glTF: E = F0' A0 + A90 against E = s (F0 A0 + A90 - a T82)
        "schlick_tint": moment(a0, t82) / moment(a0, a0) / _F82_SHAPE,
        "schlick_edge": moment(a0, a90) / moment(a0, a0),
        # UsdPreviewSurface: E = F0' A1 against the same
        "constant_f0": moment(a1, a0) / moment(a1, a1),
        "constant_edge": moment(a1, a90) / moment(a1, a1),
        "constant_tint": moment(a1, t82) / moment(a1, a1) / _F82_SHAPE,
    }


def _metal_moment(name, alpha):
    table = _metal_fit_tables()
    r = np.sqrt(np.clip(np.asarray(alpha, dtype=np.float64), 0.0, 1.0))
    return np.interp(r, table["r"], table[name])


def _affine_metal(tint, weight, alpha, target: str):
    """(gain, offset) of the fitted reflectance gain * F0 + offset, per channel."""
    untinted = 1.0 - np.asarray(tint, dtype=np.float64)
    s = np.asarray(weight, dtype=np.float64)
    if target == "schlick":
        k = _metal_moment("schlick_tint", alpha)
        gain = s * (1.0 - k * untinted * (1.0 - _F82_SCHLICK))
        offset = -s * k * untinted * _F82_SCHLICK + (s - 1.0) * _metal_moment("schlick_edge", alpha)
    else:
        k = _metal_moment("constant_tint", alpha)
        gain = s * (_metal_moment("constant_f0", alpha) - k * untinted * (1.0 - _F82_SCHLICK))
        offset = s * (_metal_moment("constant_edge", alpha) - k * untinted * _F82_SCHLICK)
    return gain, offset


def _blend_metal(color, metalness, tint, weight, alpha, target):
    gain, offset = _affine_metal(tint, weight, alpha, target)
    return color + metalness * (gain * color + offset - color)


def _unblend_metal(fitted, metalness, tint, weight, alpha, target):
    gain, offset = _affine_metal(tint, weight, alpha, target)
    denominator = 1.0 + metalness * (gain - 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.abs(denominator) > _TINY,
                        (fitted - metalness * offset) / np.where(np.abs(denominator) > _TINY, denominator, 1.0), fitted)


def schlick_metal_f0(color, metalness, tint, weight, alpha):
    """glTF's metal base colour (Schlick, F90 = 1) whose albedo best matches OpenPBR's metal of
    F0 ``color``, F82 ``tint`` and ``specular_weight`` ``weight`` at GGX ``alpha`` (cosine-weighted
    least squares over the view angle); mixed by ``metalness`` with the dielectric's ``color``.
    The identity for a white tint and weight 1."""
    return np.clip(_blend_metal(color, metalness, tint, weight, alpha, "schlick"), 0.0, 1.0)


def openpbr_metal_from_schlick(fitted, metalness, tint, weight, alpha):
    """Inverse of :func:`schlick_metal_f0` (the OpenPBR base colour, clamped to [0, 1])."""
    return np.clip(_unblend_metal(fitted, metalness, tint, weight, alpha, "schlick"), 0.0, 1.0)


def constant_metal_reflectance(color, metalness, tint, weight, alpha):
    """UsdPreviewSurface's metallic ``diffuseColor`` (F0 = F90 = the colour) whose albedo best
    matches OpenPBR's F82-tint metal (as :func:`schlick_metal_f0`)."""
    return np.clip(_blend_metal(color, metalness, tint, weight, alpha, "constant"), 0.0, 1.0)


def openpbr_metal_from_constant(fitted, metalness, tint, weight, alpha):
    """Inverse of :func:`constant_metal_reflectance` (clamped to [0, 1])."""
    return np.clip(_unblend_metal(fitted, metalness, tint, weight, alpha, "constant"), 0.0, 1.0)


#: The conductor's exact Fresnel in real arithmetic (keeps baking memory low).
conductor_reflectance = fresnel_conductor_real


def f82_tint_of_edge_color(reflectivity, edge_color):
    """The F82 tint of Standard Surface's artistic-IOR conductor: its reflectance at
    cos = 1/7 over Schlick's with the same F0 (the evaluator's albedo of that conductor)."""
    n, k = artistic_ior(reflectivity, edge_color)
    f0 = np.clip(reflectivity, 0.0, 0.99)
    return conductor_reflectance(F82_COSINE, n, k) / np.maximum(f0 + (1.0 - f0) * _F82_SCHLICK, _TINY)


def _schlick_82(f0):
    return f0 + (1.0 - f0) * _F82_SCHLICK


def ss_metal_tint(specular_color, metalness, reflectivity, specular, specular_weight=1.0):
    """OpenPBR's ``specular_color`` from Standard Surface's, mixed by metalness with the dielectric
    tint (a copy). On a metal it is the F82 tint that gives OpenPBR's metal, whose reflectance is
    ``specular_weight`` times the F82-tint curve of F0 = reflectivity / specular_weight, the
    conductor's reflectance at 82 degrees (Standard Surface: artistic IOR of ``reflectivity`` =
    base * base_color and edge colour ``specular * specular_color``)."""
    weight = np.maximum(specular_weight, _TINY)
    conductor = f82_tint_of_edge_color(reflectivity, specular * specular_color)
    conductor = conductor * _schlick_82(np.clip(reflectivity, 0.0, 0.99))
    tint = conductor / (weight * _schlick_82(np.clip(reflectivity / weight, 0.0, 1.0)))
    return specular_color + metalness * (tint - specular_color)


def edge_color_for_f82_tint(tint, metalness, reflectivity, specular, specular_weight=1.0, iterations: int = 40):
    """Inverse of :func:`ss_metal_tint`: Standard Surface's ``specular_color`` in [0, 1] whose
    conductor reaches OpenPBR's F82 ``tint``. The function increases with the edge colour: the
    root is bracketed in [0, 1] and found by the Illinois variant of regula falsi (Dahlquist &
    Bjoerck, "Numerical Methods", 1974, section 6.2.3), superlinear and never leaving the bracket.
    A tint outside what the conductor reaches gets the nearest end of the range. Only metallic
    texels are solved (elsewhere the tint is copied)."""
    tint, metalness, reflectivity, specular, specular_weight = np.broadcast_arrays(
        *(np.asarray(x, dtype=np.float64) for x in (tint, metalness, reflectivity, specular, specular_weight)))
    result = np.array(tint, dtype=np.float64, copy=True)
    solve = metalness > 0.0
    if not np.any(solve):
        return result
    c, m, r, s, w = tint[solve], metalness[solve], reflectivity[solve], specular[solve], specular_weight[solve]

    def residual(x):
        return ss_metal_tint(x, m, r, s, w) - c

    low, high = np.zeros(c.shape), np.ones(c.shape)
    f_low, f_high = residual(low), residual(high)
    x = np.where(f_low >= 0.0, 0.0, 1.0)
    active = (f_low < 0.0) & (f_high > 0.0)
    for _ in range(iterations):
        if not np.any(active):
            break
        step = f_high - f_low
        x_new = np.where(step != 0.0, high - f_high * (high - low) / np.where(step != 0.0, step, 1.0), 0.5 * (low + high))
        f_new = residual(x_new)
        x = np.where(active, x_new, x)
        crossed = f_new * f_high < 0.0
        # Illinois: the previous iterate becomes the other end when the sign changes, else the
        # stale end's value is halved so that it too moves.
        low, f_low = np.where(crossed, high, low), np.where(crossed, f_high, 0.5 * f_low)
        high, f_high = x_new, f_new
        active = active & (np.abs(f_new) > 1e-14) & (np.abs(high - low) > 1e-15)
    result[solve] = x
    return result


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
    A roughness below what the coat alone gives maps to 0."""
    roughened = np.asarray(roughened, dtype=np.float64)
    low = np.zeros(np.broadcast(roughened, coat_weight, coat_roughness).shape)
    high = np.ones_like(low)
    for _ in range(iterations):
        middle = 0.5 * (low + high)
        above = coat_roughened(middle, coat_weight, coat_roughness) > roughened
        high = np.where(above, middle, high)
        low = np.where(above, low, middle)
    return np.where(coat_weight > 0, 0.5 * (low + high), roughened + 0.0 * low)
