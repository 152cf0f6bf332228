"""Metal fits: OpenPBR's F82-tint metal carried to models without an edge tint (re-exported by
:mod:`openpbr_tools.translate.fit`, which holds the other fits and describes the conventions they
share: vectorised, fitted against this package's lobe evaluator, exactly invertible).

**Metal edge tint and weight** (:func:`schlick_metal_f0`, :func:`constant_metal_reflectance`,
:func:`edge_color_for_f82_tint`). OpenPBR's metal has the F82-tint Fresnel (Hoffman 2023):
Schlick's curve minus a(F0, tint) mu (1 - mu)^6, scaled by ``specular_weight``. Its albedo is
s (F0 A0 + A90 - a T82) with the evaluator's tables A0, A90, T82 (per mu and roughness), so a
least-squares fit of glTF's Schlick metal (E = F0' A0 + A90) or UsdPreviewSurface's metal
(F0 = F90 = colour, E = F0' (A0 + A90)) over mu is affine in the base colour, per channel, and
is inverted exactly. Standard Surface's conductor (Gulbrandsen's artistic IOR) has a closed-form
reflectance at 82 degrees: its edge colour is solved so that it equals OpenPBR's (regula falsi
on a monotone function), which the evaluator's conductor albedo then matches exactly.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..evaluate import albedo as _albedo
from ..evaluate.fresnel import F82_COSINE, artistic_ior, fresnel_conductor_real

#: Where a ratio's denominator is below this, the source value is kept instead (as in :mod:`.fit`).
_TINY = 1e-9

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


def fitted_metal(color, tint, weight, alpha, target: str = "schlick"):
    """The metal alone, before any clip: glTF's Schlick F0 (``target`` "schlick") or the preview's
    constant reflectance ("constant") fitted to OpenPBR's metal of F0 ``color`` (affine in the colour),
    for callers that mix the metal with a dielectric of their own (subsurface, transmission)."""
    gain, offset = _affine_metal(tint, weight, alpha, target)
    return gain * color + offset


def openpbr_metal_from_schlick(fitted, metalness, tint, weight, alpha):
    """Inverse of :func:`schlick_metal_f0` (the OpenPBR base colour, clamped to [0, 1])."""
    return np.clip(_unblend_metal(fitted, metalness, tint, weight, alpha, "schlick"), 0.0, 1.0)


def metal_from_schlick_clips(fitted, metalness, tint, weight, alpha) -> bool:
    """Whether :func:`openpbr_metal_from_schlick` had to clip (no OpenPBR base colour in [0, 1]
    gives glTF's metal: the tint or weight darkens it more than a base colour of 1 makes up for)."""
    return bool(np.any(metal_from_schlick_out_of_range(fitted, metalness, tint, weight, alpha)))


def metal_from_schlick_out_of_range(fitted, metalness, tint, weight, alpha) -> np.ndarray:
    """:func:`metal_from_schlick_clips` texel by texel (any channel out of [0, 1], or a metal no base colour reaches:
    a weight of 0 under a colour that is not black)."""
    gain, offset = _affine_metal(tint, weight, alpha, "schlick")
    with np.errstate(all="ignore"):
        raw = _unblend_metal(fitted, metalness, tint, weight, alpha, "schlick")
        unreachable = (np.abs(1.0 + metalness * (gain - 1.0)) <= _TINY) & (fitted - metalness * offset > 1e-6)
    return np.any((raw < -1e-6) | (raw > 1.0 + 1e-6) | unreachable, axis=-1)


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


#: The metalness values :func:`split_metal` weighs (steps of 1/200).
_SPLIT_GRID = np.linspace(0.0, 1.0, 201)


def _split_moments(alpha, target: str):
    """(P·P, P·Q, Q·Q, 1·1) of the metal fits' weighted moments at ``alpha``: the target's metal albedo is
    b P + Q per view cosine (glTF's Schlick: P = A0, Q = A90; the preview's constant metal: P = A0 + A90,
    Q = 0), and 1·1 weighs a diffuse albedo (flat over the view cosine) on the same scale."""
    t = _albedo.tables()
    weight = _albedo.mu_nodes()[:, None] ** METAL_FIT_COSINE_POWER
    p = t.schlick_f0 if target == "schlick" else t.schlick_f0 + t.schlick_f90
    q = t.schlick_f90 if target == "schlick" else np.zeros_like(p)
    r = np.sqrt(np.clip(float(alpha), 0.0, 1.0))
    nodes = _albedo.roughness_nodes()
    return tuple(float(np.interp(r, nodes, np.sum(weight * x * y, axis=0)))
                 for x, y in ((p, p), (p, q), (q, q), (np.ones_like(p), np.ones_like(p))))


def split_metal(dielectric, metal, metalness, alpha, target: str = "schlick", clip: bool = True):
    """(metalness', base colour') of a target whose metal and dielectric share one base colour (glTF; the
    preview keeps the mix: usd_preview.preview_diffuse_color says why), for a source whose dielectric diffuses ``dielectric`` and whose metal is fitted to ``metal``
    (the target's F0 that best matches it, :func:`fitted_metal`), mixed by ``metalness``.

    Mixing the colours by the source's metalness (``dielectric + metalness (metal - dielectric)``) is exact
    only where the fitted metal equals the dielectric's colour. A metal OpenPBR dims by ``specular_weight``
    (or tints at the edge) is darker than the colour it shares with the diffuse, and the target's metal
    still reaches 1 at grazing: a metalness of 0.73 with ``specular_weight`` 0 gave a black diffuse under a
    bright metal rim where OpenPBR shows a dim diffuse and no metal. Here metalness' and the colour are
    chosen together to minimise the weighted squared error of both albedos (the diffuse ``(1 - x) b``
    against ``(1 - m) D``, and the metal ``x (b P + Q)`` against ``m (F P + Q)`` over the view cosine, the
    metal fits' weights): for each x on a grid of steps of 1/200 the best b per channel is a closed form
    (held to [0, 1] where ``clip``), and the x of least error is kept. Where the fitted metal equals the
    dielectric's colour this is the mix (x = m, b = D). Values only: arrays (per texel) keep the mix."""
    dielectric = np.asarray(dielectric, dtype=np.float64)
    metal = np.asarray(metal, dtype=np.float64)
    m = np.asarray(metalness, dtype=np.float64)
    mixed = dielectric + m * (metal - dielectric)
    if dielectric.ndim > 1 or metal.ndim > 1 or m.ndim > 0 or np.ndim(alpha) > 0 or not 0.0 < float(m) < 1.0:
        return m, (np.clip(mixed, 0.0, 1.0) if clip else mixed)
    m = float(m)
    pp, pq, qq, dd = _split_moments(alpha, target)
    x = _SPLIT_GRID[:, None]
    d = x - m
    with np.errstate(divide="ignore", invalid="ignore"):
        b = (dd * (1.0 - x) * (1.0 - m) * dielectric + pp * x * m * metal - pq * x * d) / \
            (dd * (1.0 - x) ** 2 + pp * x ** 2)
    if clip:
        b = np.clip(b, 0.0, 1.0)
    error = dd * ((1.0 - x) * b - (1.0 - m) * dielectric) ** 2 + pp * (x * b - m * metal) ** 2 + \
        2.0 * pq * (x * b - m * metal) * d + qq * d ** 2
    total = error.sum(axis=1)
    best = int(np.argmin(total))
    # the mix unless the split is measurably better (keeps materials the mix carries exactly unchanged)
    mixed_x = int(round(m * (len(_SPLIT_GRID) - 1)))
    mixed_b = np.clip(mixed, 0.0, 1.0) if clip else mixed
    mixed_error = float(np.sum(dd * ((1.0 - m) * mixed_b - (1.0 - m) * dielectric) ** 2 +
                               pp * (m * mixed_b - m * metal) ** 2))
    if not total[best] < mixed_error - 1e-9 or best == mixed_x and np.allclose(b[best], mixed_b):
        return np.float64(m), mixed_b
    return np.float64(_SPLIT_GRID[best]), b[best]
