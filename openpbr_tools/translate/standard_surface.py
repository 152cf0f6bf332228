"""OpenPBR Surface 1.1.1 <-> Autodesk Standard Surface 1.0.1.

Exact:
  * the parameters the two models share under other names (base, metalness, transmission,
    subsurface weights and colours, coat, thin-film IOR, opacity as a grey colour, thin-walled,
    normals and tangents; the specular weight and colour of an uncoated dielectric);
  * specular and coat anisotropy. OpenPBR (spec, "Microfacet model") gives
    alpha_t = r^2 sqrt(2 / (1 + (1 - a)^2)), alpha_b = (1 - a) alpha_t; MaterialX's Standard Surface
    (``mx_roughness_anisotropy``) alpha_x = r'^2 / sqrt(1 - a'), alpha_y = r'^2 sqrt(1 - a').
    Equal aspect ratios give a' = a, equal products r'^4 = r^4 2 (1 - a) / (1 + (1 - a)^2); exact
    while a <= 0.98 (Standard Surface clamps the anisotropy there);
  * subsurface radius: OpenPBR's scalar radius times its colour scale is Standard Surface's colour
    radius times its scalar scale (the colour part is normalised to a maximum of 1 going back);
  * dispersion: OpenPBR's Abbe number divided by its dispersion scale is Standard Surface's Abbe
    number (0 meaning none in both directions);
  * thin-film thickness: micrometres <-> nanometres (on a dielectric; on a metal the film interferes over
    Standard Surface's artistic-IOR conductor and OpenPBR's F82 metal, which colour it apart: approximated,
    9.3 mean CIEDE2000 on the evaluator and 6.2 in MaterialX's GLSL on a green metal under 430 nm);
  * emission: ``emission_luminance`` (nits) / ``nits_per_unit`` is Standard Surface's unitless
    ``emission`` weight (1 nit per unit by default, as MaterialX's reference renders OpenPBR).

Approximated (reported when the values make it visible; residuals are mean CIEDE2000 on the
  * rough diffuse: OpenPBR's ``base_diffuse_roughness`` drives the energy-preserving Oren-Nayar
    (EON), Standard Surface's ``diffuse_roughness`` the qualitative Oren-Nayar; copied, so rough
    materials come out darker (rough concrete at 0.9: 5.8 mean ΔE, the same as MaterialX's graph);
  * thin-walled subsurface: diffuse transmission in OpenPBR, a translucency of another shape in
    Standard Surface; weight copied (thin leaves and paper 5-7 ΔE, as MaterialX's graph);
evaluator's lit sphere, before -> after the fits of :mod:`.fit`, from ``openpbr convert --verify``):
  * the base under a coat: OpenPBR computes its Fresnel with its IOR relative to the coat's
    (n_b / n_c, mixed by coat weight) and darkens it. Standard Surface keeps ``specular_IOR`` = n_b
    (it also bends the refracted light, which a parallel coat does not change) and its ``specular``
    weight scales the reflection to OpenPBR's F0 (:func:`.fit.dielectric_specular_scale`; under a
    thin film only the film-free share). Coated plastics and ceramics 0.0-0.4 (0.5-4.1), the car
    paint sample 2.7 (4.15: the rest is its film of weight 0.6, all or nothing here), coated glass
    3.4 (4.8). Coming back the weight is divided by the same scale (specular_weight > 1 where the
    base's IOR is close to the coat's);
  * a metal's ``specular_color`` is an F82 edge tint in OpenPBR and an edge colour (Gulbrandsen's
    artistic IOR) in Standard Surface: the edge colour is solved so that the conductor's exact
    Fresnel at 82 degrees is OpenPBR's (:func:`.fit.edge_color_for_f82_tint`), which makes the
    evaluator's albedos equal; a tint the conductor cannot reach (a deep dip on a bright metal)
    gets the nearest edge colour. OpenPBR's ``specular_weight`` scales its metal, Standard
    Surface's conductor ignores ``specular``: on a full metal the weight becomes the tint of a coat
    that reflects nothing (:mod:`.ss_metal_weight`, exact), elsewhere it goes into the base colour
    (F0) and the 82-degree target. Tinted metals 0.0-0.3 (0.1-1.3), an unreachable tint 1.6 (1.7),
    specular weight 0.6-0.8 on partly metallic bases 0.5-0.9 (4.7-9.0), on full metals 0.0 (0.2-2.4);
  * fuzz (Zeltner) <-> sheen (Conty-Kulla): the sheen weight and roughness are fitted to the
    fuzz's albedo (:func:`.fit.sheen_fit`), the weight clamped to 1 where rough fuzz reflects more
    than a sheen can. Velvets 0.8-1.9 (5.2-10.6), the roughest 3.4 (3.5), a 0.6-weight grey dust
    1.1 (0.9);
  * a partial ``thin_film_weight`` becomes a film that is on (weight >= 0.5) or off;
  * OpenPBR roughens the base under a coat and darkens it by internal reflection on its own;
    Standard Surface has ``coat_affect_roughness`` and ``coat_affect_color``. Going to Standard
    Surface, ``coat_affect_roughness`` is solved so the roughened base roughness matches OpenPBR's
    (spec: r_b = min(1, (r^4 + 2 r_c^4)^(1/4)); where that needs more than 1, it is 1 and the base
    roughness is raised to match) and the base colour is pre-darkened by OpenPBR's view-independent
    darkening factor; coming back, ``coat_darkening`` is 0 (the same look) and the base roughness is
    the one OpenPBR's coat roughens into Standard Surface's base under its coat, 0 where that base is
    smoother than OpenPBR's coat allows (reported). 120 random coated Standard Surface constants to
    OpenPBR: over 2.3 mean CIEDE2000 18 -> 11, 20 closer by more than 0.3, none further (before, the
    roughness was copied and OpenPBR's coat roughened it again); the other way, p95 1.27 -> 0.95;
  * rough diffuse: Standard Surface's qualitative Oren-Nayar is darker than OpenPBR's energy-preserving
    EON at the same roughness; a dielectric base's colour is scaled so the hemispherical albedos match
    (:func:`.fit.eon_colour_for_qon`, exact inverses; clipped at 1 going to Standard Surface). Rough
    concrete (roughness 1) 5.8 -> 1.5 both ways; the angular shapes still differ;
  * Standard Surface's colour ``opacity`` becomes OpenPBR's scalar opacity (mean of the channels),
    ``transmission_extra_roughness`` and ``coat_affect_color`` have no OpenPBR equivalent.

One module because the two directions are each other's inverses, formula by formula, and are tested
as round trips.
"""

from __future__ import annotations

import numpy as np

from .. import tables
from ..evaluate import fresnel
from ..evaluate.coat import coat_darkening_factor, coat_roughened
from ..model import Material
from . import fit, ss_metal_weight, ss_rotation
from .coat_facts import DARKENING_SOURCES
from .common import Dropped, Mapping, Settings, Translation, Values, differs, translate

WHITE = np.ones(3)
#: Measured residuals, mean CIEDE2000 on the evaluator's lit sphere (module docstring).
COAT_RESIDUAL = "measured ΔE2000 up to 0.4 on coated plastics, 2.7 on a car paint with a partial thin film"
METAL_RESIDUAL = "measured ΔE2000 up to 0.3 on tinted metals, 1.6 where the tint is out of reach"
SHEEN_RESIDUAL = "measured ΔE2000 0.8-1.9 on velvets"


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


def ss_base_roughness(r, a, coat, coat_roughness, coat_anisotropy, affect):
    """OpenPBR's ``specular_roughness`` for Standard Surface's. Standard Surface's base under its coat has
    mix(r, 1, coat_affect_roughness coat coat_roughness) (MaterialX's standard_surface graph); OpenPBR's coat
    roughens the base it covers (:func:`~openpbr_tools.evaluate.coat.coat_roughened`, with OpenPBR's coat
    roughness). The result is the roughness OpenPBR roughens into Standard Surface's (the anisotropic alpha
    products kept), 0 where that is smoother than OpenPBR's coat allows (:func:`.fit.coat_unroughened`)."""
    return fit.coat_unroughened(ss_roughness_to_openpbr(_ss_under_coat(r, coat, coat_roughness, affect), a),
                                coat, ss_roughness_to_openpbr(coat_roughness, coat_anisotropy))


def _ss_under_coat(r, coat, coat_roughness, affect):
    return r + affect * coat * coat_roughness * (1.0 - r)


#: The OpenPBR inputs of its coat's roughening of the base, after the base's roughness and anisotropy.
COAT_ROUGHENING = ("coat_weight", "coat_roughness", "coat_roughness_anisotropy")


def ss_specular_roughness(r, a, coat, coat_roughness, coat_anisotropy):
    """Standard Surface's ``specular_roughness`` for OpenPBR's: the same anisotropic alpha product; where
    OpenPBR's coat roughens the base more than ``coat_affect_roughness`` 1 can (:func:`coat_affect_roughness`
    would pass 1), raised so that mix(r_s, 1, coat r_cs) is OpenPBR's roughened base. That raised roughness
    exceeds the plain one exactly where k would pass 1, so the result is the larger of the two."""
    plain = openpbr_roughness_to_ss(r, a)
    coat_s = coat * openpbr_roughness_to_ss(coat_roughness, coat_anisotropy)
    target = openpbr_roughness_to_ss(coat_roughened(r, coat, coat_roughness), a)
    with np.errstate(divide="ignore", invalid="ignore"):
        raised = np.clip((target - coat_s) / np.where(coat_s < 1.0, 1.0 - coat_s, 1.0), 0.0, 1.0)
    return np.maximum(plain, raised)


def coat_affect_roughness(r, a, coat, coat_roughness, coat_anisotropy):
    """The Standard Surface ``coat_affect_roughness`` that roughens the base as OpenPBR's coat does:
    OpenPBR r_b = mix(r, min(1, (r^4 + 2 r_c^4)^(1/4)), coat), then its anisotropy ``a``; Standard Surface
    r_b = mix(r_s, 1, k coat r_cs) on its own roughnesses r_s, r_cs (MaterialX's standard_surface graph), then
    its anisotropy: solved for k where both give the same alphas (:func:`openpbr_roughness_to_ss` of each),
    within [0, 1] (past 1, :func:`ss_specular_roughness` raises the base instead)."""
    ss_r = openpbr_roughness_to_ss(r, a)
    roughened = openpbr_roughness_to_ss(coat_roughened(r, coat, coat_roughness), a)
    denominator = coat * openpbr_roughness_to_ss(coat_roughness, coat_anisotropy) * (1.0 - ss_r)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(denominator > 1e-9, (roughened - ss_r) / np.where(denominator > 1e-9, denominator, 1.0), 0.0)
    return np.clip(k, 0.0, 1.0)


# -- the base under a coat, metals ----------------------------------------------------------------
#: OpenPBR inputs that decide how Standard Surface's base colour and specular weight stand for the base.
BASE_SOURCES = ("base_color",) + DARKENING_SOURCES  # base_metalness, specular_weight, subsurface_*, coat_*
SPECULAR_SOURCES = ("specular_weight", "specular_ior", "thin_film_weight", "base_color", "base_metalness",
                    "subsurface_weight", "subsurface_color", "coat_weight", "coat_darkening", "coat_ior")


def ss_base_color(color, metalness, specular_weight, subsurface, subsurface_color, coat_weight, coat_darkening,
                  coat_ior, clip=True):
    """OpenPBR's base colour darkened as OpenPBR darkens the base under its coat, and, on metals,
    times ``specular_weight``, which scales OpenPBR's metal (its F0) but not Standard Surface's
    conductor."""
    darkening = coat_darkening_factor(color, metalness, specular_weight, subsurface, subsurface_color, coat_weight,
                                      coat_darkening, fit.positive_ior(coat_ior))
    color = color * darkening * (1.0 + metalness * (specular_weight - 1.0))
    return np.clip(color, 0.0, 1.0) if clip else color


def ss_specular(specular_weight, specular_ior, film_weight, color, metalness, subsurface, subsurface_color,
                coat_weight, coat_darkening, coat_ior):
    """Standard Surface's ``specular`` for OpenPBR's (:func:`fit.dielectric_specular_scale`)."""
    darkening = coat_darkening_factor(color, metalness, specular_weight, subsurface, subsurface_color, coat_weight,
                                      coat_darkening, fit.positive_ior(coat_ior))
    scale = fit.dielectric_specular_scale(specular_ior, coat_ior, coat_weight, film_weight,
                                          np.max(darkening, axis=-1, keepdims=True))
    return fit.specular_weight_under_coat(specular_weight, scale, metalness)


def ss_specular_ior(specular_weight, specular_ior, *rest):
    """Standard Surface's ``specular_IOR``: OpenPBR's, except where the weight it needs (:func:`ss_specular`)
    exceeds Standard Surface's 1 (an HDR specular colour from glTF, say). OpenPBR raises F0 by its weight through
    the IOR (F0' = min(w F0, 1), MaterialX's open_pbr_surface.mtlx ``modulated_eta_s``, for reflection and
    refraction alike): there the IOR of F0' is written, with ``specular`` 1."""
    weight = np.asarray(ss_specular(specular_weight, specular_ior, *rest))
    if weight.ndim > np.ndim(specular_ior):  # (a constant's weight comes back as a 1-vector: the IOR's shape)
        weight = weight.reshape(weight.shape[:-1])
    ior = fit.positive_ior(specular_ior)
    raised = np.minimum(weight * fresnel.ior_to_f0(ior), 0.99999)
    return np.where(weight > 1.0 + 1e-9, fit.ior_from_f0(raised), specular_ior)


def ss_specular_color(specular_color, base_weight, color, metalness, specular_weight, subsurface, subsurface_color,
                      coat_weight, coat_darkening, coat_ior, specular_ior, film_weight, diffuse_roughness=0.0):
    """Standard Surface's ``specular_color``: the dielectric tint, and on metals the edge colour
    whose conductor has OpenPBR's reflectance at 82 degrees (:func:`fit.edge_color_for_f82_tint`),
    for the base colour written beside it (:func:`ss_base_color_rough`)."""
    reflectivity = base_weight * ss_base_color_rough(color, metalness, specular_weight, subsurface, subsurface_color,
                                                     coat_weight, coat_darkening, coat_ior, diffuse_roughness)
    specular = ss_specular(specular_weight, specular_ior, film_weight, color, metalness, subsurface, subsurface_color,
                           coat_weight, coat_darkening, coat_ior)
    return fit.edge_color_for_f82_tint(specular_color, metalness, reflectivity, specular, specular_weight)


def _ss_film(thickness):
    return np.where(thickness > 0, 1.0, 0.0)


def openpbr_specular_weight(specular, metalness, ior, coat_ior, coat, film_thickness, color, transmission=0.0):
    """Inverse of :func:`ss_specular` (Standard Surface does not darken: no darkening to undo); where the
    base takes Standard Surface's IOR relative to the coat (:func:`relative_under_coat`), ``specular`` itself.

    Standard Surface's ``specular`` does not dim its metal; OpenPBR's ``specular_weight`` does, and
    the base colour is divided by ``1 + m (w - 1)`` to compensate (:func:`openpbr_base_color`). Where
    that would ask for a metal colour above 1 (a metal with ``specular`` 0 would come out black), the
    weight is raised to the smallest value that keeps the metal's reflectivity, ``1 + m (w - 1) =
    max(base_color)``: exact for a pure metal, and the dielectric share (1 - m) then reflects more
    than Standard Surface's (MaterialX's standard_surface_to_open_pbr graph sets the weight to 1
    for any metalness above 0, losing the dielectric dimming entirely)."""
    weight = np.where(relative_under_coat(specular, metalness, ior, coat_ior, coat, film_thickness, color, transmission),
                      specular, _coated_weight(specular, metalness, ior, coat_ior, coat, film_thickness))
    peak = np.max(color, axis=-1, keepdims=np.ndim(color) >= 3)
    with np.errstate(divide="ignore", invalid="ignore"):
        floor = np.where(metalness > 0, 1.0 - (1.0 - np.minimum(peak, 1.0)) / np.where(metalness > 0, metalness, 1.0), 0.0)
    return np.where(metalness > 0, np.maximum(weight, floor), weight)


SPECULAR_WEIGHT_SOURCES = ("specular", "metalness", "specular_IOR", "coat_IOR", "coat", "thin_film_thickness",
                           "base_color", "transmission")


def relative_under_coat(specular, metalness, ior, coat_ior, coat, film_thickness, color=None, transmission=0.0):
    """Where OpenPBR's base gets the IOR whose IOR relative to the coat is Standard Surface's ``specular_IOR``
    (:func:`openpbr_specular_ior`), its weight Standard Surface's ``specular``: under a coat, Standard Surface's base
    reflects by its IOR against air (MaterialX's standard_surface.mtlx layers specular_bsdf, of ``specular_IOR``,
    under the coat), OpenPBR's relative to the coat. A weight scaled to the F0 under the coat (:func:`_coated_weight`)
    gives the same reflection while it stays within 1; past it (a base of the coat's IOR reflects nothing in OpenPBR:
    Standard Surface car paints, whose base and coat are both 1.5, lost their base highlight, 3.99 mean CIEDE2000 in
    MaterialX's GLSL; the red team's E#9) the IOR carries it. Not on a transmissive base, whose IOR also refracts."""
    scale = fit.dielectric_specular_scale(ior, coat_ior, coat, _ss_film(film_thickness))
    return (np.asarray(coat) > 0) & (np.asarray(metalness) < 1) & (np.asarray(transmission) <= 0) & \
        (np.asarray(specular) > scale + 1e-9)


def openpbr_specular_ior(ior, specular, metalness, coat_ior, coat, film_thickness, color, transmission):
    """OpenPBR's ``specular_ior``: Standard Surface's, or where :func:`relative_under_coat`, the IOR whose IOR
    relative to the coat is Standard Surface's (:func:`.fit.specular_ior_for_relative_ior`)."""
    relative = relative_under_coat(specular, metalness, ior, coat_ior, coat, film_thickness, color, transmission)
    return np.where(relative, fit.specular_ior_for_relative_ior(ior, coat_ior, coat), ior)


def _coated_weight(specular, metalness, ior, coat_ior, coat, film_thickness):
    """OpenPBR's specular weight that gives Standard Surface's F0 under the coat (before a metal's floor)."""
    scale = fit.dielectric_specular_scale(ior, coat_ior, coat, _ss_film(film_thickness))
    return fit.specular_weight_from_coated(specular, scale, metalness)


def _weight_raised(specular, metalness, ior, coat_ior, coat, film_thickness, color, transmission=0.0) -> bool:
    """Whether :func:`openpbr_specular_weight` raised a metal's weight above the coated-F0 solve (its floor)."""
    plain = _coated_weight(specular, metalness, ior, coat_ior, coat, film_thickness)
    return bool(np.any(openpbr_specular_weight(specular, metalness, ior, coat_ior, coat, film_thickness, color,
                                               transmission) > plain + 1e-9))


def openpbr_base_color(color, metalness, *weight_sources):
    specular_weight = openpbr_specular_weight(weight_sources[0], metalness, *weight_sources[1:])
    denominator = 1.0 + metalness * (specular_weight - 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.clip(np.where(denominator > 1e-9, color / np.where(denominator > 1e-9, denominator, 1.0), color), 0.0, 1.0)


def openpbr_base_color_rough(color, metalness, *rest):
    """:func:`openpbr_base_color`, then under a rough diffuse (the last source, ``diffuse_roughness``)
    darkened so OpenPBR's EON reflects the hemispherical albedo of Standard Surface's qualitative
    Oren-Nayar, on a dielectric base (:func:`fit.eon_colour_for_qon_dielectric`)."""
    return fit.eon_colour_for_qon_dielectric(openpbr_base_color(color, metalness, *rest[:-1]), rest[-1], metalness)


def _ss_rough_unclipped(color, metalness, *rest):
    brightened = fit.qon_colour_for_eon_dielectric(color, rest[-1], metalness)  # first: the inverse of the above
    return ss_base_color(brightened, metalness, *rest[:-1], clip=False)


def ss_base_color_rough(*sources):
    """:func:`ss_base_color` (``BASE_SOURCES``) of the colour that, under a rough diffuse (the last
    source, ``base_diffuse_roughness``), makes Standard Surface's qualitative Oren-Nayar reflect the
    hemispherical albedo of OpenPBR's EON (the exact inverse of :func:`openpbr_base_color_rough`);
    clipped at 1 on a metal (:func:`_metal_clipped`)."""
    return _metal_clipped(_ss_rough_unclipped(*sources), sources[1])


def _metal_clipped(color, metalness):
    """``color`` clipped to [0, 1] in linear Rec.709 where the base has metal (Standard Surface's conductor,
    an artistic IOR, takes a reflectivity below 1 there); a dielectric's colour outside Rec.709's gamut (a
    wide-gamut document's) is shaded as it is in MaterialX's working space, and its range is the written
    colour space's (target.inside, after the colour goes back into it)."""
    return np.where(np.asarray(metalness)[..., None] > 0 if np.ndim(metalness) and np.ndim(color) > np.ndim(metalness)
                    else np.asarray(metalness) > 0, np.clip(color, 0.0, 1.0), color)


THIN_SUBSURFACE_SOURCES = ("subsurface_weight", "geometry_thin_walled", "subsurface_scatter_anisotropy",
                           "base_metalness")


def _thin_split(w, thin, g, metalness):
    """Where OpenPBR's thin-walled subsurface is split (a thin wall with subsurface on a dielectric base)."""
    return (np.asarray(thin) > 0.5) & (np.asarray(w) > 0) & (np.asarray(metalness) <= 0)


def ss_subsurface(w, thin, g, metalness):
    """Standard Surface's ``subsurface``. On a thin wall OpenPBR's subsurface reflects (1 - g)/2 of
    its colour diffusely and transmits (1 + g)/2 (MaterialX's open_pbr_surface graph:
    ``subsurface_thin_walled``); Standard Surface's thin-walled subsurface only transmits (its
    translucent_bsdf), so it gets the transmitted share and the reflected share moves into the base
    colour (:func:`ss_base_color_thin`). Not on a base with metal, whose colour is the metal's."""
    return np.where(_thin_split(w, thin, g, metalness), w * 0.5 * (1.0 + g), w)


def ss_base_weight(base_weight, w, thin, g, metalness):
    """Standard Surface's ``base``: OpenPBR's, or 1 on a split thin wall (:func:`ss_subsurface`), whose
    base colour carries the weight (the subsurface's reflected share is not under OpenPBR's base weight)."""
    return np.where(_thin_split(w, thin, g, metalness), 1.0, base_weight)


def ss_base_color_thin(*sources):
    """:func:`ss_base_color_rough` (``BASE_SOURCES`` + ``base_diffuse_roughness``), and on a thin wall
    with subsurface (:func:`ss_subsurface`; then also ``base_weight`` and ``THIN_SUBSURFACE_SOURCES``)
    the colour whose diffuse reflection, beside Standard Surface's subsurface weight, reflects what
    OpenPBR's diffuse and its subsurface's reflected share do: ((1 - w) b c + w (1 - g)/2 s) / (1 - w'),
    w' the written weight, with the base weight b folded in (:func:`ss_base_weight`). At most 1 for
    inputs in range: (1 - w) b c + w (1 - g)/2 s <= 1 - w (1 + g)/2. Clipped on a metal (:func:`_metal_clipped`)."""
    return _metal_clipped(_ss_thin_unclipped(*sources), sources[1])


def _ss_thin_unclipped(*sources):
    base_sources, (base_weight, w, thin, g, metalness) = sources[:-5], sources[-5:]
    color = _ss_rough_unclipped(*base_sources)
    split = _thin_split(w, thin, g, metalness)
    if not np.any(split):
        return color
    subsurface_colour = np.maximum(base_sources[BASE_SOURCES.index("subsurface_color")], 0.0)
    written = ss_subsurface(w, thin, g, metalness)
    reflected = (1.0 - w) * base_weight * color + w * 0.5 * (1.0 - g) * subsurface_colour
    denominator = 1.0 - written  # the base weight is in the colour (ss_base_weight)
    with np.errstate(divide="ignore", invalid="ignore"):
        thin_colour = np.where(denominator > 1e-9, reflected / np.where(denominator > 1e-9, denominator, 1.0), color)
    return np.where(split, thin_colour, color)


def ss_base_clipped(*sources) -> bool:
    unclipped = _ss_thin_unclipped(*sources)
    return bool(np.any(np.abs(_metal_clipped(unclipped, sources[1]) - unclipped) > 1e-6))


def openpbr_specular_color(specular_color, base, color, metalness, *weight_sources):
    specular_weight = openpbr_specular_weight(weight_sources[0], metalness, *weight_sources[1:])
    return np.clip(fit.ss_metal_tint(specular_color, metalness, base * color, weight_sources[0], specular_weight), 0.0, 1.0)


def _dispersion_to_ss(scale, abbe):
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where((scale > 0) & (abbe > 0), abbe / np.where(scale > 0, scale, 1.0), 0.0)


def _film_thickness_nm(weight, thickness_um):
    return np.where(weight >= 0.5, thickness_um * 1000.0, 0.0)


def _peak(color):
    """The largest channel of each texel (the channel axis kept)."""
    return np.max(color, axis=-1, keepdims=True)


def _radius_colour(radius_scale):
    peak = _peak(radius_scale)
    return np.where(peak > 0, radius_scale / np.where(peak > 0, peak, 1.0), radius_scale)


def _radius_scalar(radius_scale, scale):
    return _peak(radius_scale) * scale


TO_SS = (
    Mapping("base", ("base_weight",) + THIN_SUBSURFACE_SOURCES, ss_base_weight, converted_to_default=True,
            converted="on a thin wall with subsurface, 1: the base weight is in the base colour"),
    Mapping("base_color", BASE_SOURCES + ("base_diffuse_roughness", "base_weight") + THIN_SUBSURFACE_SOURCES,
            ss_base_color_thin, keep="base_color", exact=False, matters=ss_base_clipped,
            note="a bright base colour (at this diffuse roughness, in Standard Surface's darker qualitative "
                 "Oren-Nayar, or carrying a thin wall's reflected subsurface) would exceed 1: clipped",
            converted="darkened as OpenPBR darkens the base under its coat (Standard Surface does not); on metals "
                      "times specular_weight, which Standard Surface's conductor ignores; under a rough diffuse, "
                      "brightened so the qualitative Oren-Nayar reflects what OpenPBR's EON does; on a thin wall, "
                      "with the share of the subsurface OpenPBR reflects"),
    Mapping("diffuse_roughness", ("base_diffuse_roughness",), exact=False, matters=lambda r: r > 0,
            note="OpenPBR's rough diffuse is energy-preserving Oren-Nayar (EON), Standard Surface's the "
                 "qualitative Oren-Nayar, darker at the same roughness: a dielectric base's colour is brightened so "
                 "the two reflect the same hemispherical albedo; the angular shapes still differ"),
    Mapping("metalness", ("base_metalness",)),
    Mapping("specular", SPECULAR_SOURCES, lambda *v: np.minimum(ss_specular(*v), 1.0), exact=False,
            matters=lambda *v: differs(ss_specular(*v), v[0]),
            note="OpenPBR's base reflects with its IOR relative to the coat's, and darkened, under a coat: "
                 f"Standard Surface's specular weight scales its bare reflection to the same F0 ({COAT_RESIDUAL})"),
    Mapping("specular_color", ("specular_color", "base_weight") + BASE_SOURCES + ("specular_ior", "thin_film_weight",
                                                                               "base_diffuse_roughness"),
            ss_specular_color, exact=False,
            note="a metal's edge colour is solved so that Standard Surface's conductor (artistic IOR) reflects as "
                 f"OpenPBR's F82-tint metal at 82 degrees; it reaches 90 degrees at 1 ({METAL_RESIDUAL})",
            matters=lambda c, bw, b, m, sw, *rest: m > 0 and (differs(c, WHITE) or sw != 1.0)),
    Mapping("specular_roughness", ("specular_roughness", "specular_roughness_anisotropy") + COAT_ROUGHENING,
            ss_specular_roughness, keep="specular_roughness",
            converted="roughness rescaled to keep OpenPBR's anisotropic alpha_t * alpha_b (under a coat that roughens "
                      "more than coat_affect_roughness 1 does, raised to match)"),
    Mapping("specular_anisotropy", ("specular_roughness_anisotropy",), exact=True),
    Mapping("specular_IOR", ("specular_ior", "specular_weight") + SPECULAR_SOURCES[2:],
            lambda n, w, *rest: ss_specular_ior(w, n, *rest),
            converted="a specular weight above Standard Surface's 1 folded into the IOR, as OpenPBR raises F0 by it"),
    Mapping("transmission", ("transmission_weight",)),
    Mapping("transmission_color", ("transmission_color",)),
    Mapping("transmission_depth", ("transmission_depth",)),
    Mapping("transmission_scatter", ("transmission_scatter",)),
    Mapping("transmission_scatter_anisotropy", ("transmission_scatter_anisotropy",)),
    Mapping("transmission_dispersion", ("transmission_dispersion_scale", "transmission_dispersion_abbe_number"),
            _dispersion_to_ss, converted="Abbe number / dispersion scale"),
    Mapping("subsurface", THIN_SUBSURFACE_SOURCES, ss_subsurface, exact=False,
            matters=lambda w, thin, g, m: w > 0 and thin > 0.5 and m > 0,
            note="thin-walled subsurface on a base with metal: OpenPBR's reflects half of it (by its scatter "
                 "anisotropy), Standard Surface's only transmits, and the base colour is the metal's",
            converted="on a thin wall, the share of OpenPBR's subsurface that is transmitted ((1 + anisotropy) / 2); "
                      "Standard Surface's thin-walled subsurface only transmits, the reflected share is in the base "
                      "colour"),
    Mapping("subsurface_color", ("subsurface_color",)),
    Mapping("subsurface_radius", ("subsurface_radius_scale",), _radius_colour),
    Mapping("subsurface_scale", ("subsurface_radius_scale", "subsurface_radius"), _radius_scalar),
    Mapping("subsurface_anisotropy", ("subsurface_scatter_anisotropy",)),
    Mapping("sheen", ("fuzz_weight", "fuzz_roughness"), lambda w, r: np.clip(w * fit.fuzz_albedo_scale(r), 0.0, 1.0),
            exact=False, matters=lambda w, r: w > 0,
            note=f"fuzz (Zeltner) as sheen (Conty-Kulla): weight and roughness fitted to its albedo ({SHEEN_RESIDUAL})"),
    Mapping("sheen_color", ("fuzz_color",)),
    Mapping("sheen_roughness", ("fuzz_roughness",), fit.charlie_roughness_for_fuzz,
            converted="Conty-Kulla roughness fitted to the fuzz's albedo"),
    Mapping("coat", ("coat_weight",)),
    Mapping("coat_color", ("coat_color",)),
    Mapping("coat_roughness", ("coat_roughness", "coat_roughness_anisotropy"), openpbr_roughness_to_ss,
            converted="roughness rescaled to keep the anisotropic alpha_x * alpha_y (the models square and split it "
                      "differently)"),
    Mapping("coat_anisotropy", ("coat_roughness_anisotropy",)),
    Mapping("coat_IOR", ("coat_ior",)),
    Mapping("coat_affect_roughness", ("specular_roughness", "specular_roughness_anisotropy") + COAT_ROUGHENING,
            coat_affect_roughness, converted="solved so the base under the coat is as rough as OpenPBR makes it"),
    Mapping("thin_film_thickness", ("thin_film_weight", "thin_film_thickness", "base_metalness"),
            lambda w, t, m: _film_thickness_nm(w, t), exact=False,
            note="Standard Surface has no film weight (below 0.5 the film is off, above fully on); on a metal the film "
                 "interferes over Standard Surface's artistic-IOR conductor, in OpenPBR over its F82 metal: other "
                 "colours at the same thickness (anodised titanium: 20 mean CIEDE2000 in MaterialX's GLSL, the red "
                 "team's J/F4), which the evaluator cannot judge (--verify does not fit it)",
            matters=lambda w, t, m: bool(np.any((0 < w) & (w < 1)) or (np.any(w >= 0.5) and np.any(t > 0)
                                                                         and np.any(m > 0)))),
    Mapping("thin_film_IOR", ("thin_film_ior",)),
    Mapping("emission", ("emission_luminance",), None),
    Mapping("emission_color", ("emission_color",)),
    Mapping("opacity", ("geometry_opacity",), lambda o: o * WHITE),
    Mapping("thin_walled", ("geometry_thin_walled",)),
    Mapping("normal", ("geometry_normal",)),
    Mapping("tangent", ("geometry_tangent",)),
    Mapping("coat_normal", ("geometry_coat_normal",)),
)

FROM_SS = (
    Mapping("base_weight", ("base",)),
    Mapping("base_color", ("base_color", "metalness") + SPECULAR_WEIGHT_SOURCES[:1] + SPECULAR_WEIGHT_SOURCES[2:]
            + ("diffuse_roughness",), openpbr_base_color_rough, keep="base_color",
            converted="on a metal, divided by its specular weight; under a rough diffuse, darkened so OpenPBR's "
                      "energy-preserving Oren-Nayar reflects the hemispherical albedo of the qualitative one"),
    Mapping("base_diffuse_roughness", ("diffuse_roughness",), exact=False, matters=lambda r: r > 0,
            note="Standard Surface's rough diffuse is the qualitative Oren-Nayar, OpenPBR's the energy-preserving "
                 "EON, brighter at the same roughness: a dielectric base's colour is darkened so the two reflect the "
                 "same hemispherical albedo; the angular shapes still differ"),
    Mapping("base_metalness", ("metalness",)),
    Mapping("specular_weight", SPECULAR_WEIGHT_SOURCES, openpbr_specular_weight, exact=False,
            matters=lambda s, m, n, nc, c, t, color, tr: (c > 0 and m < 1 and not bool(np.any(relative_under_coat(
                s, m, n, nc, c, t, color, tr)))) or (0 < m < 1 and _weight_raised(s, m, n, nc, c, t, color, tr)),
            note="OpenPBR's base reflects with its IOR relative to the coat's: its specular weight scaled to "
                 "Standard Surface's F0 under the coat; on a partly metallic base, raised so that the metal keeps "
                 "its reflectivity (OpenPBR's specular_weight dims metals, Standard Surface's specular does not), "
                 "so the dielectric share reflects more than Standard Surface's",
            converted="on a metal, raised so that the metal keeps its reflectivity (OpenPBR's specular_weight dims "
                      "metals, Standard Surface's specular does not); its base colour is divided by it"),
    Mapping("specular_color", ("specular_color", "base", "base_color", "metalness") + SPECULAR_WEIGHT_SOURCES[:1]
            + SPECULAR_WEIGHT_SOURCES[2:], openpbr_specular_color, exact=False, keep="specular_color",
            note="Standard Surface's metal edge colour becomes the F82 tint with its conductor's reflectance at "
                 "82 degrees (different Fresnel models)",
            matters=lambda c, b, bc, m, *rest: m > 0),
    Mapping("specular_roughness", ("specular_roughness", "specular_anisotropy", "coat", "coat_roughness",
                                   "coat_anisotropy", "coat_affect_roughness"), ss_base_roughness, exact=False,
            keep="specular_roughness", matters=lambda r, a, c, rc, ca, k: bool(np.any(fit.smoother_than_the_coat_allows(
                ss_roughness_to_openpbr(_ss_under_coat(r, c, rc, k), a), c, ss_roughness_to_openpbr(rc, ca)))),
            note="OpenPBR's coat roughens the base it covers, Standard Surface's only by coat_affect_roughness: a "
                 "base smoother than OpenPBR's coat allows is made as smooth as it gets (0; kept where any base renders "
                 "alike under that coat) and still renders rougher",
            converted="roughness rescaled to keep the anisotropic alpha_x * alpha_y, less the roughening OpenPBR's "
                      "coat adds (Standard Surface's coat leaves its base as smooth as authored, but by "
                      "coat_affect_roughness)"),
    Mapping("specular_roughness_anisotropy", ("specular_anisotropy",)),
    Mapping("specular_ior", ("specular_IOR",) + SPECULAR_WEIGHT_SOURCES[:2] + SPECULAR_WEIGHT_SOURCES[3:],
            openpbr_specular_ior,
            converted="Standard Surface's base reflects by its IOR against air under its coat, OpenPBR's relative to "
                      "the coat: where a weight cannot carry it, the base IOR is set so that its IOR relative to the coat "
                      "is Standard Surface's specular_IOR, the weight to its specular (an opaque base: the IOR refracts "
                      "nothing)"),
    Mapping("transmission_weight", ("transmission",)),
    Mapping("transmission_color", ("transmission_color",)),
    Mapping("transmission_depth", ("transmission_depth",)),
    Mapping("transmission_scatter", ("transmission_scatter",)),
    Mapping("transmission_scatter_anisotropy", ("transmission_scatter_anisotropy",)),
    Mapping("transmission_dispersion_scale", ("transmission_dispersion",), lambda v: np.where(v > 0, 1.0, 0.0)),
    Mapping("transmission_dispersion_abbe_number", ("transmission_dispersion",), lambda v: np.where(v > 0, v, 20.0)),
    Mapping("subsurface_weight", ("subsurface",)),
    Mapping("subsurface_color", ("subsurface_color",)),
    Mapping("subsurface_radius", ("subsurface_radius", "subsurface_scale"), lambda c, s: _peak(c) * s),
    Mapping("subsurface_radius_scale", ("subsurface_radius",), _radius_colour),
    Mapping("subsurface_scatter_anisotropy", ("subsurface_anisotropy", "thin_walled", "subsurface"),
            lambda a, thin, w: np.where((thin > 0.5) & (w > 0), 1.0, a), exact=False,
            matters=lambda a, thin, w: thin > 0.5 and w > 0 and a != 1.0,
            note="Standard Surface's thin-walled subsurface only transmits (its anisotropy has no effect there); "
                 "OpenPBR's does so at scatter anisotropy 1"),
    Mapping("fuzz_weight", ("sheen", "sheen_roughness"),
            lambda w, r: np.clip(w / fit.fuzz_albedo_scale(fit.fuzz_roughness_for_charlie(r)), 0.0, 1.0), exact=False,
            note=f"sheen (Conty-Kulla) as fuzz (Zeltner): weight and roughness fitted to its albedo ({SHEEN_RESIDUAL})",
            matters=lambda w, r: w > 0),
    Mapping("fuzz_color", ("sheen_color",)),
    Mapping("fuzz_roughness", ("sheen_roughness",), fit.fuzz_roughness_for_charlie,
            converted="Zeltner roughness fitted to the sheen's albedo"),
    Mapping("coat_weight", ("coat",)),
    Mapping("coat_darkening", ("coat",), lambda w: 0.0, when=lambda w: w > 0,
            converted="Standard Surface does not darken under a coat: OpenPBR's darkening switched off"),
    Mapping("coat_color", ("coat_color",)),
    Mapping("coat_roughness", ("coat_roughness", "coat_anisotropy"), ss_roughness_to_openpbr,
            converted="roughness rescaled to keep the anisotropic alpha_x * alpha_y (the models square and split it "
                      "differently)"),
    Mapping("coat_roughness_anisotropy", ("coat_anisotropy",)),
    Mapping("coat_ior", ("coat_IOR",)),
    Mapping("thin_film_weight", ("thin_film_thickness",), lambda t: np.where(t > 0, 1.0, 0.0),
            otherwise=(1.0, "where the thickness is 0 a film of weight 1 is no film (OpenPBR; MaterialX's "
                            "thin-film BSDFs apply only a thickness above 0), as MaterialX's translation graph "
                            "writes it (ifgreater)")),
    Mapping("thin_film_thickness", ("thin_film_thickness", "metalness"), lambda t, m: t / 1000.0,
            converted="nanometres to micrometres", exact=False, matters=lambda t, m: bool(np.any(t > 0) and np.any(m > 0)),
            note="nanometres to micrometres; on a metal the film interferes over Standard Surface's artistic-IOR "
                 "conductor, in OpenPBR over its F82 metal: other colours (the evaluator and MaterialX's GLSL: 6-9 "
                 "mean CIEDE2000 on a green metal under 430 nm)"),
    Mapping("thin_film_ior", ("thin_film_IOR",)),
    Mapping("emission_luminance", ("emission",)),
    Mapping("emission_color", ("emission_color",)),
    Mapping("geometry_opacity", ("opacity",), lambda o: np.mean(o, axis=-1, keepdims=True), exact=False,
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
    # (the red team's F-03: both were dropped without a note)
    Dropped("specular_rotation", "OpenPBR turns the anisotropy with geometry_tangent, a vector in world space, which "
            "a rotation in the surface's UV frame does not give", matters=lambda r, a: bool(np.any((r % 0.5 != 0) & (a > 0))),
            needs=("specular_anisotropy",)),
    Dropped("coat_rotation", "OpenPBR turns the coat's anisotropy with geometry_coat_tangent, a vector in world space, "
            "which a rotation in the surface's UV frame does not give",
            matters=lambda r, a: bool(np.any((r % 0.5 != 0) & (a > 0))), needs=("coat_anisotropy",)),
)


def _hdr_peak(color):
    """How far an emission colour's brightest channel exceeds 1 (1 when it does not): OpenPBR 1.1.1's
    emission_color may exceed 1 (an HDR multiplier), Standard Surface's is a colour in [0, 1] times
    its unbounded ``emission`` weight, so the excess moves into the weight (the product renders)."""
    return np.maximum(_peak(color), 1.0) if np.ndim(color) >= 3 else np.maximum(np.max(color, axis=-1), 1.0)


def _emission(mappings, settings: Settings, to_ss: bool):
    factor = 1.0 / settings.nits_per_unit if to_ss else settings.nits_per_unit
    note = (f"{'nits to a unitless weight' if to_ss else 'a unitless weight to nits'} at "
            f"{settings.nits_per_unit:g} nit(s) per unit")
    if not to_ss:
        return tuple(Mapping(m.target, m.sources, lambda v, f=factor: v * f, converted=note)
                     if m.target == "emission_luminance" else m for m in mappings)
    hdr = "; an emission colour above 1 is normalised and its peak moves into the weight"
    replaced = {
        "emission": Mapping("emission", ("emission_luminance", "emission_color"),
                            lambda v, c, f=factor: v * f * _hdr_peak(c), converted=note + hdr),
        "emission_color": Mapping("emission_color", ("emission_color",),
                                  lambda c: c / (_hdr_peak(c)[..., None] if np.ndim(c) < 3 else _hdr_peak(c)),
                                  converted="an emission colour above 1 normalised (its peak moves into emission)"),
    }
    return tuple(replaced.get(m.target, m) for m in mappings)


def openpbr_to_standard_surface(material: Material, settings: Settings | None = None) -> Translation:
    settings = settings or Settings()
    label = "OpenPBR -> Standard Surface"
    values = Values(material, tables.table_known(material.model, material.version))
    tint = ss_metal_weight.coat_tint(material, values) if settings.metal_weight_tint else None
    if tint is None:
        translation = translate(material, "standard_surface", _emission(TO_SS, settings, True), DROPPED_TO_SS, settings,
                                label)
    else:
        translation = ss_metal_weight.dimmed(translate(ss_metal_weight.undimmed(material), "standard_surface", _emission(
            TO_SS, settings, True), DROPPED_TO_SS, settings, label), material, values, tint, settings.context, label)
    return ss_metal_weight.fuzz_over_metal(translation, material, values, settings.context, label)


def standard_surface_to_openpbr(material: Material, settings: Settings | None = None) -> Translation:
    settings = settings or Settings()
    rotations = ss_rotation.carried(material, settings.node_graphs)
    written = {rotation for rotation, _, _ in rotations.values()}
    translation = translate(material, "open_pbr_surface", _emission(FROM_SS, settings, False),
                            tuple(d for d in DROPPED_FROM_SS if d.source not in written), settings,
                            "Standard Surface -> OpenPBR")
    translation.diagnostics += ss_rotation.apply(material, translation.material, rotations, settings.context,
                                                 f"{material.name} (Standard Surface -> OpenPBR)")
    return translation
