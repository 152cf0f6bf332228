"""OpenPBR Surface 1.1.1 <-> UsdPreviewSurface 2.6 (metallic workflow; the specular workflow is read).

UsdPreviewSurface is the lowest common denominator every USD renderer draws: a diffuse lobe, one
GGX specular lobe (metallic or specular workflow), a clear coat, emission and opacity.

Exact:
  * metalness, IOR, roughness of an isotropic base (both alpha = roughness^2), clear coat weight and
    roughness, normal maps, opacity; the base colour of an opaque material (``base_weight * base_color``,
    a metal's F0 in both).

Approximated (reported when visible):
  * anisotropy: the preview's isotropic roughness keeps the geometric mean of OpenPBR's alphas;
  * transmission: the preview has no refraction; glass becomes opacity 1 - transmission_weight
    (the reflection stays, the refracted image becomes see-through);
  * ``specular_weight``/``specular_color`` (the metallic workflow has no control), the coat's
    colour and IOR (the preview's coat has IOR 1.5), subsurface (folded into the diffuse colour);
  * emission: ``emissiveColor`` = ``emission_color * emission_luminance / nits_per_unit``.

Not carried (reported): fuzz, thin film, dispersion, diffuse roughness, volume colour.
Reading a specular-workflow preview: ``specularColor`` is the F0 colour; it becomes an IOR with the
same F0 luminance and a ``specular_color`` tint (approximate for coloured F0).
"""

from __future__ import annotations

import numpy as np

from ..model import Material
from .common import Dropped, Mapping, Settings, Translation, differs, translate
from .gltf import _alphas_openpbr

WHITE = np.ones(3)


def preview_roughness(r, a):
    alpha_t, alpha_b = _alphas_openpbr(r, a)
    return (alpha_t * alpha_b) ** 0.25


def ior_from_f0(f0):
    root = np.sqrt(np.clip(f0, 0.0, 0.999999))
    return (1.0 + root) / (1.0 - root)


def to_usd_mappings(settings: Settings) -> tuple[Mapping, ...]:
    nits = settings.nits_per_unit
    return (
        Mapping("diffuseColor", ("base_weight", "base_color", "subsurface_weight", "subsurface_color"),
                lambda w, c, s, sc: w * c + s * (w * sc - w * c), exact=False, matters=lambda w, c, s, sc: s > 0,
                note="subsurface folded into the diffuse colour"),
        Mapping("metallic", ("base_metalness",)),
        Mapping("roughness", ("specular_roughness", "specular_roughness_anisotropy"), preview_roughness, exact=False,
                matters=lambda r, a: a > 0, note="anisotropy dropped: isotropic roughness keeps the geometric mean of the alphas"),
        Mapping("ior", ("specular_ior",)),
        Mapping("clearcoat", ("coat_weight",)),
        Mapping("clearcoatRoughness", ("coat_roughness",)),
        Mapping("emissiveColor", ("emission_color", "emission_luminance"), lambda c, l: c * l / nits,
                converted=f"emission_color * emission_luminance at {nits:g} nit(s) per unit"),
        Mapping("opacity", ("geometry_opacity", "transmission_weight"), lambda o, t: o * (1.0 - t), exact=False,
                matters=lambda o, t: t > 0, note="no refraction in UsdPreviewSurface: transmission becomes transparency"),
        Mapping("normal", ("geometry_normal",)),
    )


DROPPED_TO_USD = (
    Dropped("specular_weight", "the metallic workflow has no specular weight", matters=lambda w: w != 1.0),
    Dropped("specular_color", "the metallic workflow has no specular tint", matters=lambda c: differs(c, WHITE)),
    Dropped("coat_color", "the preview clear coat is colourless", matters=lambda c, w: w > 0 and differs(c, WHITE),
            needs=("coat_weight",)),
    Dropped("coat_ior", "the preview clear coat has IOR 1.5", matters=lambda n, w: w > 0 and abs(n - 1.5) > 1e-6,
            needs=("coat_weight",)),
    Dropped("fuzz_weight", "UsdPreviewSurface has no sheen", matters=lambda w: w > 0),
    Dropped("thin_film_weight", "UsdPreviewSurface has no thin film", matters=lambda w: w > 0),
    Dropped("transmission_color", "UsdPreviewSurface has no transmission tint",
            matters=lambda c, t: t > 0 and differs(c, WHITE), needs=("transmission_weight",)),
    Dropped("transmission_dispersion_scale", "UsdPreviewSurface has no dispersion", matters=lambda s: s > 0),
    Dropped("base_diffuse_roughness", "UsdPreviewSurface's diffuse is Lambertian", matters=lambda r: r > 0),
    Dropped("geometry_coat_normal", "UsdPreviewSurface's coat uses the base normal"),
    Dropped("geometry_tangent", "UsdPreviewSurface has no tangent input"),
)


def from_usd_mappings(settings: Settings) -> tuple[Mapping, ...]:
    nits = settings.nits_per_unit

    def specular_ior(workflow, specular, ior):
        luminance = float(np.dot(specular, [0.2126, 0.7152, 0.0722]))
        return np.where(workflow >= 1, ior_from_f0(luminance), ior)

    def specular_tint(workflow, specular):
        peak = np.max(specular)
        return np.where(workflow >= 1, specular / peak if peak > 0 else WHITE, WHITE)

    return (
        Mapping("base_color", ("diffuseColor",)),
        Mapping("base_metalness", ("metallic", "useSpecularWorkflow"), lambda m, w: np.where(w >= 1, 0.0, m)),
        Mapping("specular_roughness", ("roughness",)),
        Mapping("specular_ior", ("useSpecularWorkflow", "specularColor", "ior"), specular_ior, exact=False,
                matters=lambda w, s, i: w >= 1, note="specular workflow: F0 colour became an IOR and a tint"),
        Mapping("specular_color", ("useSpecularWorkflow", "specularColor"), specular_tint),
        Mapping("coat_weight", ("clearcoat",)),
        Mapping("coat_roughness", ("clearcoatRoughness",)),
        Mapping("coat_ior", ("clearcoat",), lambda c: 1.5, when=lambda c: c > 0, converted="the preview clear coat has IOR 1.5"),
        Mapping("emission_color", ("emissiveColor",), lambda c: c / np.max(c) if np.max(c) > 0 else WHITE),
        Mapping("emission_luminance", ("emissiveColor",), lambda c: np.max(c) * nits,
                converted=f"nits at {nits:g} nit(s) per unit"),
        Mapping("geometry_opacity", ("opacity", "opacityThreshold"), lambda o, t: np.where(t > 0, np.where(o >= t, 1.0, 0.0), o),
                exact=False, matters=lambda o, t: t > 0, note="an opacity threshold becomes a binary opacity"),
        Mapping("geometry_normal", ("normal",)),
    )


DROPPED_FROM_USD = (
    Dropped("occlusion", "OpenPBR has no ambient occlusion input", matters=lambda v: v != 1.0),
    Dropped("displacement", "OpenPBR is a surface shader; displacement belongs to a displacement shader",
            matters=lambda v: v != 0.0),
)


def openpbr_to_usd_preview(material: Material, settings: Settings | None = None) -> Translation:
    settings = settings or Settings()
    return translate(material, "UsdPreviewSurface", to_usd_mappings(settings), DROPPED_TO_USD, settings,
                     "OpenPBR -> UsdPreviewSurface")


def usd_preview_to_openpbr(material: Material, settings: Settings | None = None) -> Translation:
    settings = settings or Settings()
    return translate(material, "open_pbr_surface", from_usd_mappings(settings), DROPPED_FROM_USD, settings,
                     "UsdPreviewSurface -> OpenPBR")
