"""OpenPBR Surface 1.1.1 <-> Autodesk Standard Surface 1.0.1.

Exact:
  * the parameters the two models share under other names (base, metalness, specular, transmission,
    subsurface weights and colours, coat, thin-film IOR, opacity as a grey colour, thin-walled,
    normals and tangents);
  * specular and coat anisotropy. OpenPBR (spec, "Microfacet model") gives
    alpha_t = r^2 sqrt(2 / (1 + (1 - a)^2)), alpha_b = (1 - a) alpha_t; MaterialX's Standard Surface
    (``mx_roughness_anisotropy``) alpha_x = r'^2 / sqrt(1 - a'), alpha_y = r'^2 sqrt(1 - a').
    Equal aspect ratios give a' = a, equal products r'^4 = r^4 2 (1 - a) / (1 + (1 - a)^2); exact
    while a <= 0.98 (Standard Surface clamps the anisotropy there);
  * subsurface radius: OpenPBR's scalar radius times its colour scale is Standard Surface's colour
    radius times its scalar scale (the colour part is normalised to a maximum of 1 going back);
  * dispersion: OpenPBR's Abbe number divided by its dispersion scale is Standard Surface's Abbe
    number (0 meaning none in both directions);
  * thin-film thickness: micrometres <-> nanometres;
  * emission: ``emission_luminance`` (nits) / ``nits_per_unit`` is Standard Surface's unitless
    ``emission`` weight (1 nit per unit by default, as MaterialX's reference renders OpenPBR).

Approximated (reported when the values make it visible):
  * a metal's ``specular_color`` is an F82 edge tint in OpenPBR and an edge colour (Gulbrandsen's
    artistic IOR, reaching it at grazing) in Standard Surface: copied as is;
  * fuzz (Zeltner) <-> sheen (Conty-Kulla): weight, colour and roughness copied;
  * a partial ``thin_film_weight`` becomes a film that is on (weight >= 0.5) or off;
  * OpenPBR roughens the base under a coat and darkens it by internal reflection on its own;
    Standard Surface has ``coat_affect_roughness`` and ``coat_affect_color``. Going to Standard
    Surface, ``coat_affect_roughness`` is solved so the roughened base roughness matches OpenPBR's
    (spec: r_b = min(1, (r^4 + 2 r_c^4)^(1/4))) and the base colour is pre-darkened by OpenPBR's
    view-independent darkening factor; coming back, ``coat_darkening`` is 0 (the same look). The
    base's specular IOR, which OpenPBR makes relative to the coat, is copied;
  * Standard Surface's colour ``opacity`` becomes OpenPBR's scalar opacity (mean of the channels),
    ``transmission_extra_roughness`` and ``coat_affect_color`` have no OpenPBR equivalent.
"""

from __future__ import annotations

import numpy as np

from ..model import Material
from .common import DARKENING_SOURCES, Dropped, Mapping, Settings, Translation, coat_darkening_factor, differs, translate

WHITE = np.ones(3)


def _anisotropy_scale(a):
    a = np.clip(a, 0.0, 1.0)
    return (2.0 * (1.0 - a) / (1.0 + (1.0 - a) ** 2)) ** 0.25


def openpbr_roughness_to_ss(r, a):
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(a > 0, r * _anisotropy_scale(a), r)


def ss_roughness_to_openpbr(r, a):
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = _anisotropy_scale(np.minimum(a, 0.999999))
        return np.where(a > 0, np.minimum(r / scale, 1.0), r)


def coat_affect_roughness(r, coat, coat_roughness):
    """The Standard Surface ``coat_affect_roughness`` that roughens the base as OpenPBR's coat does:
    OpenPBR r_b = mix(r, min(1, (r^4 + 2 r_c^4)^(1/4)), coat); Standard Surface
    r_b = mix(r, 1, k coat r_c) (MaterialX's standard_surface graph), solved for k."""
    target = np.minimum(1.0, (r ** 4 + 2.0 * coat_roughness ** 4) ** 0.25)
    roughened = r + coat * (target - r)
    denominator = coat * coat_roughness * (1.0 - r)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(denominator > 1e-9, (roughened - r) / np.where(denominator > 1e-9, denominator, 1.0), 0.0)
    return np.clip(k, 0.0, 1.0)


def _dispersion_to_ss(scale, abbe):
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where((scale > 0) & (abbe > 0), abbe / np.where(scale > 0, scale, 1.0), 0.0)


def _film_thickness_nm(weight, thickness_um):
    return np.where(weight >= 0.5, thickness_um * 1000.0, 0.0)


def _radius_colour(radius_scale):
    peak = np.max(radius_scale)
    return radius_scale / peak if peak > 0 else radius_scale


def _radius_scalar(radius_scale, scale):
    return np.max(radius_scale) * scale


TO_SS = (
    Mapping("base", ("base_weight",)),
    Mapping("base_color", ("base_color",) + DARKENING_SOURCES,
            lambda c, *rest: c * coat_darkening_factor(c, *rest),
            converted="darkened as OpenPBR darkens the base under its coat (Standard Surface does not)",
            when=lambda c, m, sw, ssw, ssc, cw, cd, ci: True),
    Mapping("diffuse_roughness", ("base_diffuse_roughness",)),
    Mapping("metalness", ("base_metalness",)),
    Mapping("specular", ("specular_weight",)),
    Mapping("specular_color", ("specular_color", "base_metalness"), lambda c, m: c, exact=False,
            note="a metal's F82 edge tint is copied as Standard Surface's edge colour (different Fresnel models)",
            matters=lambda c, m: m > 0 and differs(c, WHITE)),
    Mapping("specular_roughness", ("specular_roughness", "specular_roughness_anisotropy"), openpbr_roughness_to_ss,
            converted="roughness rescaled to keep OpenPBR's anisotropic alpha_t * alpha_b"),
    Mapping("specular_anisotropy", ("specular_roughness_anisotropy",), exact=True),
    Mapping("specular_IOR", ("specular_ior",)),
    Mapping("transmission", ("transmission_weight",)),
    Mapping("transmission_color", ("transmission_color",)),
    Mapping("transmission_depth", ("transmission_depth",)),
    Mapping("transmission_scatter", ("transmission_scatter",)),
    Mapping("transmission_scatter_anisotropy", ("transmission_scatter_anisotropy",)),
    Mapping("transmission_dispersion", ("transmission_dispersion_scale", "transmission_dispersion_abbe_number"),
            _dispersion_to_ss, converted="Abbe number / dispersion scale"),
    Mapping("subsurface", ("subsurface_weight",)),
    Mapping("subsurface_color", ("subsurface_color",)),
    Mapping("subsurface_radius", ("subsurface_radius_scale",), _radius_colour),
    Mapping("subsurface_scale", ("subsurface_radius_scale", "subsurface_radius"), _radius_scalar),
    Mapping("subsurface_anisotropy", ("subsurface_scatter_anisotropy",)),
    Mapping("sheen", ("fuzz_weight",), exact=False, note="fuzz (Zeltner) rendered as sheen (Conty-Kulla)",
            matters=lambda w: w > 0),
    Mapping("sheen_color", ("fuzz_color",)),
    Mapping("sheen_roughness", ("fuzz_roughness", "fuzz_weight"), lambda r, w: r, exact=False,
            note="sheen roughness conventions differ between the fuzz and sheen models", matters=lambda r, w: w > 0),
    Mapping("coat", ("coat_weight",)),
    Mapping("coat_color", ("coat_color",)),
    Mapping("coat_roughness", ("coat_roughness", "coat_roughness_anisotropy"), openpbr_roughness_to_ss),
    Mapping("coat_anisotropy", ("coat_roughness_anisotropy",)),
    Mapping("coat_IOR", ("coat_ior",)),
    Mapping("coat_affect_roughness", ("specular_roughness", "coat_weight", "coat_roughness"), coat_affect_roughness,
            converted="solved so the base under the coat is as rough as OpenPBR makes it"),
    Mapping("thin_film_thickness", ("thin_film_weight", "thin_film_thickness"), _film_thickness_nm, exact=False,
            note="Standard Surface has no film weight: a film weight below 0.5 is off, above is fully on",
            matters=lambda w, t: 0 < w < 1),
    Mapping("thin_film_IOR", ("thin_film_ior",)),
    Mapping("emission", ("emission_luminance",), None),
    Mapping("emission_color", ("emission_color",)),
    Mapping("opacity", ("geometry_opacity",), lambda o: np.repeat(np.asarray(o, dtype=np.float64).reshape(-1)[:1], 3)),
    Mapping("thin_walled", ("geometry_thin_walled",)),
    Mapping("normal", ("geometry_normal",)),
    Mapping("tangent", ("geometry_tangent",)),
    Mapping("coat_normal", ("geometry_coat_normal",)),
)

FROM_SS = (
    Mapping("base_weight", ("base",)),
    Mapping("base_color", ("base_color",)),
    Mapping("base_diffuse_roughness", ("diffuse_roughness",)),
    Mapping("base_metalness", ("metalness",)),
    Mapping("specular_weight", ("specular",)),
    Mapping("specular_color", ("specular_color", "metalness"), lambda c, m: c, exact=False,
            note="Standard Surface's metal edge colour is copied as OpenPBR's F82 edge tint (different Fresnel models)",
            matters=lambda c, m: m > 0 and differs(c, WHITE)),
    Mapping("specular_roughness", ("specular_roughness", "specular_anisotropy"), ss_roughness_to_openpbr,
            converted="roughness rescaled to keep the anisotropic alpha_x * alpha_y"),
    Mapping("specular_roughness_anisotropy", ("specular_anisotropy",)),
    Mapping("specular_ior", ("specular_IOR",)),
    Mapping("transmission_weight", ("transmission",)),
    Mapping("transmission_color", ("transmission_color",)),
    Mapping("transmission_depth", ("transmission_depth",)),
    Mapping("transmission_scatter", ("transmission_scatter",)),
    Mapping("transmission_scatter_anisotropy", ("transmission_scatter_anisotropy",)),
    Mapping("transmission_dispersion_scale", ("transmission_dispersion",), lambda v: np.where(v > 0, 1.0, 0.0)),
    Mapping("transmission_dispersion_abbe_number", ("transmission_dispersion",), lambda v: np.where(v > 0, v, 20.0)),
    Mapping("subsurface_weight", ("subsurface",)),
    Mapping("subsurface_color", ("subsurface_color",)),
    Mapping("subsurface_radius", ("subsurface_radius", "subsurface_scale"), lambda c, s: np.max(c) * s),
    Mapping("subsurface_radius_scale", ("subsurface_radius",), _radius_colour),
    Mapping("subsurface_scatter_anisotropy", ("subsurface_anisotropy",)),
    Mapping("fuzz_weight", ("sheen",), exact=False, note="sheen (Conty-Kulla) rendered as fuzz (Zeltner)",
            matters=lambda w: w > 0),
    Mapping("fuzz_color", ("sheen_color",)),
    Mapping("fuzz_roughness", ("sheen_roughness",)),
    Mapping("coat_weight", ("coat",)),
    Mapping("coat_darkening", ("coat",), lambda w: 0.0, when=lambda w: w > 0,
            converted="Standard Surface does not darken under a coat: OpenPBR's darkening switched off"),
    Mapping("coat_color", ("coat_color",)),
    Mapping("coat_roughness", ("coat_roughness", "coat_anisotropy"), ss_roughness_to_openpbr),
    Mapping("coat_roughness_anisotropy", ("coat_anisotropy",)),
    Mapping("coat_ior", ("coat_IOR",)),
    Mapping("thin_film_weight", ("thin_film_thickness",), lambda t: np.where(t > 0, 1.0, 0.0)),
    Mapping("thin_film_thickness", ("thin_film_thickness",), lambda t: t / 1000.0, converted="nanometres to micrometres"),
    Mapping("thin_film_ior", ("thin_film_IOR",)),
    Mapping("emission_luminance", ("emission",)),
    Mapping("emission_color", ("emission_color",)),
    Mapping("geometry_opacity", ("opacity",), lambda o: np.mean(o), exact=False,
            note="colour opacity averaged to OpenPBR's scalar opacity", matters=lambda o: float(np.ptp(o)) > 1e-6),
    Mapping("geometry_thin_walled", ("thin_walled",)),
    Mapping("geometry_normal", ("normal",)),
    Mapping("geometry_tangent", ("tangent",)),
    Mapping("geometry_coat_normal", ("coat_normal",)),
)

DROPPED_TO_SS = (
    Dropped("geometry_coat_tangent", "Standard Surface's coat uses the base tangent"),
)
DROPPED_FROM_SS = (
    Dropped("transmission_extra_roughness", "OpenPBR has no extra transmission roughness", matters=lambda v: v != 0),
    Dropped("coat_affect_color", "OpenPBR darkens under a coat physically (coat_darkening), not by saturation",
            matters=lambda v: v != 0),
    Dropped("coat_affect_roughness", "OpenPBR roughens the base under a coat on its own", matters=lambda v: v != 0),
)


def _emission(mappings, settings: Settings, to_ss: bool):
    factor = 1.0 / settings.nits_per_unit if to_ss else settings.nits_per_unit
    note = (f"{'nits to a unitless weight' if to_ss else 'a unitless weight to nits'} at "
            f"{settings.nits_per_unit:g} nit(s) per unit")
    return tuple(
        Mapping(m.target, m.sources, lambda v, f=factor: v * f, converted=note)
        if m.target in ("emission", "emission_luminance") else m
        for m in mappings
    )


def openpbr_to_standard_surface(material: Material, settings: Settings | None = None) -> Translation:
    settings = settings or Settings()
    return translate(material, "standard_surface", _emission(TO_SS, settings, True), DROPPED_TO_SS, settings,
                     "OpenPBR -> Standard Surface")


def standard_surface_to_openpbr(material: Material, settings: Settings | None = None) -> Translation:
    settings = settings or Settings()
    return translate(material, "open_pbr_surface", _emission(FROM_SS, settings, False), DROPPED_FROM_SS, settings,
                     "Standard Surface -> OpenPBR")
