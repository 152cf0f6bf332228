"""glTF 2.0 metallic-roughness material with the ratified KHR_materials_* extensions, as the
``gltf_pbr`` MaterialX node carries them (parameter names of ``ND_gltf_pbr_surfaceshader``).

Core (glTF 2.0 specification, Appendix B): alpha = roughness^2,
``material = mix(dielectric_brdf, metal_brdf, metallic)`` with
``metal_brdf = specular_brdf * (baseColor + (1 - baseColor)(1 - |VdotH|)^5)`` and the dielectric
built by ``fresnel_mix``: ``F * specular_brdf + (1 - max(F)) * base`` with
F = F0 + (F90 - F0)(1 - |VdotH|)^5. Extensions:

* KHR_materials_ior / KHR_materials_specular: F0 = min(((ior-1)/(ior+1))^2 specularColor, 1)
  * specular, F90 = specular;
* KHR_materials_transmission (+ volume): the base's diffuse is mixed with a specular
  transmission tinted by baseColor; thin-walled unless ``thickness`` > 0 (volume), in which case
  light refracts. Here the transmission is the rough interface's own refraction (or
  straight-through) lobe, which already carries (1 - F) and is energy-compensated, instead of
  fresnel_mix's (1 - max F) weighting of a separate BTDF (documented approximation);
  KHR_materials_volume's attenuation (-ln(attenuationColor) / attenuationDistance) is exposed for
  previews with ``thickness`` as the path length;
* KHR_materials_clearcoat: ``mix(material, clearcoat_brdf, clearcoat * Fc(NdotV))`` with
  Fc = 0.04 + 0.96 (1 - NdotV)^5 and alpha_c = clearcoatRoughness^2;
* KHR_materials_sheen: Conty-Kulla "Charlie" distribution, alpha = sheenRoughness^2, layered by
  ``1 - max3(sheenColor) E(NdotV)`` (the extension's view-only albedo scaling, which it allows
  for direct and indirect light). The extension lets implementations choose the visibility term
  (Charlie's shadowing or Ashikhmin's smooth denominator); MaterialX's ``gltf_pbr`` uses
  Ashikhmin's, and so does this evaluator (``GltfPbr.sheen_visibility = "charlie"`` switches);
* KHR_materials_iridescence: F -> mix(F, F_iridescence, iridescence), the film on a substrate of
  the IOR giving the lobe's F0 (spectral Airy reflectance, :mod:`.thinfilm`, instead of the
  extension's Belcour-Barla approximation). As the extension specifies, the film-substrate
  interface uses both indices; MaterialX 1.39.5's ``gltf_pbr`` instead reuses the air-substrate
  Schlick F0 there, which gives it more saturated fringes;
* KHR_materials_anisotropy: alpha_t = mix(alpha, 1, strength^2), alpha_b = alpha, direction
  rotated by anisotropy_rotation (radians) from the tangent towards the bitangent;
* KHR_materials_emissive_strength: emission = emissive * emissive_strength;
* KHR_materials_diffuse_transmission (its factors): the diffuse BRDF becomes mix(Lambert(baseColor),
  Lambert transmission of diffuseTransmissionColor, diffuseTransmissionFactor) under the same
  Fresnel weight;
* KHR_materials_dispersion only changes refraction directions and is not evaluated; occlusion is
  not evaluated (a baked, geometry-dependent factor).

Appendix B (a non-normative example implementation) uses the single-scattering microfacet
BRDF and says nothing about the energy single scattering loses on rough surfaces; as for other
ambiguities, MaterialX's ``gltf_pbr`` graph is followed and the specular lobes carry Turquin's
multiple-scattering compensation (2019, eq. 16). ``GltfPbr.energy_compensation = False`` gives
the plain single-scattering lobes. Note that ``fresnel_mix`` weights the diffuse base by
1 - F(VdotH), which at grazing views lets specular plus diffuse exceed 1 (e.g. about 1.27 for a
white base, roughness 0.2, 78 degrees): a property of the specified model, kept as is.
"""

from __future__ import annotations

import numpy as np

from . import albedo as tab
from . import closures, microfacet, sheen
from .fresnel import f0_to_ior, ior_to_f0
from .layering import BSDFModel, Scatter, add, any_nonzero, as_colour, layer, mix, rotate_about_normal
from .thinfilm import thin_film_rgb

ALPHA_FLOOR = 1e-4
CLEARCOAT_F0 = 0.04


def _film_factor(cos, film, f0):
    _, thickness, ior = film
    return thin_film_rgb(cos, thickness, ior, f0_to_ior(np.clip(f0, 0.0, 0.9999)))


class GltfPbr(BSDFModel):
    model = "gltf_pbr"
    energy_compensation = True
    sheen_visibility = "ashikhmin"

    def __init__(self, params: dict):
        super().__init__(params)
        f = {k: np.asarray(v, dtype=float) for k, v in params.items() if v is not None and not isinstance(v, (bool, np.bool_))}
        self.f = f
        alpha = np.clip(f["roughness"] ** 2, ALPHA_FLOOR, 1.0)
        alpha_t = microfacet.gltf_anisotropic_alpha(alpha, f["anisotropy_strength"])
        self.alpha = (np.clip(alpha_t, ALPHA_FLOOR, 1.0), alpha)
        self.rotation = f["anisotropy_rotation"]
        self.alpha_c = np.clip(f["clearcoat_roughness"] ** 2, ALPHA_FLOOR, 1.0)
        self.f0 = np.minimum(as_colour(ior_to_f0(f["ior"])) * f["specular_color"], 1.0) * as_colour(f["specular"])
        self.f90 = f["specular"]
        self.thin_walled = not np.any(f["thickness"] > 0.0)
        distance = f.get("attenuation_distance")
        attenuating = None if distance is None else np.isfinite(distance) & (distance > 0.0)
        if attenuating is not None and np.any(attenuating):  # per pixel: none where the distance is not a length
            self.volume_absorption = np.where(as_colour(attenuating), -np.log(np.maximum(f["attenuation_color"], 1e-6))
                                              / as_colour(np.where(attenuating, distance, 1.0)), 0.0)
        self.volume_path_length = f["thickness"]
        mode = int(np.asarray(f["alpha_mode"]).reshape(-1)[0])
        if mode == 0:
            self.opacity = np.asarray(1.0)
        elif mode == 1:
            self.opacity = np.where(f["alpha"] >= f["alpha_cutoff"], 1.0, 0.0)
        else:
            self.opacity = np.clip(f["alpha"], 0.0, 1.0)
        self.film = None
        if any_nonzero(f["iridescence"]):
            self.film = (f["iridescence"], f["iridescence_thickness"], f["iridescence_ior"])

    def _dielectric(self, wi, wo, inside, ax, ay, shape, cos_h):
        f = self.f
        mu_o = wo[..., 2]
        a_avg = tab.average_alpha(ax, ay)
        f0, f90 = self.f0, as_colour(self.f90)
        f0_max = np.max(f0, axis=-1, keepdims=True)
        comp = tab.ggx_compensation(mu_o, a_avg, f0) if self.energy_compensation else np.ones(3)
        e_spec = tab.ggx_schlick_albedo(mu_o, a_avg, f0, f90) * comp
        # Diffuse base weighted by 1 - max(F(VdotH)); F90 is grey, so max(F) = F with max(F0).
        y_avg = as_colour(tab.lambert_schlick_albedo(mu_o))
        diffuse_weight_avg = 1.0 - f0_max - (f90 - f0_max) * y_avg
        base_colour = np.maximum(f["base_color"], 0.0)
        translucent = None
        if any_nonzero(f["diffuse_transmission"]):
            # KHR_materials_diffuse_transmission: the diffuse BRDF becomes mix(BRDF, BTDF, t), the BTDF
            # Lambertian through the surface, tinted by its colour, under the same Fresnel weight
            # (taken at the view direction for the transmitted part)
            t = as_colour(np.clip(f["diffuse_transmission"], 0.0, 1.0))
            weight_o = 1.0 - np.max(f0 + (f90 - f0) * as_colour((1.0 - np.abs(mu_o)) ** 5), axis=-1, keepdims=True)
            translucent = closures.translucent_lobe(wi, wo, np.maximum(f["diffuse_transmission_color"], 0.0) * t)
            translucent = translucent.scaled(weight_o)
            base_colour = base_colour * (1.0 - t)
        e_diffuse = diffuse_weight_avg * base_colour
        value = None
        if wi is not None:
            y = as_colour((1.0 - cos_h) ** 5)
            fr = f0 + (f90 - f0) * y
            diffuse_value = as_colour(np.where((wi[..., 2] > 0.0), 1.0 / np.pi, 0.0)) * base_colour
            value = fr * as_colour(shape) * comp + (1.0 - np.max(fr, axis=-1, keepdims=True)) * diffuse_value
        if self.film is not None:
            w = as_colour(self.film[0])
            e1 = as_colour(tab.ggx_albedo(mu_o, a_avg))
            f_film_o = _film_factor(mu_o, self.film, f0)
            e_spec = e_spec * (1.0 - w) + w * f_film_o * e1 * comp
            e_diffuse = e_diffuse * (1.0 - w) + w * (1.0 - np.max(f_film_o, axis=-1, keepdims=True)) * base_colour
            if wi is not None:
                f_film = _film_factor(cos_h, self.film, f0)
                fr_mixed = fr * (1.0 - w) + w * f_film
                value = fr_mixed * as_colour(shape) * comp + (1.0 - np.max(fr_mixed, axis=-1, keepdims=True)) * diffuse_value
        opaque = Scatter.lobe(value, e_spec + e_diffuse, 0.0, np.zeros(3))
        if translucent is not None:
            opaque = add(opaque, translucent)
        w_t = f["transmission"]
        if not any_nonzero(w_t):
            return opaque
        # Transmission replaces the diffuse part of the base (KHR_materials_transmission).
        spec_only = Scatter.lobe(
            None if wi is None else _specular_value(shape, comp, f0, f90, cos_h, self.film),
            e_spec,
            0.0,
            np.zeros(3),
        )
        # KHR_materials_iridescence replaces the Fresnel of fresnel_mix, whose base is the transmission: what the film
        # reflects is not transmitted (a clear, thin-walled soap bubble reflects and transmits all it receives)
        _, trans = closures.dielectric_interface(
            wi, wo, inside, ax, ay, f["ior"], thin_walled=self.thin_walled, energy_compensation=self.energy_compensation,
            thin_film=self.film,
        )
        trans = trans.scaled(base_colour * as_colour(w_t))
        return add(mix(opaque, spec_only, as_colour(w_t)), trans)

    def _scatter(self, wi, wo, inside) -> Scatter:
        f = self.f
        ax, ay = self.alpha
        wi_r, wo_r = rotate_about_normal(wi, self.rotation), rotate_about_normal(wo, self.rotation)
        shape = cos_h = None
        if wi is not None:
            shape, cos_h = microfacet.ggx_reflection(wi_r, wo_r, ax, ay)
        base = self._dielectric(wi_r, wo_r, inside, ax, ay, shape, cos_h)
        if any_nonzero(f["metallic"]):
            comp = self.energy_compensation
            metal = closures.schlick_lobe(wi_r, wo_r, ax, ay, np.maximum(f["base_color"], 0.0), 1.0, energy_compensation=comp)
            if self.film is not None:
                film = closures.schlick_lobe(
                    wi_r, wo_r, ax, ay, np.maximum(f["base_color"], 0.0), 1.0,
                    thin_film=(np.ones_like(self.film[0]),) + self.film[1:], energy_compensation=comp,
                )
                metal = mix(metal, film, as_colour(self.film[0]))
            base = mix(base, metal, as_colour(f["metallic"]))
        colour = np.maximum(f["sheen_color"], 0.0)
        intensity = np.max(colour, axis=-1)
        if any_nonzero(intensity):
            r = np.clip(f["sheen_roughness"] ** 2, sheen.CHARLIE_MIN_ROUGHNESS, 1.0)
            normalised = colour / as_colour(np.where(intensity > 0.0, intensity, 1.0))
            sheen_lobe = closures.charlie_lobe(wi, wo, r, normalised, intensity, visibility=self.sheen_visibility)
            base = layer(sheen_lobe, base)
        cc = f["clearcoat"]
        if any_nonzero(cc):
            cwi, cwo = self.coat_dirs(wi, wo)  # clearcoat_normal's frame
            mu_o = cwo[..., 2]
            fc = CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) * (1.0 - mu_o) ** 5
            comp = tab.ggx_compensation(mu_o, self.alpha_c, np.full(3, CLEARCOAT_F0)) if self.energy_compensation else 1.0
            e_c = as_colour(tab.ggx_albedo(mu_o, self.alpha_c)) * comp
            value = None
            if wi is not None:
                shape_c, _ = microfacet.ggx_reflection(cwi, cwo, self.alpha_c, self.alpha_c)
                value = as_colour(shape_c) * comp
            coat = Scatter.lobe(value, e_c, 0.0, 1.0 - e_c)
            base = mix(base, coat, as_colour(cc * fc))
        return base

    def emission(self, wo) -> np.ndarray:
        f = self.f
        out = f["emissive"] * as_colour(f["emissive_strength"])
        return np.broadcast_to(out, np.broadcast_shapes(out.shape, np.shape(wo)[:-1] + (3,)))


def _specular_value(shape, comp, f0, f90, cos_h, film):
    """The specular (reflection) part of the dielectric value alone: F * specular_brdf."""
    y = as_colour((1.0 - cos_h) ** 5)
    fr = f0 + (f90 - f0) * y
    if film is not None:
        w = as_colour(film[0])
        fr = fr * (1.0 - w) + w * _film_factor(cos_h, film, f0)
    return fr * as_colour(shape) * comp
