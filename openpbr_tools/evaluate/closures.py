"""The building blocks the models share, each returned as a :class:`~.layering.Scatter`: a lobe
value for (wi, wo) when ``wi`` is given, and its tabulated directional albedo for ``wo``.

These correspond to MaterialX's PBS nodes (``dielectric_bsdf``, ``generalized_schlick_bsdf``,
``conductor_bsdf``, ``oren_nayar_diffuse_bsdf``, ``sheen_bsdf``, ``translucent_bsdf``,
``subsurface_bsdf``; MaterialX Physically Based Shading Nodes v1.39) built from the lobes of
:mod:`.microfacet`, :mod:`.diffuse`, :mod:`.sheen` and the factors of :mod:`.fresnel`.
Colours have a trailing RGB axis; scalar parameters broadcast with the directions' shape.
"""

from __future__ import annotations

import numpy as np

from . import albedo as tab
from . import diffuse, fresnel, microfacet, sheen
from .layering import Scatter, as_colour, cosines, mix
from .thinfilm import thin_film_rgb

_EPS = 1e-7


def _mirror_z(w):
    return np.concatenate([w[..., :2], -w[..., 2:3]], axis=-1)


def _rgb(x):
    x = np.asarray(x, dtype=float)
    return x if x.shape[-1:] == (3,) else x[..., None] * np.ones(3)


def _thin_film_factor(cos_h, film, substrate_n, substrate_k=None):
    """Fresnel of a thin film on the substrate; ``film`` = (weight, thickness_nm, film_ior)."""
    _, thickness, ior = film
    return thin_film_rgb(cos_h, thickness, ior, substrate_n, substrate_k)


def dielectric_interface(
    wi, wo, inside, alpha_x, alpha_y, eta, thin_walled=False, thin_film=None, energy_compensation=True, transmission=True,
    reflection_shape=None,
):
    """Rough dielectric interface (GGX, exact Fresnel): ``(reflection, transmission)`` lobes.

    Closed surfaces refract (Walter et al. 2007, eq. 20-21); thin-walled ones transmit straight
    through (the reflection lobe mirrored below the surface, weighted by 1 - F). Energy
    compensation divides both lobes by the single-scattering R + T of the refracting interface,
    which makes a white, non-absorbing interface reflect plus transmit exactly 1 (Turquin 2019,
    eq. 16 with F = 1 applied to the whole BSDF); thin-walled transmission is rescaled to
    1 - E_R. ``eta`` is the IOR behind the surface over the IOR in
    front; inside a closed surface (``inside``) it is inverted. The reflection's throughput is
    1 - E_R (untinted, as MaterialX's ``dielectric_bsdf``); callers tint the response.
    ``thin_film`` = (weight, thickness_nm, film_ior) mixes in a thin-film-coated reflection.
    ``transmission=False`` skips the transmission lobe's value (its albedo is always returned).
    ``reflection_shape`` passes a precomputed ``microfacet.ggx_reflection(wi, wo, ...)``.
    """
    eta = np.asarray(eta, dtype=float)
    eta_eff = eta if thin_walled or not np.any(inside) else np.where(inside, 1.0 / eta, eta)
    a_avg = tab.average_alpha(alpha_x, alpha_y)
    mu_o = wo[..., 2]
    r_ss, t_ss = tab.dielectric_albedo(mu_o, a_avg, eta_eff)
    comp = 1.0 / np.maximum(r_ss + t_ss, 1e-3) if energy_compensation else np.ones_like(r_ss)
    e_r = r_ss * comp
    if thin_walled:
        # Straight-through transmission: the mirrored reflection lobe times (1 - F), rescaled so
        # that a clear slab transmits what it does not reflect.
        t_thin = np.maximum(tab.ggx_albedo(mu_o, a_avg) - r_ss, 0.0)
        t_scale = (1.0 - e_r) / np.maximum(t_thin, 1e-3) if energy_compensation else np.ones_like(r_ss)
        e_t = t_thin * t_scale
    else:
        t_scale = comp
        e_t = t_ss * comp
    refl_value = trans_value = None
    film_r = None
    if wi is not None:
        shape_r, cos_h = reflection_shape or microfacet.ggx_reflection(wi, wo, alpha_x, alpha_y)
        f = fresnel.fresnel_dielectric(cos_h, eta_eff)
        refl_value = as_colour(shape_r * f * comp)
        if transmission and thin_walled:
            shape_t, cos_ht = microfacet.ggx_reflection(_mirror_z(wi), wo, alpha_x, alpha_y)
            f_t = fresnel.fresnel_dielectric(cos_ht, eta_eff)
            trans_value = as_colour(shape_t * (1.0 - f_t) * t_scale)
        elif transmission:
            eta_o = np.where(inside, eta, 1.0) if np.any(inside) else np.ones_like(eta)
            eta_i = np.where(inside, 1.0, eta) if np.any(inside) else eta
            shape_t, cos_ht = microfacet.ggx_transmission(wi, wo, alpha_x, alpha_y, eta_i, eta_o)
            f_t = fresnel.fresnel_dielectric(cos_ht, eta_eff)
            trans_value = as_colour(shape_t * (1.0 - f_t) * comp)
    if thin_film is not None:
        # The coated reflection is a reflection lobe: Turquin's compensation with the film's
        # normal-incidence reflectance keeps its albedo below the film's Fresnel factor.
        e1 = tab.ggx_albedo(mu_o, a_avg)
        f_film_0 = _thin_film_factor(np.ones_like(np.asarray(thin_film[1], dtype=float)), thin_film, _rgb(eta_eff))
        comp_film = 1.0 + f_film_0 * as_colour((1.0 - e1) / np.maximum(e1, 1e-4)) if energy_compensation else 1.0
        if wi is not None:
            film_r = _thin_film_factor(cos_h, thin_film, _rgb(eta_eff)) * as_colour(shape_r) * comp_film
    reflection = Scatter.lobe(refl_value, as_colour(e_r) * np.ones(3), 0.0, as_colour(1.0 - e_r) * np.ones(3))
    transmission = Scatter.lobe(trans_value, np.zeros(3), as_colour(e_t) * np.ones(3), np.ones(3))
    if thin_film is not None:
        weight = as_colour(thin_film[0])
        e_film = _thin_film_factor(mu_o, thin_film, _rgb(eta_eff)) * as_colour(e1) * comp_film
        film = Scatter.lobe(film_r, e_film, 0.0, 1.0 - e_film)
        plain_throughput = reflection.throughput
        reflection = mix(reflection, film, weight)
        # The film changes how much the interface reflects; the transmission gets the rest.
        transmission = transmission.scaled(
            np.clip(reflection.throughput, 0.0, 1.0) / np.maximum(plain_throughput, 1e-3)
        )
    return reflection, transmission


def schlick_lobe(
    wi, wo, alpha_x, alpha_y, f0, f90=1.0, f82_tint=None, thin_film=None, film_substrate=None, energy_compensation=True,
    reflection_shape=None,
):
    """GGX reflection with (generalised) Schlick or F82-tint Fresnel, multiple-scattering
    compensated (Turquin 2019, eq. 16, with the lobe's normal-incidence reflectance).

    Throughput is 1 minus the RGB average of the albedo, as in MaterialX's
    ``generalized_schlick_bsdf``. ``film_substrate`` = (n, k) RGB of the substrate under a thin
    film (defaults to the IOR whose Fresnel reflectance at normal incidence is ``f0``).
    """
    f0 = np.maximum(np.asarray(f0, dtype=float), 0.0)
    f90 = np.asarray(f90, dtype=float)
    a_avg = tab.average_alpha(alpha_x, alpha_y)
    mu_o = wo[..., 2]
    comp = tab.ggx_compensation(mu_o, a_avg, f0) if energy_compensation else np.ones(3)
    e = tab.ggx_schlick_albedo(mu_o, a_avg, f0, f90, f82_tint) * comp
    value = None
    if film_substrate is None:
        film_substrate = (fresnel.f0_to_ior(f0), None)
    if wi is not None:
        shape, cos_h = reflection_shape or microfacet.ggx_reflection(wi, wo, alpha_x, alpha_y)
        c = as_colour(cos_h)
        f = fresnel.fresnel_schlick(c, f0, f90) if f82_tint is None else fresnel.f82_tint(c, f0, f82_tint, f90)
        value = as_colour(shape) * f * comp
    lobe = Scatter.lobe(value, e, 0.0, 1.0 - np.mean(e, axis=-1, keepdims=True))
    if thin_film is not None:
        film_value = None
        if wi is not None:
            film_value = _thin_film_factor(cos_h, thin_film, *film_substrate) * as_colour(shape) * comp
        e1 = as_colour(tab.ggx_albedo(mu_o, a_avg))
        e_film = _thin_film_factor(mu_o, thin_film, *film_substrate) * e1 * comp
        film = Scatter.lobe(film_value, e_film, 0.0, 1.0 - np.mean(e_film, axis=-1, keepdims=True))
        lobe = mix(lobe, film, as_colour(thin_film[0]))
    return lobe


def conductor_lobe(wi, wo, alpha_x, alpha_y, n, k, thin_film=None, reflection_shape=None):
    """GGX reflection with exact conductor Fresnel (complex IOR n + ik per channel), compensated
    as :func:`schlick_lobe`. Its albedo uses the F82-tint fit of the conductor curve (exact at
    0, 82 and 90 degrees), a documented approximation of the exact integral."""
    f0 = fresnel.fresnel_conductor(1.0, n, k)
    schlick_82 = f0 + (1.0 - f0) * (1.0 - fresnel.F82_COSINE) ** 5
    tint = fresnel.fresnel_conductor(fresnel.F82_COSINE, n, k) / np.maximum(schlick_82, _EPS)
    a_avg = tab.average_alpha(alpha_x, alpha_y)
    mu_o = wo[..., 2]
    comp = tab.ggx_compensation(mu_o, a_avg, f0)
    e = tab.ggx_schlick_albedo(mu_o, a_avg, f0, 1.0, tint) * comp
    value = None
    if wi is not None:
        shape, cos_h = reflection_shape or microfacet.ggx_reflection(wi, wo, alpha_x, alpha_y)
        value = as_colour(shape) * fresnel.fresnel_conductor(as_colour(cos_h), n, k) * comp
    lobe = Scatter.lobe(value, e, 0.0, 1.0 - np.mean(e, axis=-1, keepdims=True))
    if thin_film is not None:
        film_value = None
        if wi is not None:
            film_value = _thin_film_factor(cos_h, thin_film, n, k) * as_colour(shape) * comp
        e_film = _thin_film_factor(mu_o, thin_film, n, k) * as_colour(tab.ggx_albedo(mu_o, a_avg)) * comp
        film = Scatter.lobe(film_value, e_film, 0.0, 1.0 - np.mean(e_film, axis=-1, keepdims=True))
        lobe = mix(lobe, film, as_colour(thin_film[0]))
    return lobe


def eon_lobe(wi, wo, sigma, colour):
    """EON diffuse (energy-preserving Oren-Nayar), OpenPBR's glossy-diffuse base. With zero
    roughness it is exactly Lambertian, which is evaluated directly."""
    if not np.any(np.asarray(sigma)):
        return lambert_lobe(wi, wo, colour)
    cos_i, cos_o, cos_io = cosines(wi, wo)
    e = diffuse.eon_albedo(cos_o, sigma, colour)
    value = None if wi is None else diffuse.eon_diffuse(cos_i, cos_o, cos_io, sigma, colour)
    return Scatter.lobe(value, e, 0.0, np.zeros(3))


def oren_nayar_lobe(wi, wo, sigma, colour):
    """Qualitative Oren-Nayar diffuse (Standard Surface); albedo from its table."""
    cos_i, cos_o, cos_io = cosines(wi, wo)
    colour = np.asarray(colour, dtype=float)
    e = as_colour(tab.oren_nayar_albedo(cos_o, sigma)) * colour
    value = None if wi is None else as_colour(diffuse.oren_nayar(cos_i, cos_o, cos_io, sigma)) * colour
    return Scatter.lobe(value, e, 0.0, np.zeros(3))


def lambert_lobe(wi, wo, colour):
    """Lambertian diffuse reflection of ``colour``."""
    colour = np.asarray(colour, dtype=float)
    cos_o = wo[..., 2]
    e = as_colour(np.ones_like(cos_o)) * colour
    value = None if wi is None else as_colour(diffuse.lambert(wi[..., 2], cos_o)) * colour
    return Scatter.lobe(value, e, 0.0, np.zeros(3))


def translucent_lobe(wi, wo, colour):
    """Lambertian diffuse transmission of ``colour`` (thin-walled translucency)."""
    colour = np.asarray(colour, dtype=float)
    cos_o = wo[..., 2]
    e = as_colour(np.ones_like(cos_o)) * colour
    value = None if wi is None else as_colour(diffuse.translucent(wi[..., 2], cos_o)) * colour
    return Scatter.lobe(value, np.zeros(3), e, np.zeros(3))


def zeltner_lobe(wi, wo, roughness, colour, weight):
    """Zeltner LTC sheen layer (OpenPBR fuzz): response weight * colour * f, throughput
    1 - weight * R(mu_o)."""
    r = np.clip(np.asarray(roughness, dtype=float), sheen.ZELTNER_MIN_ROUGHNESS, 1.0)
    e = np.clip(sheen.zeltner_sheen_albedo(wo[..., 2], r), 0.0, 1.0)
    w = np.asarray(weight, dtype=float)
    colour = np.asarray(colour, dtype=float)
    value = None if wi is None else as_colour(w * sheen.zeltner_sheen(wi, wo, r)) * colour
    return Scatter.lobe(value, as_colour(w * e) * colour, 0.0, as_colour(1.0 - w * e) * np.ones(3))


def charlie_lobe(wi, wo, roughness, colour, weight, visibility="ashikhmin"):
    """Conty-Kulla sheen layer; throughput 1 - weight * E(mu_o) (albedo clamped to [0, 1] as
    MaterialX does, since the Ashikhmin visibility overshoots at grazing angles)."""
    e = np.clip(tab.charlie_albedo(wo[..., 2], roughness, visibility), 0.0, 1.0)
    w = np.asarray(weight, dtype=float)
    colour = np.asarray(colour, dtype=float)
    value = None if wi is None else as_colour(w * sheen.conty_kulla_sheen(wi, wo, roughness, visibility)) * colour
    return Scatter.lobe(value, as_colour(w * e) * colour, 0.0, as_colour(1.0 - w * e) * np.ones(3))
