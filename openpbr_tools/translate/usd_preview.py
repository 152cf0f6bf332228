"""OpenPBR Surface 1.1.1 <-> UsdPreviewSurface 2.6 (metallic workflow; the specular workflow is read).

UsdPreviewSurface is the lowest common denominator every USD renderer draws: a diffuse lobe, one
GGX specular lobe (metallic or specular workflow), a clear coat, emission and opacity.

Exact:
  * metalness, IOR of an uncoated base with specular weight 1, roughness of an isotropic base (both
    alpha = roughness^2), clear coat weight and roughness, normal maps, opacity; the base colour of
    an opaque dielectric (``base_weight * base_color``).

Approximated (reported when visible; residuals are mean CIEDE2000 on the evaluator's lit sphere,
before -> after the fits of :mod:`.fit`, from ``openpbr convert --verify``):
  * the preview's one ``ior`` gives the F0 of its base and of its clear coat (spec: "including the
    clearcoat"): it is solved so that coat plus base reflect as OpenPBR's at normal incidence, with
    OpenPBR's coat IOR, its base's IOR relative to the coat and its ``specular_weight``
    (:func:`.fit.preview_ior`); on a metal, whose preview F0 is its colour, it is the coat's IOR.
    Coming back, the coat's IOR is the preview's ior and the base's IOR the one whose relative IOR
    under it gives the preview's base F0 (it round-trips the preview's ior exactly);
  * OpenPBR's darkening of the base under its coat and the coat's colour are folded into the
    diffuse colour (the preview's clear coat is colourless and does not darken; coming back,
    ``coat_darkening`` is 0). Coated plastics and ceramics 0.3-1.3 (3.8-31.3), the car paint sample
    2.5 (8.7), coated metals 0.4 (7.2-29.3), coated glass 3.8 (3.4);
  * a metal: the preview's has F0 = F90 = its colour; the colour is the least-squares fit of
    OpenPBR's F82-tint metal's albedo with its specular weight (:func:`.fit.constant_metal_reflectance`),
    inverted exactly coming back (untinted). Tinted metals 0.1-1.4 (0.1-1.4), specular weight
    0.6-0.8 on metals 0.2-0.7 (4.9-9.4);
  * anisotropy: the preview's isotropic roughness keeps the geometric mean of OpenPBR's alphas;
  * transmission: the preview has no refraction; glass becomes opacity 1 - transmission_weight
    (the reflection stays, the refracted image becomes see-through), of the dielectric part only:
    1 - transmission_weight (1 - base_metalness), as OpenPBR's metal covers its transmission;
  * ``specular_color`` (the metallic workflow has no tint), subsurface (folded into the diffuse colour);
  * emission: ``emissiveColor`` = ``emission_color * emission_luminance / nits_per_unit``, times what
    OpenPBR's coat does to it (its tint and Fresnel transmission, averaged over the visible disk:
    :func:`openpbr_tools.evaluate.coat.coat_emission_factor`), which the preview's clear coat does not do;
    divided by it coming back.

Not carried (reported): fuzz, thin film, dispersion, diffuse roughness, volume colour.
Reading the preview's opacity: in its default "transparent" mode a glass keeps its reflections, so
``1 - opacity`` becomes ``transmission_weight`` (geometry_opacity 1); "presence" mode and a cut-out
threshold become ``geometry_opacity``.
Reading a specular-workflow preview: ``specularColor`` is the F0 colour (white edge) over ``diffuseColor``;
the two become OpenPBR's mix of a metal and a dielectric (:mod:`.specular_workflow`: exact for a grey F0,
a copper-coloured F0 over a dark diffuse is the metal). ``Settings.specular_split`` off gives the earlier
reading, an IOR of the F0 colour's luminance and ``specular_color`` S / max(S), which the candidate search
(:func:`.candidates.alternative_reading`) weighs beside the split for constant materials.
"""

from __future__ import annotations

import numpy as np

from .. import colorspaces
from ..evaluate.coat import coat_absorption, coat_darkening_factor, coat_emission_factor
from ..evaluate.microfacet import openpbr_alphas
from ..model import Constant, Input, Material
from ..rules.translation import APPROXIMATED, CONVERTED
from . import fit, specular_workflow
from .coat_facts import COAT_EMISSION_NOTE, COAT_EMISSION_UNDONE, EMISSION_UNDER_COAT
from .common import Dropped, Mapping, Settings, Translation, differs, translate

WHITE = np.ones(3)
#: Measured residuals, mean CIEDE2000 on the evaluator's lit sphere (module docstring).
COAT_RESIDUAL = "measured ΔE2000 0.3-1.3 on coated plastics, 2.5 on a coated car paint"
METAL_RESIDUAL = "measured ΔE2000 up to 1.4 on tinted metals"


def preview_roughness(r, a):
    alpha_t, alpha_b = openpbr_alphas(r, a)
    return (alpha_t * alpha_b) ** 0.25


ior_from_f0 = fit.ior_from_f0

DIFFUSE_SOURCES = ("base_weight", "base_color", "subsurface_weight", "subsurface_color", "base_metalness",
                   "specular_weight", "coat_weight", "coat_darkening", "coat_ior", "coat_color", "specular_color",
                   "specular_roughness", "specular_roughness_anisotropy")


def _darkening(color, subsurface, subsurface_color, metalness, specular_weight, coat_weight, coat_darkening, coat_ior):
    return coat_darkening_factor(color, metalness, specular_weight, subsurface, subsurface_color, coat_weight,
                                 coat_darkening, fit.positive_ior(coat_ior))


def preview_diffuse_color(weight, color, subsurface, subsurface_color, metalness, specular_weight, coat_weight,
                          coat_darkening, coat_ior, coat_color, specular_color, roughness, anisotropy):
    """The preview's ``diffuseColor``: the base (subsurface mixed in) darkened and tinted as OpenPBR's
    coat darkens and absorbs (the preview's clear coat does neither), and on metals the constant
    reflectance (the preview's metal has F0 = F90 = diffuseColor) fitted to OpenPBR's F82-tint
    metal (:func:`fit.constant_metal_reflectance`). Mixed at OpenPBR's metalness, not split as glTF's is
    (:func:`fit.split_metal`): the evaluator (the preview's metal with F0 = F90 = its colour, as Storm shades it)
    rates the split better on 30 dimmed metals (1.79 -> 1.01 mean CIEDE2000), but MaterialX's GLSL UsdPreviewSurface
    rendered 4 of them worse, one by 9.4 (tests/benchmarks/bench_metal_split_glsl.py --target UsdPreviewSurface)."""
    darkening = _darkening(color, subsurface, subsurface_color, metalness, specular_weight, coat_weight,
                           coat_darkening, coat_ior)
    under = darkening * coat_absorption(coat_color, coat_weight)
    # base_weight weighs the diffuse lobe only; the metal's F0 is base_weight * base_color (no subsurface)
    dielectric = (weight * color + subsurface * (subsurface_color - weight * color)) * under
    metal = fit.fitted_metal(weight * color * under, specular_color, specular_weight,
                             preview_roughness(roughness, anisotropy) ** 2, "constant")
    return np.clip(dielectric + metalness * (metal - dielectric), 0.0, 1.0)


def _diffuse_matters(weight, color, subsurface, subsurface_color, metalness, specular_weight, coat_weight,
                     coat_darkening, coat_ior, coat_color, specular_color, *roughness):
    return bool(subsurface > 0 or metalness > 0 or (coat_weight > 0 and differs(coat_color, WHITE)))


IOR_SOURCES = ("specular_ior", "specular_weight", "coat_ior", "coat_weight", "base_metalness")


def preview_specular_ior(specular_ior, specular_weight, coat_ior, coat_weight, metalness):
    """The preview's ``ior``, which gives the F0 of its dielectric base and of its clear coat: on
    dielectrics :func:`fit.preview_ior`, on metals (whose preview F0 is the colour) the coat's IOR
    under a coat, else the base's."""
    dielectric = fit.preview_ior(specular_weight, specular_ior, coat_ior, coat_weight)
    metal = np.where(coat_weight > 0, coat_ior, specular_ior)
    return dielectric + metalness * (metal - dielectric)


#: How a specular-workflow preview's lobe takes light from its diffuse (:mod:`.specular_workflow`).
SPECULAR_STRENGTH = specular_workflow.STRENGTH["UsdPreviewSurface"]
SPLIT_NOTE = ("the specular workflow's F0 colour and diffuse colour become a metal share and a dielectric one "
              "(one base colour, one metalness: the spec-gloss -> metal-rough solve of Babylon.js and glTF-Toolkit, "
              "dielectric F0 the specular colour's smallest channel; exact for a grey specular colour)")


#: What the preview -> OpenPBR mappings say of an ior below 1 (the red team's C2: OpenUSD's nativeClearcoat with ior
#: 0.5 became an OpenPBR coat and base of IOR 0.5, 14.4 mean CIEDE2000 off; with the reciprocal 0.29)
BELOW_ONE = ("an ior below 1 is written as its reciprocal, which has the same F0: the preview's Fresnel is the same "
             "for n and 1 / n, OpenPBR's below 1 is a medium denser outside (a bubble)")


def _reciprocal_below_one(ior):
    """1 / n for an IOR in (0, 1), else n."""
    ior = np.asarray(ior, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where((ior > 0.0) & (ior < 1.0), 1.0 / np.where(ior > 0.0, ior, 1.0), ior)


def _metalness(metallic, workflow, diffuse, specular):
    """OpenPBR's metalness: the preview's in the metallic workflow, the split's in the specular one."""
    split_metalness, _, _ = specular_workflow.split(diffuse, specular, SPECULAR_STRENGTH)
    return np.where(workflow >= 1, split_metalness, metallic)


def _coloured(colour) -> bool:
    """Whether any texel of ``colour`` (..., 3) has unequal channels (a grey F0 splits exactly)."""
    colour = np.asarray(colour, dtype=np.float64)
    return bool(np.any(np.ptp(colour, axis=-1) > 1e-6)) if colour.shape[-1:] == (3,) else False


PRESENCE_CAVEAT = "UsdPreviewSurface 2.6; a reader older than 2.6 shows it as a see-through glass that keeps its reflections"


def to_usd_mappings(settings: Settings, presence_over_transmission: bool = False) -> tuple[Mapping, ...]:
    """The OpenPBR -> UsdPreviewSurface mappings; ``presence_over_transmission``: the opacity is written in
    presence mode although the material transmits (:func:`_opacity_mode`), so it is geometry_opacity alone."""
    nits = settings.nits_per_unit
    opacity = Mapping("opacity", ("geometry_opacity", "transmission_weight", "base_metalness"),
                      lambda o, t, m: o * (1.0 - t * (1.0 - m)), exact=False, matters=lambda o, t, m: t * (1.0 - m) > 0,
                      site="transmission_weight",
                      note="no refraction in UsdPreviewSurface: transmission becomes transparency (of the dielectric "
                           "part only: OpenPBR's metal covers it by base_metalness)")
    if presence_over_transmission:
        opacity = Mapping("opacity", ("geometry_opacity", "transmission_weight", "base_metalness"), lambda o, t, m: o,
                          exact=False,
                          note=f"geometry_opacity written in opacityMode 'presence' ({PRESENCE_CAVEAT}); the preview's "
                               "one opacity cannot also hold the transmission, which shows as the base on the part "
                               "that is present (the smaller error here: the surface is mostly absent)")
    return (
        Mapping("diffuseColor", DIFFUSE_SOURCES, preview_diffuse_color, keep="base_color", exact=False, matters=_diffuse_matters,
                note="subsurface, and the coat's darkening and colour (the preview's clear coat is colourless and "
                     "does not darken), folded into the diffuse colour; on a metal it is the constant reflectance "
                     "(F0 = F90) fitted to OpenPBR's metal with its F82 edge tint and specular weight "
                     f"({METAL_RESIDUAL})"),
        Mapping("metallic", ("base_metalness",)),
        Mapping("roughness", ("specular_roughness", "specular_roughness_anisotropy"), preview_roughness, keep="specular_roughness", exact=False,
                matters=lambda r, a: a > 0, note="anisotropy dropped: isotropic roughness keeps the geometric mean of the alphas"),
        Mapping("ior", IOR_SOURCES, preview_specular_ior, exact=False,
                matters=lambda *v: differs(preview_specular_ior(*v), v[0]),
                note="the preview's one ior gives the F0 of its base and of its clear coat: solved so that coat plus "
                     "base reflect as OpenPBR's at normal incidence (specular_weight, the coat's IOR and the base's "
                     f"IOR relative to it included; {COAT_RESIDUAL})"),
        Mapping("clearcoat", ("coat_weight",)),
        Mapping("clearcoatRoughness", ("coat_roughness",)),
        Mapping("emissiveColor", EMISSION_UNDER_COAT,
                lambda c, l, w, cc, ci: c * coat_emission_factor(cc, w, ci) * l / nits, exact=False,
                matters=lambda c, l, w, *coat: l > 0 and w > 0, note=COAT_EMISSION_NOTE,
                converted=f"emission_color * emission_luminance at {nits:g} nit(s) per unit"),
        opacity,
        Mapping("normal", ("geometry_normal",)),
    )


DROPPED_TO_USD = (
    Dropped("specular_color", "the metallic workflow has no specular tint", matters=lambda c: differs(c, WHITE)),
    Dropped("fuzz_weight", "UsdPreviewSurface has no sheen", matters=lambda w: w > 0),
    Dropped("thin_film_weight", "UsdPreviewSurface has no thin film", matters=lambda w: w > 0),
    Dropped("transmission_color", "UsdPreviewSurface has no transmission tint",
            matters=lambda c, t: t > 0 and differs(c, WHITE), needs=("transmission_weight",)),
    Dropped("transmission_dispersion_scale", "UsdPreviewSurface has no dispersion", matters=lambda s: s > 0),
    Dropped("base_diffuse_roughness", "UsdPreviewSurface's diffuse is Lambertian", matters=lambda r: r > 0),
    Dropped("subsurface_weight", "UsdPreviewSurface has no subsurface scattering: the subsurface colour is mixed into "
                                 "the diffuse colour (no light travels under the surface)", matters=lambda w: w > 0),
    Dropped("subsurface_radius_scale", "UsdPreviewSurface has no subsurface scattering", matters=lambda r, w: w > 0,
            needs=("subsurface_weight",)),
    Dropped("geometry_coat_normal", "UsdPreviewSurface's coat uses the base normal"),
    Dropped("geometry_tangent", "UsdPreviewSurface has no tangent input"),
    # (the audit's F1: these were read by no mapping and named by no drop, so they vanished without a word)
    Dropped("geometry_coat_tangent", "UsdPreviewSurface has no tangent input"),
    Dropped("coat_roughness_anisotropy", "UsdPreviewSurface's clear coat is isotropic",
            matters=lambda a, w: a > 0 and w > 0, needs=("coat_weight",)),
    Dropped("geometry_thin_walled", "UsdPreviewSurface has no thin-walled mode: a thin wall's subsurface "
                                    "translucency is lost (its transparency refracts nothing either way)",
            matters=lambda thin, w: bool(thin) and w > 0, needs=("subsurface_weight",)),
    Dropped("transmission_depth", "UsdPreviewSurface has no volume: the medium's absorption and scattering over this "
                                  "depth are lost", needs=("transmission_weight", "transmission_color", "transmission_scatter"),
            matters=lambda d, w, c, scatter: w > 0 and d > 0 and (differs(c, WHITE) or np.max(scatter) > 0)),
    Dropped("transmission_scatter", "UsdPreviewSurface has no volume scattering",
            matters=lambda scatter, w, d: w > 0 and d > 0 and np.max(scatter) > 0,
            needs=("transmission_weight", "transmission_depth")),
    Dropped("transmission_scatter_anisotropy", "UsdPreviewSurface has no volume scattering",
            matters=lambda g, w, d, scatter: w > 0 and d > 0 and np.max(scatter) > 0 and g != 0,
            needs=("transmission_weight", "transmission_depth", "transmission_scatter")),
    Dropped("transmission_dispersion_abbe_number", "UsdPreviewSurface has no dispersion",
            matters=lambda v, scale, w: scale > 0 and w > 0,
            needs=("transmission_dispersion_scale", "transmission_weight")),
    Dropped("subsurface_radius", "UsdPreviewSurface has no subsurface scattering", matters=lambda r, w: w > 0,
            needs=("subsurface_weight",)),
    Dropped("subsurface_scatter_anisotropy", "UsdPreviewSurface has no subsurface scattering",
            matters=lambda g, w: w > 0 and g != 0, needs=("subsurface_weight",)),
)


def from_usd_mappings(settings: Settings) -> tuple[Mapping, ...]:
    nits = settings.nits_per_unit

    split = settings.specular_split

    def specular_ior(workflow, specular, diffuse, ior, clearcoat):
        # The base's F0 (specular workflow: the dielectric share's, :mod:`.specular_workflow`, or in the
        # luminance reading the specular colour's luminance; metallic: from ior) is the F0 of OpenPBR's base
        # relative to its coat, whose IOR is the preview's ior.
        dielectric_f0 = specular_workflow.split(diffuse, specular, SPECULAR_STRENGTH)[2] if split else \
            np.sum(specular * np.asarray(colorspaces.REC709_LUMINANCE), axis=-1, keepdims=True)
        ior = _reciprocal_below_one(ior)
        relative = np.where(workflow >= 1, ior_from_f0(dielectric_f0), ior)
        return fit.specular_ior_for_relative_ior(relative, ior, clearcoat)

    def base_color(diffuse, metallic, workflow, roughness, specular):
        metalness = np.where(workflow >= 1, 0.0, metallic)
        metallic_workflow = fit.openpbr_metal_from_constant(diffuse, metalness, WHITE, 1.0, roughness ** 2)
        if not split:
            return metallic_workflow
        return np.where(workflow >= 1, specular_workflow.split(diffuse, specular, SPECULAR_STRENGTH)[1], metallic_workflow)

    def metalness(specular, diffuse, metallic, workflow):
        return _metalness(metallic, workflow, diffuse, specular) if split else np.where(workflow >= 1, 0.0, metallic)

    def specular_tint(workflow, specular):  # the luminance reading's: S / max(S), which also tints the edge
        peak = np.max(specular, axis=-1, keepdims=True)
        return np.where(workflow >= 1, np.where(peak > 0, specular / np.where(peak > 0, peak, 1.0), WHITE), WHITE)

    def emission_color(color):
        peak = np.max(color, axis=-1, keepdims=True)
        return np.where(peak > 0, color / np.where(peak > 0, peak, 1.0), WHITE)

    # Only OpenPBR's dielectric transmits (its metal covers the transmission by base_metalness), while
    # the preview's transparency covers the metal too: a transparency 1 - opacity of a metal m takes
    # transmission (1 - opacity) / (1 - m) where that is at most 1; beyond, transmission 1 and the rest as
    # geometry_opacity (opacity / m). to_usd_mappings' opacity is the inverse.
    def _transparent(opacity, threshold, mode, metallic, workflow, diffuse, specular):
        seen = (threshold <= 0) & (mode < 1)
        return seen, np.where(seen, 1.0 - opacity, 0.0), 1.0 - metalness(specular, diffuse, metallic, workflow)

    def presence(opacity, threshold, mode, metallic, workflow, diffuse, specular):
        seen, wanted, room = _transparent(opacity, threshold, mode, metallic, workflow, diffuse, specular)
        plain = np.where(threshold > 0, np.where(opacity >= threshold, 1.0, 0.0), np.where(mode >= 1, opacity, 1.0))
        beyond = seen & (wanted > room + 1e-12)
        return np.where(beyond, opacity / np.where(room < 1.0, 1.0 - room, 1.0), plain)

    def transparency(opacity, threshold, mode, metallic, workflow, diffuse, specular):
        seen, wanted, room = _transparent(opacity, threshold, mode, metallic, workflow, diffuse, specular)
        return np.where(seen & (room > 0), np.minimum(wanted / np.where(room > 0, room, 1.0), 1.0), 0.0)

    return (
        Mapping("base_color", ("diffuseColor", "metallic", "useSpecularWorkflow", "roughness", "specularColor"),
                base_color, keep="diffuseColor", exact=False, matters=lambda d, m, w, r, s: split and w >= 1 and _coloured(s),
                note=SPLIT_NOTE, converted="a metal's constant reflectance (F0 = F90) fitted by OpenPBR's F82 metal"),
        Mapping("base_metalness", ("specularColor", "diffuseColor", "metallic", "useSpecularWorkflow"), metalness,
                exact=False, matters=lambda s, d, m, w: split and w >= 1 and _coloured(s), note=SPLIT_NOTE),
        Mapping("specular_roughness", ("roughness",)),
        Mapping("specular_ior", ("ior", "useSpecularWorkflow", "specularColor", "diffuseColor", "clearcoat"),
                lambda i, w, s, d, c: specular_ior(w, s, d, i, c), converted=BELOW_ONE,
                exact=False, matters=lambda i, w, s, d, c: w >= 1 or c > 0, site="specularColor",
                note="the base's F0 (metallic workflow: from the preview's ior; specular workflow: " + (
                     "the F0 of the dielectric share, the specular colour's smallest channel; the dielectric's Fresnel "
                     "curve is not quite Schlick's" if split else "the F0 colour's luminance, with a tint")
                     + ") is OpenPBR's base relative to the clear coat, whose IOR is the preview's ior"),
        *(() if split else (Mapping("specular_color", ("useSpecularWorkflow", "specularColor"), specular_tint),)),
        Mapping("coat_weight", ("clearcoat",)),
        Mapping("coat_roughness", ("clearcoatRoughness",)),
        Mapping("coat_ior", ("ior", "clearcoat"), lambda n, c: _reciprocal_below_one(n), when=lambda n, c: c > 0,
                converted="the preview's clear coat has the preview's ior; " + BELOW_ONE),
        Mapping("coat_darkening", ("clearcoat",), lambda c: 0.0, when=lambda c: c > 0,
                converted="the preview does not darken under its clear coat"),
        Mapping("emission_color", ("emissiveColor", "clearcoat", "ior"),
                lambda c, w, n: emission_color(c / coat_emission_factor(1.0, w, n))),
        Mapping("emission_luminance", ("emissiveColor", "clearcoat", "ior"),
                lambda c, w, n: np.max(c / coat_emission_factor(1.0, w, n), axis=-1, keepdims=True) * nits,
                converted=f"nits at {nits:g} nit(s) per unit; {COAT_EMISSION_UNDONE}"),
        Mapping("geometry_opacity", OPACITY_SOURCES, presence, exact=False, matters=lambda o, t, m, *w: t > 0,
                note="an opacity threshold becomes a binary opacity"),
        Mapping("transmission_weight", OPACITY_SOURCES, transparency, exact=False,
                matters=lambda o, t, m, *w: t <= 0 and m < 1 and o < 1,
                note="the preview's transparent opacity keeps its specular reflection; OpenPBR's transmission "
                     "refracts what the preview shows see-through"),
        Mapping("geometry_normal", ("normal",)),
    )


#: UsdPreviewSurface's opacity, read by its mode (spec 2.6, "opacityMode"; MaterialX 1.39.5's
#: ND_UsdPreviewSurface graph): "transparent" (0, the default) keeps the lighting ("even a fully
#: transparent object still receives lighting as, for example, perfectly clear glass still has a
#: specular response"), so 1 - opacity is OpenPBR transmission; "presence" (1) is OpenPBR's
#: geometry_opacity; a non-zero opacityThreshold cuts out in either mode.
OPACITY_SOURCES = ("opacity", "opacityThreshold", "opacityMode", "metallic", "useSpecularWorkflow", "diffuseColor",
                   "specularColor")

DROPPED_FROM_USD = (
    Dropped("occlusion", "OpenPBR has no ambient occlusion input", matters=lambda v: v != 1.0),
    Dropped("displacement", "OpenPBR is a surface shader; displacement belongs to a displacement shader",
            matters=lambda v: v != 0.0),
)


def openpbr_to_usd_preview(material: Material, settings: Settings | None = None) -> Translation:
    settings = settings or Settings()
    mode = _opacity_mode(material)
    translation = translate(material, "UsdPreviewSurface",
                            to_usd_mappings(settings, presence_over_transmission=mode == "presence over transmission"),
                            DROPPED_TO_USD, settings, "OpenPBR -> UsdPreviewSurface")
    entry = material.inputs.get("geometry_opacity")
    label = f"{material.name} (OpenPBR -> UsdPreviewSurface)"
    if mode in ("presence", "presence over transmission"):
        translation.material.inputs["opacityMode"] = Input("opacityMode", "integer", Constant(1), entry.location)
    if mode == "presence":
        translation.diagnostics.append(settings.context.diagnostic(
            CONVERTED, f"{label}: opacity: geometry_opacity written in opacityMode 'presence' ({PRESENCE_CAVEAT})",
            entry.location))
    elif mode == "transparent":
        translation.diagnostics.append(settings.context.diagnostic(
            APPROXIMATED, f"{label}: opacity: the preview's one opacity cannot be both OpenPBR's presence "
                          "(geometry_opacity) and its transmission: folded into a transparent opacity, which keeps "
                          "the reflection and emission that geometry_opacity removes", entry.location))
    return translation


def _opacity_mode(material: Material) -> str | None:
    """How OpenPBR's ``geometry_opacity`` (presence: below 1 the surface, its reflections and emission
    included, is partly absent) goes to the preview, whose default "transparent" opacity keeps
    reflections and emission (a glass) and whose "presence" mode (spec 2.6) is OpenPBR's:

    * ``None``: opaque (geometry_opacity 1 or unset);
    * "presence": nothing transmits: presence mode, exact;
    * "presence over transmission": the material also transmits, and one opacity cannot hold both.
      Presence mode misshows the share o t (1 - m) of the surface that transmits (as its base), the
      transparent product the absent share 1 - o (as reflections and emission); presence where its
      error is the smaller (constant values; a full transmission excluded: a glass partly absent, and
      what the reader makes of a transparency beyond the dielectric's share, transmission 1 plus
      geometry_opacity, so the way back is exact);
    * "transparent": otherwise, the transparent product, reported at geometry_opacity."""
    entry = material.inputs.get("geometry_opacity")
    if entry is None or (isinstance(entry.value, Constant) and not _below_one(entry.value.value)):
        return None
    entries = [material.inputs.get(name) for name in ("transmission_weight", "base_metalness")]
    weight, metal = (e.value.value if e is not None and isinstance(e.value, Constant) else (0.0 if e is None else None)
                     for e in entries)  # None: textured or connected, not known here
    if weight is None or metal is None:
        return "transparent"
    transmits = float(weight) * (1.0 - float(metal))
    if not transmits > 0.0:
        return "presence"
    presence = float(entry.value.value) if isinstance(entry.value, Constant) else None
    if presence is not None and float(weight) < 1.0 and presence * transmits < 1.0 - presence:
        return "presence over transmission"
    return "transparent"


def _below_one(value) -> bool:
    try:
        return float(value) < 1.0
    except (TypeError, ValueError):
        return True  # not a number: not known to be opaque


def usd_preview_to_openpbr(material: Material, settings: Settings | None = None) -> Translation:
    settings = settings or Settings()
    return translate(material, "open_pbr_surface", from_usd_mappings(settings), DROPPED_FROM_USD, settings,
                     "UsdPreviewSurface -> OpenPBR")
