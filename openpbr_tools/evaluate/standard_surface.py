"""Autodesk Standard Surface 1.0.1 as a mixture of lobes.

Follows MaterialX's reference graph ``NG_standard_surface_surfaceshader_100``
(``libraries/bxdf/standard_surface.mtlx``, MaterialX 1.39.5), which implements Georgiev et al.,
"Autodesk Standard Surface" (2019):

    coat (dielectric reflection, coat_IOR, weight coat) layered over
    coat_color-attenuated mix(specular layer, metal (artistic-IOR conductor), metalness)
    specular layer = specular reflection (weight specular, tint specular_color, thin film)
                     layered over mix(sheen layer, transmission, transmission)
    sheen layer = Conty-Kulla sheen (weight sheen) over mix(Oren-Nayar diffuse, subsurface, subsurface)

coat_affect_color raises the diffuse and subsurface colours to the power 1 + coat *
coat_affect_color; coat_affect_roughness pulls the specular roughness towards 1; anisotropy uses
MaterialX's ``roughness_anisotropy`` and the rotation turns the tangent about the normal.
Approximations as for OpenPBR (:mod:`.openpbr`): refraction energy-compensated with the
reflection, subsurface as Lambertian reflection of subsurface_color, thin-walled subsurface as
translucency, transmission_depth and transmission_scatter as OpenPBR's absorption coefficient
(:mod:`.volume`; the two models share Arnold's definition) for previews, no dispersion, no volumetric
scattering. Opacity (a colour) becomes a coverage through its Rec.709 luminance.
"""

from __future__ import annotations

import numpy as np

from .. import colorspaces
from . import closures, microfacet
from .coat import coat_absorption
from .fresnel import artistic_ior, ior_to_f0
from .layering import BSDFModel, Scatter, add, any_nonzero, as_colour, layer, mix, rotate_about_normal
from .volume import absorption_coefficient

ALPHA_FLOOR = 1e-4


def roughness_anisotropy(roughness, anisotropy):
    """GGX alphas from roughness and anisotropy as MaterialX's ``roughness_anisotropy`` node:
    alpha = r^2; with a > 0, aspect = sqrt(1 - min(a, 0.98)), alpha_t = min(alpha / aspect, 1),
    alpha_b = alpha * aspect (Standard Surface spec, section "Specular", after Kulla & Conty 2017)."""
    r = np.asarray(roughness, dtype=float)
    a = np.clip(np.asarray(anisotropy, dtype=float), 0.0, 0.98)
    alpha = np.clip(r * r, ALPHA_FLOOR, 1.0)
    aspect = np.sqrt(1.0 - a)
    return np.clip(alpha / aspect, ALPHA_FLOOR, 1.0), np.clip(alpha * aspect, ALPHA_FLOOR, 1.0)


class StandardSurface(BSDFModel):
    model = "standard_surface"

    def __init__(self, params: dict):
        super().__init__(params)
        f = {k: np.asarray(v, dtype=float) for k, v in params.items() if not isinstance(v, (bool, np.bool_))}
        self.f = f
        self.thin_walled = bool(params.get("thin_walled", False))
        coat = f["coat"]
        pull = f["coat_affect_roughness"] * coat * f["coat_roughness"]
        r_spec = f["specular_roughness"] + (1.0 - f["specular_roughness"]) * pull
        self.alpha_s = roughness_anisotropy(r_spec, f["specular_anisotropy"])
        r_trans = np.clip(f["specular_roughness"] + f["transmission_extra_roughness"], 0.0, 1.0)
        r_trans = r_trans + (1.0 - r_trans) * pull
        self.alpha_t = roughness_anisotropy(r_trans, f["specular_anisotropy"])
        self.alpha_c = roughness_anisotropy(f["coat_roughness"], f["coat_anisotropy"])
        # Rotations apply only with anisotropy (MaterialX ifgreater on the anisotropy).
        self.rotation = np.where(f["specular_anisotropy"] > 0.0, f["specular_rotation"] * 2.0 * np.pi, 0.0)
        self.coat_rotation = np.where(f["coat_anisotropy"] > 0.0, f["coat_rotation"] * 2.0 * np.pi, 0.0)
        gamma = as_colour(1.0 + np.clip(coat, 0.0, 1.0) * f["coat_affect_color"])
        self.diffuse_colour = np.maximum(f["base_color"], 0.0) ** gamma
        self.subsurface_colour = np.maximum(f["subsurface_color"], 0.0) ** gamma
        self.coat_attenuation = np.clip(coat_absorption(f["coat_color"], as_colour(coat)), 0.0, 1.0)
        self.metal_n, self.metal_k = artistic_ior(
            f["base_color"] * as_colour(f["base"]), f["specular_color"] * as_colour(f["specular"])
        )
        self.coat_f0 = ior_to_f0(f["coat_IOR"])
        depth = f["transmission_depth"]
        has_depth = as_colour(depth > 0.0)
        self.transmission_tint = np.where(has_depth, 1.0, f["transmission_color"])
        if np.any(depth > 0.0):
            self.volume_absorption = absorption_coefficient(f["transmission_color"], depth, f["transmission_scatter"])
        self.opacity = np.clip(np.sum(f["opacity"] * np.asarray(colorspaces.REC709_LUMINANCE), axis=-1), 0.0, 1.0)
        self.film = None
        if np.any(f["thin_film_thickness"] > 0.0):
            self.film = (np.where(f["thin_film_thickness"] > 0.0, 1.0, 0.0), f["thin_film_thickness"], f["thin_film_IOR"])

    def _scatter(self, wi, wo, inside) -> Scatter:
        f = self.f
        wi_s, wo_s = rotate_about_normal(wi, self.rotation), rotate_about_normal(wo, self.rotation)
        diffuse = closures.oren_nayar_lobe(wi, wo, f["diffuse_roughness"], self.diffuse_colour)
        diffuse = diffuse.scaled(as_colour(f["base"]))
        if any_nonzero(f["subsurface"]):
            if self.thin_walled:
                sub = closures.translucent_lobe(wi, wo, self.subsurface_colour)
            else:
                sub = closures.lambert_lobe(wi, wo, self.subsurface_colour)
            diffuse = mix(diffuse, sub, as_colour(f["subsurface"]))
        if any_nonzero(f["sheen"]):
            sheen = closures.charlie_lobe(wi, wo, f["sheen_roughness"], f["sheen_color"], f["sheen"])
            diffuse = layer(sheen, diffuse)
        ax, ay = self.alpha_s
        shape = None if wi is None else microfacet.ggx_reflection(wi_s, wo_s, ax, ay)
        reflection, _ = closures.dielectric_interface(
            wi_s, wo_s, inside, ax, ay, f["specular_IOR"], thin_walled=self.thin_walled, thin_film=self.film,
            transmission=False, reflection_shape=shape,
        )
        reflection = reflection.weighted(as_colour(f["specular"])).scaled(np.maximum(f["specular_color"], 0.0))
        w_t = f["transmission"]
        if any_nonzero(w_t):
            tx, ty = self.alpha_t
            # (MaterialX's standard_surface.mtlx layers the filmed specular_bsdf over transmission_bsdf: what the
            # film reflects is not transmitted, so a clear, thin-walled soap bubble reflects and transmits all)
            _, transmission = closures.dielectric_interface(
                wi_s, wo_s, inside, tx, ty, f["specular_IOR"], thin_walled=self.thin_walled, thin_film=self.film
            )
            transmission = transmission.scaled(self.transmission_tint * as_colour(w_t))
            dielectric = add(layer(reflection, diffuse.scaled(as_colour(1.0 - w_t))), transmission)
        else:
            dielectric = layer(reflection, diffuse)
        base = dielectric
        if any_nonzero(f["metalness"]):
            metal = closures.conductor_lobe(
                wi_s, wo_s, ax, ay, self.metal_n, self.metal_k, thin_film=self.film, reflection_shape=shape
            )
            base = mix(dielectric, metal, as_colour(f["metalness"]))
        if any_nonzero(f["coat"]):
            cx, cy = self.alpha_c
            cwi, cwo = self.coat_dirs(wi, wo)  # coat_normal's frame
            wi_c, wo_c = rotate_about_normal(cwi, self.coat_rotation), rotate_about_normal(cwo, self.coat_rotation)
            coat, _ = closures.dielectric_interface(
                wi_c, wo_c, np.zeros(np.shape(cwo)[:-1], bool), cx, cy, f["coat_IOR"], transmission=False
            )
            base = layer(coat.weighted(as_colour(f["coat"])), base.scaled(self.coat_attenuation))
        return base

    def emission(self, wo) -> np.ndarray:
        f = self.f
        mu = np.clip(np.abs(np.asarray(wo)[..., 2]), 0.0, 1.0)
        e = f["emission_color"] * as_colour(f["emission"])
        coated = e * f["coat_color"] * as_colour((1.0 - self.coat_f0) * (1.0 - (1.0 - mu) ** 5))
        out = e + (coated - e) * as_colour(f["coat"])
        return np.broadcast_to(out, np.broadcast_shapes(out.shape, mu.shape + (3,)))
