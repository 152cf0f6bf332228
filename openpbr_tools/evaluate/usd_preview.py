"""UsdPreviewSurface 2.6 as a mixture of lobes.

What the specification (OpenUSD ``docs/spec_usdpreviewsurface.rst``) defines: Lambertian
``diffuseColor``; one GGX specular lobe with alpha = roughness^2 and Schlick Fresnel —
specular workflow: F0 = specularColor, F90 = 1; metallic workflow: F0 and F90 interpolated by
``metallic`` from (((1 - ior)/(1 + ior))^2, 1) to (diffuseColor, diffuseColor); a white second
specular lobe ``clearcoat`` with roughness clearcoatRoughness^2 whose F0 comes from ``ior``;
``emissiveColor``; ``opacity`` with ``opacityThreshold`` (cut-out when > 0) — "a fully
transparent object still receives lighting" — and ``opacityMode`` (spec 2.6): "presence" makes
opacity the surface's coverage, lighting and emission included.

Where it is silent, MaterialX's ``IMP_UsdPreviewSurface_surfaceshader`` graph is followed: the
specular lobe is layered over the diffuse with albedo scaling, the diffuse weight is
1 - metallic in the metallic workflow, lobes carry Turquin's multiple-scattering compensation,
and in "transparent" mode (threshold 0) opacity mixes the diffuse with a smooth dielectric
transmission of the same ``ior``. Unlike MaterialX's graph, the metallic workflow is the single
interpolated Schlick lobe the specification describes, not an additional artistic-IOR conductor.
Coverage is 1 unless ``opacityThreshold`` > 0 (then opacity >= threshold) or the mode is
"presence" (then opacity). ``normal``,
``displacement`` and ``occlusion`` are not evaluated.
"""

from __future__ import annotations

import numpy as np

from . import closures
from .fresnel import ior_to_f0
from .layering import BSDFModel, Scatter, add, any_nonzero, as_colour, layer

ALPHA_FLOOR = 1e-4


class UsdPreviewSurface(BSDFModel):
    model = "UsdPreviewSurface"

    def __init__(self, params: dict):
        super().__init__(params)
        f = {k: np.asarray(v, dtype=float) for k, v in params.items() if not isinstance(v, (bool, np.bool_))}
        self.f = f
        self.alpha = np.clip(f["roughness"] ** 2, ALPHA_FLOOR, 1.0)
        self.alpha_c = np.clip(f["clearcoatRoughness"] ** 2, ALPHA_FLOOR, 1.0)
        specular_workflow = as_colour(f["useSpecularWorkflow"] >= 0.5)
        m = as_colour(np.clip(f["metallic"], 0.0, 1.0))
        f0_ior = as_colour(ior_to_f0(f["ior"]))
        diffuse_colour = np.maximum(f["diffuseColor"], 0.0)
        metal_f0 = f0_ior + (diffuse_colour - f0_ior) * m
        metal_f90 = 1.0 + (diffuse_colour - 1.0) * m
        self.f0 = np.where(specular_workflow, np.maximum(f["specularColor"], 0.0), metal_f0)
        self.f90 = np.where(specular_workflow, 1.0, metal_f90)
        self.diffuse_weight = np.where(specular_workflow, 1.0, 1.0 - m)
        self.coat_f0 = f0_ior
        threshold = f["opacityThreshold"]
        cutout = threshold > 0.0
        presence = ~cutout & (f["opacityMode"] >= 1)  # spec 2.6: opacity is coverage, lighting included
        opacity = np.clip(f["opacity"], 0.0, 1.0)
        self.opacity = np.where(cutout, np.where(f["opacity"] >= threshold, 1.0, 0.0), np.where(presence, opacity, 1.0))
        self.transparency = np.where(cutout | presence, 0.0, 1.0 - opacity)
        self.thin_walled = False

    def _scatter(self, wi, wo, inside) -> Scatter:
        f = self.f
        base = closures.lambert_lobe(wi, wo, np.maximum(f["diffuseColor"], 0.0)).scaled(self.diffuse_weight)
        transparency = self.transparency
        if any_nonzero(transparency):
            _, trans = closures.dielectric_interface(wi, wo, inside, ALPHA_FLOOR, ALPHA_FLOOR, f["ior"])
            base = add(base.scaled(as_colour(1.0 - transparency)), trans.scaled(as_colour(transparency)))
        spec = closures.schlick_lobe(wi, wo, self.alpha, self.alpha, self.f0, self.f90)
        result = layer(spec, base)
        if any_nonzero(f["clearcoat"]):
            coat = closures.schlick_lobe(wi, wo, self.alpha_c, self.alpha_c, self.coat_f0 * np.ones(3), 1.0)
            result = layer(coat.weighted(as_colour(f["clearcoat"])), result)
        return result

    def emission(self, wo) -> np.ndarray:
        out = self.f["emissiveColor"]  # added as it is, as MaterialX's graph adds it (no clamp): a
        # wide-gamut document's emission can be negative in linear Rec.709 and is not dimmed by that
        return np.broadcast_to(out, np.broadcast_shapes(out.shape, np.shape(wo)[:-1] + (3,)))
