"""OpenPBR Surface 1.1.1 <-> glTF 2.0 PBR (core and KHR_materials_*), as MaterialX's ``gltf_pbr`` node.

Values here stay in the source document's colour space and scene units; the glTF writer converts
colours to linear Rec.709 and the glTF reader reports glTF's (factors linear Rec.709, lengths in
metres). Lengths are converted with ``Settings.meters_per_unit``.

Exact:
  * metalness, IOR (KHR_materials_ior), the coat weight and roughness (KHR_materials_clearcoat),
    thin film as iridescence (KHR_materials_iridescence: weight, IOR, thickness micrometres <->
    nanometres), opacity (alpha, BLEND below 1), normal maps, dispersion (KHR_materials_dispersion:
    dispersion = 20 / V, with OpenPBR's scale: 20 * scale / V);
  * roughness and anisotropy (KHR_materials_anisotropy: alpha_t = mix(alpha, 1, s^2),
    alpha_b = alpha, alpha = r_g^2). OpenPBR's alpha_t = r^2 sqrt(2 / (1 + (1 - a)^2)) and
    alpha_b = (1 - a) alpha_t give r_g = sqrt(alpha_b) and s = sqrt((alpha_t - alpha_b) / (1 - alpha_b));
  * the base colour of an opaque dielectric (``base_weight * base_color``: glTF has no base weight),
    and of an untinted metal of specular weight 1 (its F0 in both models);
  * emission: the radiance (``emission_color`` times ``emission_luminance`` / ``nits_per_unit``) as glTF's
    emissive where at most 1, per texel; above 1, normalised to glTF's [0, 1] factor with the rest moved to
    KHR_materials_emissive_strength (one value: a textured luminance above 1 gets its mean); under a coat, times
    what OpenPBR's coat does to emission (:func:`openpbr_tools.evaluate.coat.coat_emission_factor`;
    MaterialX's ``gltf_pbr`` adds its emission above the clearcoat, as this evaluator does; the
    KHR_materials_clearcoat text darkens it by the clearcoat's Fresnel, which a viewer following it
    applies on top), divided by it coming back;

Exact, given glTF's model:
  * the coat's roughening of the base (OpenPBR spec, "Coat": mix(r, min(1, (r^4 + 2 r_c^4)^(1/4)),
    coat weight)) is put into glTF's base roughness, since glTF's clearcoat does not roughen the
    base; back, it is taken out (bisection). A rough-coated gold went from 3.88 to 0.51 mean ΔE.

Approximated (reported when visible; residuals are mean CIEDE2000 on the evaluator's lit sphere,
before -> after the fits of :mod:`.fit`, from ``openpbr convert --verify``):
  * glTF tints transmission with the base colour; OpenPBR has ``transmission_color``. A partly
    transmissive material gets a base colour mixed between its diffuse and transmission colours;
  * a solid (not thin-walled) transmissive material is a volume (KHR_materials_volume; glTF's
    thickness 0 would make it thin-walled, without refraction or dispersion); with
    ``transmission_depth`` > 0 the volume gets attenuation colour and distance (with
    ``transmission_scatter``, the colour of the absorption alone: glTF's volume does not scatter), and its thickness is
    one scene unit (glTF's thickness is the mesh's, unknown here; one
    unit is the path MaterialX's reference renders OpenPBR's absorption over);
  * the base under a coat: OpenPBR computes its Fresnel with its IOR relative to the coat's and
    darkens it; KHR_materials_specular's ``specular`` scales the bare base's F0 (and F90) to
    OpenPBR's (:func:`.fit.dielectric_specular_scale`), keeping ``ior`` for refraction. OpenPBR's
    ``specular_weight`` changes F0 only, glTF's F0 and F90: equal at normal incidence. Coated
    plastics and ceramics 0.1-1.1 (2.3-25.7 before, with the coat colour below), 1.9 (2.8) under
    an anisotropic coat (glTF's is isotropic), the car paint sample 1.0 (3.7), coated glass 3.4
    (4.7); a full thin film on the base under a coat 4.9 (4.4: glTF's ``1 - max(F)`` diffuse
    weight shows a film's fringes more than OpenPBR does);
  * the coat's colour (glTF's clearcoat is colourless) and OpenPBR's darkening of the base under
    its coat are folded into the base colour (their view-independent factors), which misses the
    tint of the dielectric reflection under the coat; coming back, ``coat_darkening`` is 0. A red
    coat over white plastic 0.5 (29.5), blue-glazed ceramic 0.6 (25.7);
  * a metal's F82 edge tint and specular weight: glTF's metal is F0-only Schlick; its base colour
    is the least-squares fit of OpenPBR's metal's albedo (:func:`.fit.schlick_metal_f0`). Tinted
    metals 0.1-1.2 (0.1-1.8), a strong tint (0.6, 0.5, 0.3) on gold 1.7 (1.8); specular weight
    0.6-0.8 on metals 0.6 (5.1-9.5). Coming back, the fit is inverted exactly (glTF's
    ``specular_color``, which glTF's metals ignore, becomes the F82 tint);
  * fuzz as sheen: Zeltner's and Charlie's albedos differ in shape; the sheen roughness and colour
    are fitted to the fuzz's albedo (:func:`.fit.sheen_fit`), the colour clamped to 1 where rough
    fuzz reflects more than a sheen can. Velvets 1.2-2.3 (3.2-5.2), a 0.6-weight grey dust 1.6 (1.0);
  * the coat's IOR (glTF fixes 1.5), subsurface (folded into the base colour).

Draft extensions (:mod:`openpbr_tools.io.gltf.drafts`, with the versions implemented). Read whenever
present, exactly: KHR_materials_coat (weight, roughness and anisotropy with glTF's anisotropy
convention, IOR, colour, darkening, normal) in place of its KHR_materials_clearcoat fallback,
KHR_materials_fuzz in place of the sheen fit, KHR_materials_diffuse_roughness, and the
EXT_materials_*_openpbr sub-extensions (OpenPBR's specular weight and colour, whose base colour is
then a metal's F0 as is; coat darkening; OpenPBR's anisotropy). Written with
``Settings.gltf_drafts`` (``openpbr convert --gltf-drafts``): the same extensions beside the ratified
fallbacks, and then the core factors are OpenPBR's own where a draft gives them their meaning: the
base colour is not darkened or tinted by the coat (KHR_materials_coat does that) and a metal's base
colour is its F0 with KHR_materials_specular + EXT_materials_specular_openpbr holding the specular
weight and F82 tint, so OpenPBR -> glTF -> OpenPBR returns every draft-carried parameter exactly. A
viewer without the drafts sees the ratified fallbacks (clearcoat without the coat's colour, sheen).
The drafts' own code is :mod:`.gltf_drafts`, the anisotropy convention :mod:`.gltf_anisotropy`.

One module because the two directions are each other's inverses: every fit and its inverse (the
metal F0, the specular weight under a coat, the coat's roughening, the sheen fit) sit side by side.
"""

from __future__ import annotations

import copy
import dataclasses

import numpy as np

from ..evaluate.coat import coat_absorption, coat_darkening_factor, coat_emission_factor, coat_roughened
from ..evaluate.fresnel import ior_to_f0
from ..evaluate.microfacet import gltf_anisotropic_alpha, openpbr_alphas
from ..evaluate.volume import absorption_coefficient, with_channel_axis
from .. import gltf_state
from ..io.gltf import drafts
from ..io.gltf.slots import DIFFUSE_TRANSMISSION, UNLIT
from ..model import Constant, Input, Material
from ..rules.translation import APPROXIMATED, CONVERTED, NOT_CARRIED
from . import fit, spec_gloss
from .coat_facts import COAT_EMISSION_NOTE, COAT_EMISSION_UNDONE, EMISSION_UNDER_COAT
from .common import Dropped, Mapping, Settings, Translation, differs, translate
from .gltf_anisotropy import gltf_anisotropy_strength, gltf_roughness, openpbr_anisotropy, openpbr_roughness
from .gltf_drafts import (DRAFT_TARGETS, GLTF_CLEARCOAT_IOR, apply_drafts, draft_record, needs_specular_openpbr,
                          with_draft_coat)

WHITE = np.ones(3)
#: Measured residuals, mean CIEDE2000 on the evaluator's lit sphere (module docstring).
COAT_RESIDUAL = "measured ΔE2000 0.1-1.1 on coated plastics, 1.0 on a coated car paint"
METAL_RESIDUAL = "measured ΔE2000 up to 1.2 on tinted metals, 1.7 for a strong tint"
SHEEN_RESIDUAL = "measured ΔE2000 1.2-2.3 on velvets"


def _smoother_than_the_coat(r, s, c, rc) -> bool:
    with np.errstate(all="ignore"):  # inf/nan from hostile files are reported elsewhere
        return bool(np.any(fit.smoother_than_the_coat_allows(openpbr_roughness(r, s), c, rc)))


def average_alpha_openpbr(r, a):
    """sqrt(alpha_t alpha_b) of OpenPBR's anisotropic roughness, alpha_t capped at 1 as glTF's is:
    the isotropic alpha the evaluator's albedo tables are read at."""
    alpha_t, alpha_b = openpbr_alphas(r, a)
    return np.sqrt(np.minimum(alpha_t, 1.0) * alpha_b)


def average_alpha_gltf(r_g, s):
    alpha_b = r_g ** 2
    return np.sqrt(gltf_anisotropic_alpha(alpha_b, s) * alpha_b)


def gltf_metal_split(weight, color, transmission, transmission_color, depth, subsurface, subsurface_color,
                    metalness=0.0, specular_weight=1.0, coat_weight=0.0, coat_darkening=0.0, coat_ior=1.5,
                    coat_color=WHITE, specular_color=WHITE, roughness=0.3, anisotropy=0.0, coat_roughness=0.0,
                    clip=True, split=True):
    """(metalness, base colour): glTF's one base colour for OpenPBR's base, subsurface, transmission and metal, in
    linear Rec.709, and the metalness that mixes it (:func:`fit.split_metal`); ``clip``:
    held to [0, 1] there, as a glTF file's baseColorFactor is (3.9.2). A gltf_pbr node in a MaterialX document
    (``clip`` False) is shaded unclamped in the renderer's working space, and only its value in the document's
    colour space must lie in [0, 1] (the node's range, which the translation holds afterwards): clipping in
    Rec.709 there darkened a wide-gamut gold by 1.2 mean CIEDE2000 (the red team's L-01)."""
    roughness = coat_roughened(roughness, coat_weight, coat_roughness)  # glTF's base roughness
    darkening = coat_darkening_factor(color, metalness, specular_weight, subsurface, subsurface_color,
                                      coat_weight, coat_darkening, fit.positive_ior(coat_ior))
    absorption = coat_absorption(coat_color, coat_weight)  # glTF's clearcoat is colourless
    # OpenPBR's metal has F0 base_weight * base_color; its dielectric diffuses base_weight * base_color and
    # scatters subsurface_color (base_weight weighs the diffuse lobe only), and transmits; the coat covers
    # them all. glTF's one base colour mixes the fitted metal and that dielectric by metalness (only the
    # dielectric transmits, in both models). openpbr_base_color inverts it (with no subsurface).
    diffuse = weight * (color * darkening * absorption)
    metal = fit.fitted_metal(diffuse, specular_color, specular_weight, average_alpha_openpbr(roughness, anisotropy))
    dielectric = diffuse + subsurface * (subsurface_color * darkening * absorption - diffuse)
    tint = np.where(depth > 0, WHITE, transmission_color) * darkening * absorption
    dielectric = dielectric + transmission * (tint - dielectric)
    if not split or np.ndim(transmission) == 0 and transmission > 0:  # glTF's metalness also weighs its transmission
        mixed = dielectric + metalness * (metal - dielectric)
        return np.asarray(metalness, dtype=np.float64), (np.clip(mixed, 0.0, 1.0) if clip else mixed)
    return fit.split_metal(dielectric, metal, metalness, average_alpha_openpbr(roughness, anisotropy), clip=clip)


def gltf_metallic(*values, clip=True):
    """glTF's metalness (:func:`gltf_metal_split`): OpenPBR's, unless its metal is dimmed or tinted away from
    the colour it shares with the diffuse (:func:`fit.split_metal`)."""
    return gltf_metal_split(*values, clip=clip)[0]


def gltf_specular(specular_weight, specular_ior, coat_ior, coat_weight, film_weight, color, metalness, subsurface,
                  subsurface_color, coat_darkening):
    """KHR_materials_specular's weight for OpenPBR's (:func:`fit.dielectric_specular_scale`)."""
    darkening = coat_darkening_factor(color, metalness, specular_weight, subsurface, subsurface_color, coat_weight,
                                      coat_darkening, fit.positive_ior(coat_ior))
    scale = fit.dielectric_specular_scale(specular_ior, coat_ior, coat_weight, film_weight,
                                          np.max(darkening, axis=-1, keepdims=True))
    return fit.specular_weight_under_coat(specular_weight, scale, metalness)


def gltf_relative_base(specular_weight, specular_ior, coat_ior, coat_weight, film_weight, metalness, transmission,
                       coat_darkening):
    """Where the glTF output writes the base's IOR relative to the coat as ``ior`` and OpenPBR's weight as
    ``specular`` (the reflection the coat leaves the base, as glTF's base has it against air), instead of
    the base's own IOR with the weight scaled (:func:`gltf_specular`): exactly where the reader
    (:func:`_coated_base`) reads that output back so, and back to this base IOR. Equal at normal
    incidence either way; a glTF clearcoat material of the default specular converted to OpenPBR and
    back is its own again (so is any with the scaled form: both read back to the same OpenPBR material,
    so one glTF of the pair cannot be told from the other; the relative form is taken for a whole weight)."""
    if not np.any(np.asarray(coat_weight, dtype=float) > 0):  # (most materials: no coat, nothing to decide)
        return np.zeros(np.shape(specular_ior), dtype=bool)
    with np.errstate(all="ignore"):
        eta = gltf_ior(fit.base_ior_under_coat(specular_ior, coat_ior, coat_weight))
        plain = (np.abs(np.asarray(coat_ior, dtype=float) - GLTF_CLEARCOAT_IOR) < 1e-9) & \
            (np.asarray(coat_darkening, dtype=float) <= 0)
        read = _coated_base(specular_weight, metalness, eta, coat_weight, film_weight, GLTF_CLEARCOAT_IOR, transmission,
                            which=True)
        back = fit.specular_ior_for_relative_ior(eta, GLTF_CLEARCOAT_IOR, coat_weight)
        # both forms read back to this material; the relative one is glTF's own where the weight is whole (the
        # default specular, which a glTF clearcoat material has), the scaled one where it is not
        whole = np.abs(np.asarray(specular_weight, dtype=float) - 1.0) < 1e-9
        return plain & whole & read & (np.abs(back - specular_ior) < 1e-6)


RELATIVE_SOURCES = ("specular_weight", "specular_ior", "coat_ior", "coat_weight", "thin_film_weight", "base_metalness",
                    "transmission_weight", "coat_darkening")


def gltf_base_ior(specular_ior, *relative):
    """glTF's ``ior``: OpenPBR's (:func:`gltf_ior`), or its IOR relative to the coat (:func:`gltf_relative_base`)."""
    eta = fit.base_ior_under_coat(specular_ior, relative[1], relative[2])
    return np.where(gltf_relative_base(relative[0], specular_ior, *relative[1:]), gltf_ior(eta), gltf_ior(specular_ior))


def _relative_specular(specular):
    """:func:`gltf_specular` (as ``specular``, on SPECULAR_SOURCES) where the base IOR is written as it is,
    OpenPBR's weight where it is written relative to the coat (:func:`gltf_relative_base`), over
    SPECULAR_SOURCES + ("transmission_weight",)."""
    def formula(*v):
        relative = gltf_relative_base(v[0], v[1], v[2], v[3], v[4], v[6], v[10], v[9])
        return np.where(relative, fit.specular_weight_under_coat(v[0], 1.0, v[6]), specular(*v[:10]))
    return formula


ROUGHNESS_SOURCES = ("specular_roughness", "specular_roughness_anisotropy", "coat_weight", "coat_roughness")

SPECULAR_SOURCES = ("specular_weight", "specular_ior", "coat_ior", "coat_weight", "thin_film_weight", "base_color",
                    "base_metalness", "subsurface_weight", "subsurface_color", "coat_darkening")


def openpbr_specular_weight(specular, metallic, ior, clearcoat, iridescence, coat_ior=GLTF_CLEARCOAT_IOR,
                            transmission=0.0):
    """Inverse of :func:`gltf_specular` (glTF's clearcoat has IOR 1.5, KHR_materials_coat's its
    ``coatIor``; neither darkens here: the ratified reading sets no darkening); where that needs a
    weight above OpenPBR's 1 (:func:`_coated_base`), glTF's ``specular`` as it is."""
    weight, _ = _coated_base(specular, metallic, ior, clearcoat, iridescence, coat_ior, transmission)
    return weight


def openpbr_specular_ior(specular, metallic, ior, clearcoat, iridescence, transmission, coat_ior=GLTF_CLEARCOAT_IOR):
    """OpenPBR's ``specular_ior``: glTF's ``ior``, except under a clearcoat that would leave an opaque
    base too little reflection to restore by the weight (:func:`_coated_base`)."""
    _, specular_ior = _coated_base(specular, metallic, ior, clearcoat, iridescence, coat_ior, transmission)
    return specular_ior


def relative_base(specular, metallic, ior, clearcoat, iridescence, transmission, coat_ior=GLTF_CLEARCOAT_IOR):
    """Where :func:`_coated_base` sets the base IOR from glTF's as its IOR relative to the coat."""
    return _coated_base(specular, metallic, ior, clearcoat, iridescence, coat_ior, transmission, which=True)


def _coated_base(specular, metallic, ior, clearcoat, iridescence, coat_ior, transmission=0.0, which=False):
    """(OpenPBR ``specular_weight``, ``specular_ior``) for glTF's base reflection under its clearcoat.

    glTF's base reflects as against air under a clearcoat (F0 from ``ior``, times ``specular``:
    KHR_materials_clearcoat layers the coat on the unchanged base BRDF); OpenPBR's base reflects
    against the coat (the relative IOR n_b / n_c, mixed with n_b by the coat weight). The inverse of
    the forward mapping keeps n_b = ``ior`` and restores F0 by the weight, 1 / (F0(eta) / F0(n_b));
    that needs a weight above 1 where the coat takes most of the base's reflection, and is impossible
    where the IORs match (glTF's default ``ior`` 1.5 under its 1.5 clearcoat: OpenPBR's base would not
    reflect at all). There the base IOR is chosen instead so that its IOR relative to the coat is glTF's
    ``ior`` (:func:`.fit.specular_ior_for_relative_ior`), and the weight is glTF's ``specular``: the
    base's Fresnel curve is glTF's, at normal incidence exactly. Only on an opaque base (a transmitting
    one refracts by its IOR) of the default, whole ``specular`` (what glTF clearcoat materials have; a
    weaker one keeps the scaled weight, above OpenPBR's soft maximum 1: so each OpenPBR material reads
    back from one glTF form, :func:`gltf_relative_base`). Texel by texel. ``which``: where that is done."""
    scale = fit.dielectric_specular_scale(ior, coat_ior, clearcoat, iridescence)
    weight = fit.specular_weight_from_coated(specular, scale, metallic)
    if not np.any(np.asarray(clearcoat, dtype=float) > 0):  # (most materials: no clearcoat)
        return np.zeros(np.shape(weight), dtype=bool) if which else (weight, ior)
    with np.errstate(all="ignore"):
        lost = (np.asarray(clearcoat, dtype=float) > 0) & (np.asarray(metallic, dtype=float) < 1) & \
            (np.asarray(transmission, dtype=float) <= 0) & \
            ((weight > 1.0 + 1e-9) | ((scale + np.asarray(metallic, dtype=float) * (1.0 - scale) <= 1e-9)
                                      & (np.asarray(specular, dtype=float) > 0)))
    relative = fit.specular_ior_for_relative_ior(gltf_ior(ior), coat_ior, clearcoat)
    with np.errstate(all="ignore"):  # (a relative IOR no base reaches under a thin coat: not this way)
        reached = np.abs(fit.base_ior_under_coat(relative, coat_ior, clearcoat) - gltf_ior(ior)) < 1e-6
    whole = np.abs(np.asarray(specular, dtype=float) - 1.0) < 1e-9  # (gltf_relative_base: one form each)
    lost = lost & reached & whole
    if which:
        return lost
    if not np.any(lost):
        return weight, ior
    return np.where(lost, fit.specular_weight_from_coated(specular, 1.0, metallic), weight), \
        np.where(lost, relative, ior)


SPECULAR_WEIGHT_SOURCES = ("specular", "metallic", "ior", "clearcoat", "iridescence")


def hdr_specular_scale(specular_color, metallic, whole=False):
    """The largest component of a dielectric's KHR_materials_specular colour above 1 (``whole``: any
    colour's), texel by texel (1 elsewhere, for a black colour and for a full metal, whose specular
    colour is OpenPBR's F82 tint). glTF's F0 is
    min(F0(ior) * colour, 1) * specular and its F90 ``specular``: the colour scales F0 only. OpenPBR's
    specular_color tints the whole Fresnel curve, grazing edge included, and stops at 1; its
    specular_weight scales F0 only (through the IOR, MaterialX's open_pbr_surface.mtlx
    ``scaled_specular_F0``, clamped below 1). So the colour divided by this factor, and the weight
    multiplied by it, give glTF's F0 with the least tint at the edge: exactly for a grey colour (a colour
    of 0.21 renders 5.3 mean CIEDE2000 from glTF's in MaterialX's GLSL written as a tint, 2.1 folded into
    the weight); a coloured one keeps its hue in the divided colour, which still tints the edge, where
    glTF clamps each channel at 1. A colour the toolkit wrote is OpenPBR's own tint (``whole`` False:
    only its excess over 1 is folded), so that OpenPBR -> glTF -> OpenPBR gives back the source."""
    colour = np.asarray(specular_color, dtype=float)  # (3,), or (H, W, 3) beside floats (H, W, 1) when baked
    largest = np.max(colour, axis=-1, keepdims=colour.ndim > 1) if colour.ndim else colour
    return np.where((np.asarray(metallic, dtype=float) < 1) & (largest > (0.0 if whole else 1.0)), largest, 1.0)


def gltf_ior(specular_ior):
    """KHR_materials_ior's ``ior`` (at least 1) for OpenPBR's: as it is from 1 up; below 1, its reciprocal,
    which has the same normal-incidence reflectance ((n - 1)/(n + 1))^2."""
    n = np.asarray(specular_ior, dtype=float)
    return np.where(n >= 1.0, n, 1.0 / np.maximum(n, 1e-6))


def attenuation_color(color, depth, scatter):
    """KHR_materials_volume's attenuation colour (reached at the attenuation distance, the depth): OpenPBR's
    transmission colour where the medium does not scatter; where it does, the colour its absorption alone
    reaches (:func:`~openpbr_tools.evaluate.volume.absorption_coefficient`: OpenPBR's absorption is its
    extinction less its scattering, and glTF's core volume only absorbs)."""
    color = np.asarray(color, dtype=float)
    depth = with_channel_axis(depth)
    absorbing = np.exp(-absorption_coefficient(color, depth, scatter) * depth)
    scatters = np.max(np.asarray(scatter, dtype=float), axis=-1, keepdims=True) > 0
    return np.where(depth > 0, np.where(scatters, absorbing, color), WHITE)


TRANSMISSION_MIX_SOURCES = ("transmission", "attenuation_distance", "thickness", "attenuation_color")


def _absorbs(attenuation_color):
    """Whether KHR_materials_volume's attenuation colour absorbs (is not white), per texel."""
    colour = np.asarray(attenuation_color, dtype=float)
    return np.any(np.abs(colour - 1.0) > 1e-9, axis=-1, keepdims=colour.ndim > 1)  # (texels: (H, W, 1))


def _unmixed(color, metallic, transmission, attenuation_distance, thickness, attenuation_color=WHITE):
    """(target, effective metalness) of the metal-fit inverse once the transmission is taken out of
    :func:`gltf_metal_split`'s mix: with k = 1 - (1 - m) t, (1 - m)(1 - t) D + m fit(D) equals k B for a
    thin wall (tinted by the base colour, OpenPBR's transmission colour coming back) and B - (1 - m) t
    for a volume (tinted white): a mix of D and fit(D) by m / k reaching B, or (B - (1 - m) t) / k. A volume
    of white attenuation absorbs nothing and is read as tinted by the base colour (the depth left 0)."""
    k = 1.0 - (1.0 - metallic) * transmission
    safe = np.where(k > 0, k, 1.0)
    volume = np.isfinite(attenuation_distance) & (attenuation_distance > 0) & (thickness > 0) & _absorbs(attenuation_color)
    target = np.where(volume & (k > 0), (color - (1.0 - metallic) * transmission) / safe, color)
    return np.clip(target, 0.0, 1.0), np.where(k > 0, metallic / safe, metallic)


def openpbr_metal_weight(color, metallic, specular_color, roughness, anisotropy_strength, *weight_sources,
                         coat_ior=GLTF_CLEARCOAT_IOR, transmission=0.0, attenuation_distance=np.inf, thickness=0.0,
                         attenuation_color=WHITE):
    """OpenPBR's ``specular_weight`` (:func:`openpbr_specular_weight`), except where glTF's material is metal and the
    metal's colour does not fit under that weight. glTF's specular scales "the specular reflection of the dielectric"
    only (KHR_materials_specular); OpenPBR's weight dims its metal too (open_pbr_surface.mtlx scales the metal's
    F82 Fresnel by it), so a metal's base colour is solved as glTF's colour over the weight. Where the weight
    holds it (a material written from OpenPBR, whose metal was dimmed by the weight: the round trip's), it is kept;
    where it cannot (glTF's specular 0 on a metal: black, the red team's F1), it is 1, which glTF's metal is: on a
    partial metal the dielectric's reflection then rises to OpenPBR's whole weight (a small error: F0 0.04 against a
    metal's colour lost). Texel by texel."""
    weight = openpbr_specular_weight(weight_sources[0], metallic, *weight_sources[1:], coat_ior=coat_ior,
                                     transmission=transmission)
    full = np.asarray(metallic, dtype=float) > 0.0  # (a texel of 254/255 metal is as black as one of 1)
    if not np.any(full):
        return weight
    target, metalness = _unmixed(color, metallic, transmission, attenuation_distance, thickness, attenuation_color)
    clipped = fit.metal_from_schlick_out_of_range(target, metalness, specular_color, weight,
                                                  average_alpha_gltf(roughness, anisotropy_strength))
    if np.ndim(full) == np.ndim(clipped) + 1:  # (a metalness texture with its channel axis)
        clipped = clipped[..., None]
    whole = full & clipped
    if np.ndim(weight) < np.ndim(whole):  # a constant weight over a textured colour stays one constant
        return np.where(np.any(whole), 1.0, weight)
    if np.ndim(whole) and np.ndim(weight) == np.ndim(whole) + 1:  # (a weight with its channel axis)
        whole = whole[..., None]
    return np.where(whole, 1.0, weight)


def openpbr_base_color(*values, **options):
    """Inverse of :func:`gltf_metal_split`'s metal fit and transmission mix: OpenPBR's base colour (F0
    under an F82 edge tint of ``specular_color``) whose fitted Schlick metal, mixed with the transmitting
    dielectric, is glTF's base colour, under :func:`openpbr_metal_weight` (whose arguments it takes)."""
    return _metal_inverse(fit.openpbr_metal_from_schlick, *values, **options)


def _metal_inverse_clips(*values, **options):
    """Whether :func:`openpbr_base_color` clips (no base colour in [0, 1] gives glTF's metal)."""
    return _metal_inverse(fit.metal_from_schlick_clips, *values, **options)


def _metal_inverse(solve, color, metallic, specular_color, roughness, anisotropy_strength, *weight_sources,
                   coat_ior=GLTF_CLEARCOAT_IOR, transmission=0.0, attenuation_distance=np.inf, thickness=0.0,
                   attenuation_color=WHITE):
    specular_weight = openpbr_metal_weight(color, metallic, specular_color, roughness, anisotropy_strength,
                                           *weight_sources, coat_ior=coat_ior, transmission=transmission,
                                           attenuation_distance=attenuation_distance, thickness=thickness,
                                           attenuation_color=attenuation_color)
    target, metalness = _unmixed(color, metallic, transmission, attenuation_distance, thickness, attenuation_color)
    return solve(target, metalness, specular_color, specular_weight, average_alpha_gltf(roughness, anisotropy_strength))


def _base_color_matters(weight, color, transmission, transmission_color, depth, subsurface, subsurface_color,
                        metalness, specular_weight, coat_weight, coat_darkening, coat_ior, coat_color, specular_color,
                        *roughness):
    mixed_transmission = 0 < transmission < 1 and (depth > 0 or differs(transmission_color, weight * color))
    # a full volume's glTF base colour is white (it would tint the transmission): exact for a dielectric,
    # whose OpenPBR base colour then shows nowhere; a metal's colour is lost
    full_volume = transmission >= 1 and depth > 0 and differs(color, WHITE) and metalness > 0
    tinted_metal = metalness > 0 and (differs(specular_color, WHITE) or specular_weight != 1)
    coloured_coat = coat_weight > 0 and differs(coat_color, WHITE)
    darkened = coat_weight > 0 and coat_darkening > 0 and differs(
        coat_darkening_factor(color, metalness, specular_weight, subsurface, subsurface_color, coat_weight, coat_darkening,
                              fit.positive_ior(coat_ior)), 1.0)
    return bool(subsurface > 0 or mixed_transmission or full_volume or tinted_metal or coloured_coat or darkened)


def _coat_folding_notes(material: Material, settings: Settings) -> list:
    """Ratified glTF output: the coat's colour and darkening have no place in glTF's colourless,
    non-darkening clearcoat and are folded into the base colour (view-independent factors): each
    is reported at its own input, where a reader of the report looks for it."""
    values = {name: getattr(material.inputs.get(name), "value", None) for name in ("coat_weight", "coat_color",
                                                                                   "coat_darkening")}
    weight = values["coat_weight"].value if hasattr(values["coat_weight"], "value") else 0.0
    if not isinstance(weight, (int, float)) or weight <= 0:
        return []
    notes = []
    color = values["coat_color"]
    if color is not None and (not hasattr(color, "value") or differs(color.value, WHITE)):
        notes.append(("coat_color", "glTF's clearcoat is colourless: the coat's colour is folded into the base colour, "
                                    "which misses its tint on the reflection under the coat"))
    darkening = material.inputs.get("coat_darkening")
    amount = darkening.value.value if darkening is not None and hasattr(darkening.value, "value") else \
        (None if darkening is not None else 1.0)  # OpenPBR's default darkening is 1
    if amount is None or amount > 0:
        notes.append(("coat_darkening", "glTF's clearcoat does not darken the base: OpenPBR's darkening is folded into "
                                        "the base colour as its view-independent factor"))
    return [settings.context.diagnostic(APPROXIMATED, f"{material.name} (OpenPBR -> glTF): {name}: {why}",
                                        (material.inputs[name].location if name in material.inputs
                                         else material.location.with_input(name)))
            for name, why in notes]


def _peak(color):
    """The largest channel of each texel (keeps the channel axis, so it divides colours)."""
    return np.max(color, axis=-1, keepdims=True)


def _emissive(radiance, luminance):
    """glTF's emissiveFactor (or texture) for an emitted ``radiance`` (OpenPBR's colour times its luminance in units):
    the radiance divided by :func:`_emissive_scale`, the one KHR_materials_emissive_strength every texel shares, so
    that texture times strength is the radiance at every texel. Before session 26 the luminance went into the
    strength and a textured luminance lost its brightness per texel (McUsd's lava: 7.16 mean CIEDE2000, its texture
    back exactly now); before session 27 each texel was divided by its own peak and the strength was their mean, so
    an 8-bit emission texture times a luminance of 5 came out at the mean peak, 3 (the red team's E#10: 6.42 mean
    CIEDE2000; the source texture and a strength of 5 now)."""
    return np.asarray(radiance, dtype=np.float64) / _emissive_scale(radiance)


def _emissive_scale(radiance) -> float:
    """The strength of :func:`_emissive`: the largest channel over every texel of the radiance, where above 1, else 1
    (a texture is evaluated whole, so this is one value for it)."""
    values = np.asarray(radiance, dtype=np.float64)
    return max(1.0, float(np.max(values))) if values.size and np.all(np.isfinite(values)) else 1.0


def _emissive_strength(radiance, luminance, nits_per_unit=1.0):
    """KHR_materials_emissive_strength: :func:`_emissive_scale`, one value for every texel."""
    return np.full(np.shape(_peak(radiance)), _emissive_scale(radiance))


def _normalised(color):
    """A colour divided by its largest channel, white where it is black."""
    peak = _peak(color)
    return np.where(peak > 0, color / np.where(peak > 0, peak, 1.0), WHITE)


def gltf_sheen_color(color, weight, roughness):
    """Fuzz as KHR_materials_sheen: weight * colour * k(r), k scaling the fitted Charlie albedo to
    Zeltner's (:func:`fit.sheen_fit`); glTF caps the colour at 1."""
    return np.clip(color * weight * fit.fuzz_albedo_scale(roughness), 0.0, 1.0)


def gltf_sheen_roughness(roughness):
    """glTF's sheen roughness (alpha = roughness^2 is Charlie's r) for the fitted Charlie r."""
    return np.sqrt(fit.charlie_roughness_for_fuzz(roughness))


def fuzz_roughness_from_gltf(sheen_roughness):
    return fit.fuzz_roughness_for_charlie(sheen_roughness ** 2)


def fuzz_weight_from_gltf(sheen_color, sheen_roughness):
    scale = fit.fuzz_albedo_scale(fuzz_roughness_from_gltf(sheen_roughness))
    return np.clip(_peak(sheen_color) / scale, 0.0, 1.0)


def gltf_base_color_drafts(weight, color, transmission, transmission_color, depth, subsurface, subsurface_color):
    """glTF's base colour beside the drafts: OpenPBR's own (KHR_materials_coat tints and darkens,
    EXT_materials_specular_openpbr makes it a metal's F0), with transmission and subsurface mixed in."""
    diffuse = weight * color
    diffuse = diffuse + subsurface * (subsurface_color - diffuse)  # base_weight: the diffuse lobe only
    tint = np.where(depth > 0, WHITE, transmission_color)
    return diffuse + transmission * (tint - diffuse)


def _mixed_base_matters(weight, color, transmission, transmission_color, depth, subsurface, subsurface_color):
    mixed_transmission = 0 < transmission < 1 and (depth > 0 or differs(transmission_color, weight * color))
    return bool(subsurface > 0 or mixed_transmission)


DRAFT_BASE_SOURCES = ("base_weight", "base_color", "transmission_weight", "transmission_color", "transmission_depth",
                      "subsurface_weight", "subsurface_color")


#: The sources of glTF's base colour (and of its metalness, where the metal is split: :func:`gltf_metal_split`)
BASE_SOURCES = ("base_weight", "base_color", "transmission_weight", "transmission_color", "transmission_depth",
                "subsurface_weight", "subsurface_color", "base_metalness", "specular_weight", "coat_weight",
                "coat_darkening", "coat_ior", "coat_color", "specular_color", "specular_roughness",
                "specular_roughness_anisotropy", "coat_roughness")


def _splits(material: Material) -> bool:
    """Whether the metal may be split (:func:`fit.split_metal`): not for a material read from glTF (its reading
    inverts the mix), and only where every base source is a constant (per texel the mix is kept, and a metalness
    that depended on a texture elsewhere would fall back to glTF's default of 1 where that texture cannot be
    baked: the review's reproducer)."""
    if isinstance(material.extra.get("gltf"), dict) or material.extra.get(MIXED_METAL):
        return False
    return all(isinstance(material.inputs[name].value, Constant) for name in BASE_SOURCES if name in material.inputs)


#: ``Material.extra`` key of an OpenPBR material read from glTF in memory (a gltf_pbr node, whose .mtlx carries no
#: glTF state): translated back to glTF, its metal is mixed by metalness (the inverse of its reading), not split
MIXED_METAL = "gltf_mixed_metal"


def to_gltf_mappings(settings: Settings, specular_openpbr: bool = False,
                     thickness: float | None = None, split: bool = True) -> tuple[Mapping, ...]:
    """The OpenPBR -> glTF mappings; ``specular_openpbr``: with ``Settings.gltf_drafts``, the material gets
    EXT_materials_specular_openpbr (a metal with an F82 tint or a specular weight); ``thickness``: the
    volume thickness of the glTF material this one came from (gltf_state), in metres; ``split``: a metal's
    metalness and base colour are fitted together (:func:`fit.split_metal`), not for a material that came from
    glTF, whose reading (:func:`openpbr_base_color`) inverts the plain mix exactly."""
    mpu = settings.meters_per_unit or 1.0
    nits = settings.nits_per_unit
    base_sources = BASE_SOURCES
    if settings.gltf_drafts and specular_openpbr:
        # EXT_materials_specular_openpbr: KHR_materials_specular and the base colour are OpenPBR's own
        base_and_specular = (
            Mapping("base_color", DRAFT_BASE_SOURCES, gltf_base_color_drafts, keep="base_color", exact=False, matters=_mixed_base_matters,
                    note="glTF's base colour also tints transmission and stands in for subsurface: colours mixed"),
            Mapping("specular", ("specular_weight",)),
            Mapping("specular_color", ("specular_color",)),
        )
    elif settings.gltf_drafts:
        # KHR_materials_coat carries the coat's colour and darkening: not folded into the base or the
        # specular weight (whose fit, without darkening, is what the reader inverts)
        base_and_specular = (
            Mapping("base_color", base_sources,
                    lambda *v: gltf_metal_split(*v[:10], 0.0, v[11], WHITE, *v[13:], split=False)[1],
                    keep="base_color", exact=False, matters=lambda *v: _base_color_matters(*v[:10], 0.0, v[11], WHITE, *v[13:]),
                    note="glTF's base colour also tints transmission and stands in for subsurface: colours mixed"),
            # the coat's IOR as KHR_materials_coat holds it (at least 1), which is what a reader inverts with
            Mapping("specular", SPECULAR_SOURCES + ("transmission_weight",),
                    _relative_specular(lambda *v: gltf_specular(v[0], v[1], np.maximum(v[2], 1.0), *v[3:9], 0.0)),
                    exact=False,
                    matters=lambda *v: v[6] < 1 and differs(
                        _relative_specular(lambda *u: gltf_specular(u[0], u[1], np.maximum(u[2], 1.0), *u[3:9], 0.0))(*v),
                        1.0),
                    note="KHR_materials_specular scales F0 and F90 where OpenPBR's specular_weight and a coat (the base's "
                         f"IOR relative to the coat's) change F0 only: equal at normal incidence ({COAT_RESIDUAL})"),
            Mapping("specular_color", ("specular_color",)),
        )
    else:
        base_and_specular = (
            Mapping("base_color", base_sources,
                    lambda *v: gltf_metal_split(*v, clip=settings.gltf_file, split=split)[1],
                    keep="base_color", exact=False, matters=_base_color_matters, clips=settings.gltf_file,
                    note="glTF's base colour also tints transmission and stands in for subsurface: colours mixed; "
                         "the coat's colour (glTF's clearcoat is colourless) is folded into it, which misses the "
                         f"tint of the dielectric reflection under the coat; a metal's F82 edge tint and specular "
                         f"weight are fitted into its F0 ({METAL_RESIDUAL})"),
            Mapping("specular", SPECULAR_SOURCES + ("transmission_weight",), _relative_specular(gltf_specular),
                    exact=False, matters=lambda *v: v[6] < 1 and differs(_relative_specular(gltf_specular)(*v), 1.0),
                    clips=False,  # (the base colour only weighs the coat's darkening here, unclipped)
                    note="KHR_materials_specular scales F0 and F90 where OpenPBR's specular_weight and a coat (the base's "
                         f"IOR relative to the coat's) change F0 only: equal at normal incidence ({COAT_RESIDUAL})"),
            Mapping("specular_color", ("specular_color", "base_metalness"), lambda c, m: c, exact=False,
                    matters=lambda c, m: differs(c, WHITE) and m > 0,
                    note="glTF's specular colour tints dielectric F0 only; a metal's F82 edge tint is fitted into its "
                         f"base colour instead ({METAL_RESIDUAL})"),
        )
    metallic = Mapping("metallic", ("base_metalness",)) if settings.gltf_drafts or not split else Mapping(
        "metallic", base_sources, lambda *v: gltf_metallic(*v, clip=settings.gltf_file), keep="base_metalness",
        exact=False, site="base_metalness", clips=settings.gltf_file,
        matters=lambda *v: differs(gltf_metallic(*v, clip=settings.gltf_file), v[7]),
        note="glTF's metal shares its base colour with the diffuse and reaches white at grazing whatever the colour: "
             "a metal OpenPBR dims by specular_weight (or tints at the edge) is carried by a lower metallic and a "
             "re-mixed base colour, fitted to both albedos")
    return base_and_specular + (
        metallic,
        Mapping("roughness", ROUGHNESS_SOURCES, lambda r, a, c, rc: gltf_roughness(coat_roughened(r, c, rc), a),
                keep="specular_roughness",
                converted="roughness from OpenPBR's anisotropic alpha_b, roughened by the coat as OpenPBR does "
                          "(glTF's clearcoat does not roughen the base)"),
        Mapping("anisotropy_strength", ROUGHNESS_SOURCES,
                lambda r, a, c, rc: gltf_anisotropy_strength(coat_roughened(r, c, rc), a),
                converted="KHR_materials_anisotropy strength solved from OpenPBR's alpha_t and alpha_b", exact=False,
                matters=lambda r, a, c, rc: bool(np.any(openpbr_alphas(coat_roughened(r, c, rc), a)[0] > 1.0 + 1e-9)),
                note="OpenPBR's alpha_t along the tangent exceeds 1, glTF's cap (alpha_t = mix(alpha, 1, s^2)): the "
                     "highlight is stretched less"),
        Mapping("ior", ("specular_ior",) + RELATIVE_SOURCES[:1] + RELATIVE_SOURCES[2:], gltf_base_ior,
                exact=False, matters=lambda n, *r: n < 1.0 or bool(np.any(gltf_relative_base(r[0], n, *r[1:]))),
                note="an IOR below 1 (a medium optically denser outside, e.g. a bubble) is written as its reciprocal, "
                     "glTF's ior being at least 1: the same reflectance at normal incidence, without OpenPBR's total "
                     "internal reflection towards grazing angles, and refraction bends the other way; under a "
                     "clearcoat it may be the base's IOR relative to the coat, with OpenPBR's specular weight as "
                     "glTF's specular (glTF's base reflects as against air under its clearcoat, OpenPBR's against the "
                     "coat): the same reflection at normal incidence"),
        Mapping("transmission", ("transmission_weight",)),
        Mapping("attenuation_color", ("transmission_color", "transmission_depth", "transmission_scatter"),
                attenuation_color),
        Mapping("attenuation_distance", ("transmission_depth",), lambda d: np.where(d > 0, d * mpu, np.inf),
                converted=f"scene units to metres at {mpu:g} m per unit"),
        # A solid (not thin-walled) transmissive OpenPBR material is a volume in glTF whatever its
        # depth: glTF's thickness 0 means thin-walled (no refraction, no dispersion).
        Mapping("thickness", ("transmission_depth", "geometry_thin_walled", "transmission_weight"),
                lambda d, thin, t: np.where((thin > 0.5) | (t <= 0), 0.0, thickness or mpu) + 0.0 * d,
                exact=thickness is not None, matters=lambda d, thin, t: d > 0 and thin < 0.5 and t > 0,
                converted="the source glTF's volume thickness, kept in the side channel (gltf_state)"
                if thickness is not None else "",
                note="glTF's volume thickness is the mesh's; set to one scene unit, the path MaterialX's "
                     "reference renders OpenPBR's absorption over"),
        Mapping("dispersion", ("transmission_dispersion_scale", "transmission_dispersion_abbe_number"),
                lambda s, v: np.where(v > 0, 20.0 * s / np.where(v > 0, v, 1.0), 0.0),
                converted="KHR_materials_dispersion = 20 * scale / Abbe number"),
        Mapping("sheen_color", ("fuzz_color", "fuzz_weight", "fuzz_roughness"), gltf_sheen_color,
                exact=settings.gltf_drafts, matters=lambda c, w, r: w > 0,
                converted="the fallback of KHR_materials_fuzz (draft, exact): fuzz (Zeltner) as sheen (Charlie), "
                          "colour and roughness fitted to its albedo",
                note=f"fuzz (Zeltner) as glTF sheen (Charlie): colour and roughness fitted to its albedo ({SHEEN_RESIDUAL})"),
        Mapping("sheen_roughness", ("fuzz_roughness", "fuzz_weight"), lambda r, w: gltf_sheen_roughness(r),
                converted="Charlie roughness fitted to the fuzz's albedo",
                when=lambda r, w: w > 0),  # without fuzz, no KHR_materials_sheen that does nothing
        Mapping("clearcoat", ("coat_weight",)),
        Mapping("clearcoat_roughness", ("coat_roughness",)),
        Mapping("iridescence", ("thin_film_weight",)),
        Mapping("iridescence_thickness", ("thin_film_thickness", "thin_film_weight"), lambda t, w: t * 1000.0,
                when=lambda t, w: w > 0, converted="micrometres to nanometres"),
        Mapping("iridescence_ior", ("thin_film_ior", "thin_film_weight"), lambda n, w: n, when=lambda n, w: w > 0),
        Mapping("emissive", EMISSION_UNDER_COAT,
                lambda c, l, w, cc, ci: _emissive(c * coat_emission_factor(cc, w, ci) * (l / nits), l),
                when=lambda c, l, *coat: l > 0, exact=False, matters=lambda c, l, w, *coat: l > 0 and w > 0,
                note=COAT_EMISSION_NOTE),
        Mapping("emissive_strength", EMISSION_UNDER_COAT,
                lambda c, l, w, cc, ci: _emissive_strength(c * coat_emission_factor(cc, w, ci) * (l / nits), l, nits),
                when=lambda c, l, *coat: l > 0, converted=f"nits at {nits:g} nit(s) per unit"),
        Mapping("alpha", ("geometry_opacity",)),
        # A cut-out texture (every texel 0 or 1: a UsdPreviewSurface opacityThreshold read as OpenPBR, a leaf mask)
        # is glTF's MASK at the default cutoff 0.5, exactly and without BLEND's sorting; one partial texel needs
        # BLEND (the baker takes the largest per-texel mode). A constant opacity below 1, 0 included, stays BLEND.
        Mapping("alpha_mode", ("geometry_opacity",), _alpha_mode),
        Mapping("normal", ("geometry_normal",)),
        Mapping("tangent", ("geometry_tangent",)),
        Mapping("clearcoat_normal", ("geometry_coat_normal",)),
    )


def _alpha_mode(opacity):
    """glTF's alphaMode (0 OPAQUE, 1 MASK, 2 BLEND) per texel of OpenPBR's geometry_opacity: a texel of a texture
    (two dimensions) that is 0 is cut out (MASK), one between 0 and 1 blends; a constant below 1 blends."""
    cut = 1.0 if np.ndim(opacity) >= 2 else 2.0
    return np.where(opacity >= 1.0, 0.0, np.where(opacity <= 0.0, cut, 2.0))


DROPPED_TO_GLTF = (
    Dropped("coat_ior", "glTF's clearcoat IOR is fixed at 1.5", matters=lambda n, w: w > 0 and abs(n - 1.5) > 1e-6,
            needs=("coat_weight",)),
    Dropped("coat_roughness_anisotropy", "glTF's clearcoat is isotropic", matters=lambda a, w: a > 0 and w > 0,
            needs=("coat_weight",)),
    Dropped("base_diffuse_roughness", "glTF's diffuse is Lambertian", matters=lambda r: r > 0),
    Dropped("transmission_scatter", "glTF has no volume scattering (not ratified): the attenuation colour is the "
                                    "medium's absorption (extinction less scattering, as OpenPBR defines it), and the "
                                    "scattered light's colour is lost", matters=lambda c: np.max(c) > 0),
    Dropped("subsurface_weight", "glTF has no subsurface scattering: the subsurface colour is mixed into the base "
                                 "colour and shaded as diffuse (no light travels under the surface)",
            matters=lambda w: w > 0),
    Dropped("subsurface_radius", "glTF has no subsurface scattering", matters=lambda r, w: w > 0, needs=("subsurface_weight",)),
    Dropped("subsurface_radius_scale", "glTF has no subsurface scattering", matters=lambda r, w: w > 0,
            needs=("subsurface_weight",)),
    Dropped("subsurface_scatter_anisotropy", "glTF has no subsurface scattering", matters=lambda g, w: w > 0 and g != 0,
            needs=("subsurface_weight",)),
    Dropped("geometry_coat_tangent", "glTF uses the mesh's tangents"),
    Dropped("transmission_scatter_anisotropy", "glTF has no volume scattering (not ratified)",
            matters=lambda g, scatter: g != 0 and np.max(scatter) > 0, needs=("transmission_scatter",)),
)


def from_gltf_mappings(settings: Settings, found: dict | None = None,
                       coat_ior: float = GLTF_CLEARCOAT_IOR, hdr: bool = True,
                       whole: bool = False) -> tuple[Mapping, ...]:
    """The glTF -> OpenPBR mappings; ``found``: the material's draft extensions (see
    :func:`gltf_to_openpbr`), ``coat_ior``: KHR_materials_coat's IOR where it replaces clearcoat's,
    ``whole``: every constant specular colour's largest component folds into the weight (a file another
    tool wrote, :func:`hdr_specular_scale`)."""
    found = found or {}
    # ``hdr``: a constant specular colour folds its excess over 1 (``whole``: its largest component) into the
    # weight (hdr_specular_scale); a
    # textured one is kept as MaterialX nodes (texture times factor), which OpenPBR renders above 1 as glTF does;
    # a draft's colour is OpenPBR's own
    fold = hdr and drafts.SPECULAR_OPENPBR not in found

    def scale(colour, metallic):
        return hdr_specular_scale(colour, metallic, whole) if fold else 1.0
    mpu = settings.meters_per_unit or 1.0
    nits = settings.nits_per_unit
    overridden = {target for name in found for target in DRAFT_TARGETS.get(name, ())}
    if drafts.SPECULAR_OPENPBR in found:  # OpenPBR's specular: the base colour is a metal's F0 as is
        base_and_specular = (Mapping("base_color", ("base_color",)), Mapping("specular_weight", ("specular",)),
                             Mapping("specular_ior", ("ior",)))
    else:
        base_and_specular = (
            Mapping("base_color", ("base_color", "metallic", "specular_color", "roughness", "anisotropy_strength")
                    + SPECULAR_WEIGHT_SOURCES[:1] + SPECULAR_WEIGHT_SOURCES[2:] + TRANSMISSION_MIX_SOURCES,
                    lambda *v: openpbr_base_color(*v[:-4], coat_ior=coat_ior, transmission=v[-4],
                                                  attenuation_distance=v[-3], thickness=v[-2], attenuation_color=v[-1]),
                    keep="base_color",
                    converted="a metal's base colour solved for OpenPBR's F82 edge tint (specular_color)", exact=False,
                    matters=lambda *v: _metal_inverse_clips(*v[:-4], coat_ior=coat_ior, transmission=v[-4],
                                                            attenuation_distance=v[-3], thickness=v[-2],
                                                            attenuation_color=v[-1]),
                    note="a metal's base colour solved for OpenPBR's F82 edge tint and specular weight (glTF's metals "
                         "ignore KHR_materials_specular, OpenPBR's do not) leaves [0, 1] and is clipped: the metal "
                         "renders darker or differently tinted"),
            Mapping("specular_weight", SPECULAR_WEIGHT_SOURCES + ("transmission", "specular_color", "base_color",
                                                                  "roughness", "anisotropy_strength")
                    + TRANSMISSION_MIX_SOURCES[1:],
                    lambda s, m, n, w, f, t, c, b, r, a, d, k, ac: openpbr_metal_weight(
                        b, m, c, r, a, s, n, w, f, coat_ior=coat_ior, transmission=t, attenuation_distance=d, thickness=k,
                        attenuation_color=ac) * scale(c, m), exact=False,
                    matters=lambda s, m, n, w, f, t, c, *_: m < 1 and (s != 1.0 or w > 0 or np.any(scale(c, m) != 1)),
                    note="KHR_materials_specular scales F0 and F90, OpenPBR's specular_weight F0 only (under a coat, of "
                         "the base relative to the coat): equal at normal incidence; a specular colour above 1 raises "
                         "the weight by its largest component",
                    converted="glTF's specular scales the dielectric only, so on a metal it has no effect; OpenPBR's "
                              "weight, which dims the metal too, is 1 where the metal's colour does not fit under it",
                    converted_to_default=True),
            Mapping("specular_ior", ("ior", "specular", "metallic", "clearcoat", "iridescence", "transmission"),
                    lambda n, s, m, c, f, t: openpbr_specular_ior(s, m, n, c, f, t, coat_ior=coat_ior), exact=False,
                    matters=lambda n, s, m, c, f, t: bool(np.any(relative_base(s, m, n, c, f, t, coat_ior=coat_ior))),
                    note="glTF's base reflects as against air under its clearcoat, OpenPBR's against the coat: the "
                         "base IOR is set so that its IOR relative to the coat is glTF's ior, the specular weight "
                         "to glTF's specular (the same reflection at normal incidence; converted back to glTF, the "
                         "ior is this base IOR and the specular is scaled to match)"),
        )
    if drafts.ANISOTROPY_OPENPBR in found:  # roughnessFactor and anisotropyStrength are OpenPBR's
        roughness = (
            Mapping("specular_roughness", ("roughness", "clearcoat", "clearcoat_roughness"),
                    lambda r, c, rc: fit.coat_unroughened(r, c, rc), keep="roughness",
                    converted="roughness less the roughening OpenPBR's coat adds", exact=False,
                    matters=lambda r, c, rc: bool(np.any(fit.smoother_than_the_coat_allows(r, c, rc))),
                    note="the base is smoother than OpenPBR's coat lets a base be (the coat roughens it, glTF's does "
                         "not): it is made as smooth as OpenPBR's gets (0; kept where any base renders alike under that coat), "
                         "and still renders rougher"),
            Mapping("specular_roughness_anisotropy", ("anisotropy_strength",)),
        )
    else:
        roughness = (
            Mapping("specular_roughness", ("roughness", "anisotropy_strength", "clearcoat", "clearcoat_roughness"),
                    lambda r, s, c, rc: fit.coat_unroughened(openpbr_roughness(r, s), c, rc), keep="roughness",
                    converted="roughness from glTF's anisotropic alphas, less the roughening OpenPBR's coat adds",
                    exact=False, matters=_smoother_than_the_coat,
                    note="the base is smoother than OpenPBR's coat lets a base be (the coat roughens it, glTF's does "
                         "not): it is made as smooth as OpenPBR's gets (0; kept where any base renders alike under that coat), "
                         "and still renders rougher"),
            Mapping("specular_roughness_anisotropy", ("roughness", "anisotropy_strength"), openpbr_anisotropy,
                    converted="anisotropy from glTF's alpha_t / alpha_b"),
        )
    mappings = base_and_specular + roughness + (
        Mapping("base_metalness", ("metallic",)),
        Mapping("specular_color", ("specular_color",)) if not fold else
        Mapping("specular_color", ("specular_color", "metallic"),
                lambda c, m: np.asarray(c, dtype=float) / hdr_specular_scale(c, m, whole), exact=False,
                matters=lambda c, m: bool(np.any(np.asarray(m) < 1) and differs(c, WHITE)) if whole else
                bool(np.any(hdr_specular_scale(c, m) > 1)),
                note="glTF's specular colour scales F0 only, OpenPBR's tints the grazing edge too (and stops at 1): "
                     "the colour is divided by its largest component, which multiplies specular_weight (OpenPBR's "
                     "weight scales F0 as glTF's colour does, the same at normal incidence); the divided colour "
                     "still tints the edge where it is not white" if whole else
                     "a colour above 1 (KHR_materials_specular allows one; OpenPBR's stops at 1) is divided by its "
                     "largest component, which multiplies specular_weight: OpenPBR raises F0 by the weight as glTF "
                     "by the colour, the same at normal incidence; the grazing tint is the divided colour"),
        Mapping("transmission_weight", ("transmission",)),
        # a volume (thickness > 0) absorbs by its attenuation; a thin wall (thickness 0, where glTF ignores
        # attenuation) is tinted by the base colour only
        Mapping("transmission_color", ("base_color", "attenuation_color", "attenuation_distance", "transmission",
                                       "thickness"),
                lambda c, a, d, t, h: np.where(np.isfinite(d) & (d > 0) & (h > 0) & _absorbs(a), a, c), exact=False,
                when=lambda c, a, d, t, h: t > 0,
                matters=lambda c, a, d, t, h: bool(0 < t < 1 or (np.isfinite(d) and d > 0 and h > 0 and _absorbs(a)
                                                                  and differs(c, WHITE))),
                note="glTF tints transmission with the base colour (shared with the diffuse part, and on top of "
                     "a volume's attenuation); OpenPBR keeps one transmission colour"),
        Mapping("transmission_depth", ("attenuation_distance", "thickness", "attenuation_color"),
                lambda d, h, a: np.where(np.isfinite(d) & (h > 0) & _absorbs(a), d / mpu, 0.0),
                converted=f"metres to scene units at {mpu:g} m per unit", exact=False,
                matters=lambda d, h, a: bool(np.isfinite(d) and d > 0 and h > 0 and not np.any(_absorbs(a))),
                note="a white attenuation colour absorbs nothing at any distance: the depth is left 0, so that the "
                     "transmission keeps glTF's base-colour tint (OpenPBR's transmission colour is the volume's "
                     "where a depth is set)"),
        Mapping("geometry_thin_walled", ("transmission", "thickness"), lambda t, d: np.where((t > 0) & (d <= 0), 1.0, 0.0),
                converted="glTF transmission without a volume is thin-walled"),
        # KHR_materials_dispersion: dispersion = 20 / V_d; OpenPBR's V_d is abbe_number / scale (the same optics
        # from any pair of the same ratio: an OpenPBR pair written to glTF comes back as scale 1 and 20 / dispersion)
        Mapping("transmission_dispersion_scale", ("dispersion",), lambda v: np.where(v > 0, 1.0, 0.0),
                converted="glTF's one dispersion number (20 / Abbe number) as scale 1 and the Abbe number it gives"),
        Mapping("transmission_dispersion_abbe_number", ("dispersion",),
                lambda v: np.where(v > 0, 20.0 / np.where(v > 0, v, 1.0), 20.0),
                converted="Abbe number 20 / glTF's dispersion, at scale 1"),
        Mapping("fuzz_weight", ("sheen_color", "sheen_roughness"), fuzz_weight_from_gltf, exact=False,
                matters=lambda c, r: np.max(c) > 0,
                note=f"glTF sheen (Charlie) as fuzz (Zeltner): weight and roughness fitted to its albedo ({SHEEN_RESIDUAL})"),
        Mapping("fuzz_color", ("sheen_color",), _normalised),
        # a film's and a sheen's other parameters where the material has one: without KHR_materials_iridescence or
        # KHR_materials_sheen, glTF's defaults (iridescenceIor 1.3, 100 nm, sheenRoughnessFactor 0) are no
        # authored values, and OpenPBR keeps its own (1.4, 0.5 um, 0.5)
        Mapping("fuzz_roughness", ("sheen_roughness", "sheen_color"), lambda r, c: fuzz_roughness_from_gltf(r),
                when=lambda r, c: np.max(c) > 0, converted="Zeltner roughness fitted to the sheen's albedo"),
        Mapping("coat_weight", ("clearcoat",)),
        Mapping("coat_roughness", ("clearcoat_roughness",)),
        Mapping("coat_ior", ("clearcoat",), lambda w: GLTF_CLEARCOAT_IOR, when=lambda w: w > 0,
                converted="glTF's clearcoat IOR is 1.5"),
        Mapping("coat_darkening", ("clearcoat",), lambda w: 0.0, when=lambda w: w > 0,
                converted="glTF does not darken under a clearcoat"),
        Mapping("thin_film_weight", ("iridescence",)),
        Mapping("thin_film_thickness", ("iridescence_thickness", "iridescence"), lambda t, w: t / 1000.0,
                when=lambda t, w: w > 0, converted="nanometres to micrometres"),
        Mapping("thin_film_ior", ("iridescence_ior", "iridescence"), lambda n, w: n, when=lambda n, w: w > 0),
        Mapping("emission_color", ("emissive", "clearcoat"),
                lambda c, w: _normalised(c / coat_emission_factor(1.0, w, GLTF_CLEARCOAT_IOR))),
        Mapping("emission_luminance", ("emissive", "emissive_strength", "clearcoat"),
                lambda c, s, w: _peak(c / coat_emission_factor(1.0, w, GLTF_CLEARCOAT_IOR)) * s * nits,
                converted=f"nits at {nits:g} nit(s) per unit; {COAT_EMISSION_UNDONE}"),
        Mapping("geometry_opacity", ("alpha", "alpha_mode", "alpha_cutoff"),
                lambda a, m, c: np.where(m == 0, 1.0, np.where(m == 1, np.where(a >= c, 1.0, 0.0), a)),
                exact=False, matters=lambda a, m, c: m == 1, note="an alpha MASK becomes a binary opacity"),
        Mapping("geometry_normal", ("normal",)),
        Mapping("geometry_tangent", ("tangent",)),
        Mapping("geometry_coat_normal", ("clearcoat_normal",)),
    )
    return tuple(m for m in mappings if m.target not in overridden)


DROPPED_FROM_GLTF = (
    Dropped("occlusion", "OpenPBR has no ambient occlusion input (bake it into lighting)", matters=lambda v: v != 1.0),
    Dropped("anisotropy_rotation", "OpenPBR rotates anisotropy through the tangent", matters=lambda v: v != 0.0),
    # a constant thickness travels in the side channel (gltf_state); a thickness texture does not
    Dropped("thickness", "OpenPBR has no volume thickness (only thin-walled or not): the texture is not kept",
            matters=lambda d, t: False, needs=("transmission",)),
)


DRAFT_DROPPED = ("coat_ior", "coat_roughness_anisotropy", "base_diffuse_roughness")  # carried by the drafts




def _thin_subsurface_as_diffuse_transmission(material: Material):
    """OpenPBR's thin-walled subsurface (OpenPBR 1.1, "Thin-walled mode": a sheet that scatters
    S = subsurface_color, 1/2 S (1 - g) back and 1/2 S (1 + g) through) as glTF's
    KHR_materials_diffuse_transmission (reflection (1 - t) baseColor, transmission t colour): t =
    w (1 + g) / 2, colour S, and the base colour the reflection left, ((1 - w) C + w S (1 - g) / 2) /
    (1 - t), exact (at most 1). Returns (the material with that base colour and no subsurface, the
    extension's values) or (the material, None) where it does not apply (not thin-walled, textured)."""
    def constant(name, default):
        entry = material.inputs.get(name)
        if entry is None:
            return np.asarray(default, dtype=np.float64)
        value = getattr(entry.value, "value", None)
        return None if value is None or isinstance(value, str) else np.asarray(value, dtype=np.float64)

    thin, weight = constant("geometry_thin_walled", 0.0), constant("subsurface_weight", 0.0)
    if thin is None or weight is None or float(thin) < 0.5 or float(weight) <= 0:
        return material, None
    color, scatter = constant("subsurface_color", (0.8, 0.8, 0.8)), constant("subsurface_scatter_anisotropy", 0.0)
    base, base_weight = constant("base_color", (0.8, 0.8, 0.8)), constant("base_weight", 1.0)
    if color is None or scatter is None or base is None or base_weight is None:
        return material, None
    t = float(weight) * (1.0 + float(scatter)) / 2.0
    reflected = (1.0 - weight) * base_weight * base + weight * color * (1.0 - scatter) / 2.0
    left = reflected / (1.0 - t) if 1.0 - t > 1e-9 else base_weight * base
    changed = copy.copy(material)
    changed.inputs = dict(material.inputs)
    anchor = material.inputs["subsurface_weight"]
    changed.inputs["base_color"] = Input("base_color", "color3", Constant(tuple(float(c) for c in left)),
                                         (material.inputs.get("base_color") or anchor).location,
                                         colorspace=(material.inputs.get("base_color") or anchor).colorspace
                                         or material.colorspace)
    changed.inputs["base_weight"] = Input("base_weight", "float", Constant(1.0), (
        material.inputs["base_weight"].location if "base_weight" in material.inputs
        else material.location.with_input("base_weight")))
    changed.inputs.pop("subsurface_weight")
    source_color = material.inputs.get("subsurface_color")
    record = {"diffuseTransmissionFactor": Input("diffuse_transmission", "float", Constant(t), anchor.location),
              "diffuseTransmissionColorFactor": Input(
                  "diffuse_transmission_color", "color3", Constant(tuple(float(c) for c in color)),
                  (source_color or anchor).location,
                  colorspace=(source_color.colorspace if source_color is not None else None) or material.colorspace)}
    return changed, record


def openpbr_to_gltf(material: Material, settings: Settings | None = None) -> Translation:
    settings = settings or Settings()
    source = material
    diffuse_transmission = None
    if settings.gltf_file:  # a gltf_pbr node has no diffuse transmission: the subsurface is folded, as before
        material, diffuse_transmission = _thin_subsurface_as_diffuse_transmission(material)
    dropped = DROPPED_TO_GLTF
    if settings.gltf_drafts:
        dropped = tuple(d for d in dropped if d.source not in DRAFT_DROPPED)
    specular_openpbr = settings.gltf_drafts and needs_specular_openpbr(material)
    state = material.gltf_state()
    thickness = state.get("thickness") if isinstance(state.get("thickness"), float) else None
    split = _splits(material)
    translation = translate(material, "gltf_pbr", to_gltf_mappings(settings, specular_openpbr, thickness, split),
                            dropped,
                            settings, "OpenPBR -> glTF")
    if settings.gltf_file and unlit_state(state):
        _unlit_back(translation, material, state)
    if settings.gltf_drafts:
        record, notes = draft_record(material, settings, specular_openpbr)
        if record:
            translation.material.extra["gltf_drafts"] = record
        translation.diagnostics += notes
    else:
        translation.diagnostics += _coat_folding_notes(material, settings)
    if diffuse_transmission is not None:
        translation.material.extra.setdefault("gltf_extensions", {})[DIFFUSE_TRANSMISSION] = diffuse_transmission
        translation.diagnostics.append(settings.context.diagnostic(
            CONVERTED, f"{material.name} (OpenPBR -> glTF): the thin-walled subsurface is "
                       f"KHR_materials_diffuse_transmission (its forward scattering) and the base colour (its back "
                       "scattering)", source.inputs["subsurface_weight"].location))
        translation.source = source
    return translation


def gltf_to_openpbr(material: Material, settings: Settings | None = None) -> Translation:
    """glTF -> OpenPBR: the ratified extensions through the mappings above, and the draft extensions
    the glTF reader found (``extra["gltf"]["drafts"]``) exactly, in place of their fallbacks."""
    settings = settings or Settings()
    state = material.gltf_state()
    found = state.get("drafts") if isinstance(state.get("drafts"), dict) else {}
    if drafts.COAT in found:  # the clearcoat is KHR_materials_coat's fallback: its sub-extensions too
        found = {k: v for k, v in found.items() if k not in (drafts.CLEARCOAT_DARKENING, drafts.CLEARCOAT_IOR)}
    if drafts.COAT in found:
        source, coat_ior = with_draft_coat(material, found[drafts.COAT])
    else:
        source, coat_ior = with_draft_coat(material, found.get(drafts.CLEARCOAT_IOR), ior_only=True)
    source, infinite_ior = _infinite_ior(source)
    metal_notes = []
    if state.get("toolkit_written") is False and drafts.SPECULAR_OPENPBR not in found:  # a glTF file another tool wrote
        source, metal_notes = _metal_ignores_specular(source, settings)
    unlit = _unlit_as_emission(source, state)
    specular_glossiness = unlit is None and spec_gloss.state_of(material) is not None
    colour = material.inputs.get("specular_color")
    mappings = from_gltf_mappings(settings, found, coat_ior, hdr=colour is None or isinstance(colour.value, Constant),
                                  whole=state.get("toolkit_written") is False)
    if specular_glossiness:  # read as a viewer of the extension does: not its metallic-roughness fallback
        source = spec_gloss.without_fallback(source)
        mappings = tuple(m for m in mappings if m.target not in spec_gloss.DECIDED)  # (spec_gloss.read's)
    translation = translate(unlit or source, "open_pbr_surface", mappings, DROPPED_FROM_GLTF, settings,
                            "glTF -> OpenPBR")
    translation.source = material
    translation.material.extra[MIXED_METAL] = True  # its way back mixes the metal as this reading inverted it
    translation.diagnostics += metal_notes
    if unlit is not None:
        translation.diagnostics += _unlit_emission(translation.material, material, settings)
    if infinite_ior:
        translation.diagnostics.append(settings.context.diagnostic(
            APPROXIMATED, f"{material.name} (glTF -> OpenPBR): ior: KHR_materials_ior's ior 0 (Fresnel 1 at every angle, "
                          f"an infinite IOR) is read as specular_ior {INFINITE_IOR:g} (F0 {float(ior_to_f0(INFINITE_IOR)):.4f})",
            material.inputs["ior"].location))
    if specular_glossiness:
        spec_gloss.read(translation, material, settings)
    if found:
        translation.diagnostics += apply_drafts(translation.material, material, found, settings)
    translation.diagnostics += _volume_of_diffuse_transmission(material, state, settings)
    translation.diagnostics += _diffuse_transmission_in(translation.material, material, state, settings)
    return translation


def _metal_ignores_specular(material: Material, settings: Settings) -> tuple[Material, list]:
    """A fully metallic glTF material (a constant metallicFactor of 1, glTF's default) from another tool: its
    KHR_materials_specular colour and factor have no effect (glTF's metal is Schlick's with F0 = base colour and
    F90 = 1), while OpenPBR's specular_color would tint the metal's edge (F82) and its specular_weight dim it.
    They are read as white and 1, which renders as glTF does (physicallybased.info's tungsten, exported with its
    F82 tint in the specular colour: mean CIEDE2000 2.10, max 14.7, read as a tint; 0 read so). Only for a glTF
    file another tool wrote (its asset.generator): a file this toolkit wrote, or its gltf_pbr result in memory
    or in a .mtlx, carries OpenPBR's tint there on purpose, for the round trip, and is read as before."""
    metallic = material.inputs.get("metallic")
    if metallic is not None and not (isinstance(metallic.value, Constant) and float(metallic.value.value) >= 1.0):
        return material, []
    notes, inputs = [], dict(material.inputs)
    for name, neutral, target in (("specular_color", (1.0, 1.0, 1.0), "specular_color"), ("specular", 1.0, "specular_weight")):
        entry = material.inputs.get(name)
        if entry is None or (isinstance(entry.value, Constant) and not differs(entry.value.value, neutral)):
            continue
        inputs[name] = Input(name, entry.type, Constant(neutral), entry.location)
        notes.append(settings.context.diagnostic(
            CONVERTED, f"{material.name} (glTF -> OpenPBR): {name}: KHR_materials_specular has no effect on a fully "
                       f"metallic material (glTF's metal is Schlick's with F0 = base colour), so OpenPBR's {target}, which "
                       f"would tint or dim the metal, is left at {neutral if isinstance(neutral, float) else 'white'}",
            entry.location))
    if not notes:
        return material, []
    changed = copy.copy(material)
    changed.inputs = inputs
    return changed, notes


#: The IOR that stands for KHR_materials_ior's ior 0, whose Fresnel term is 1 at every angle ("the effective IOR
#: becomes positive infinity"): F0 0.996, and an evaluator, a renderer or a Standard Surface still computes with it.
INFINITE_IOR = 1000.0


def _infinite_ior(material: Material) -> tuple[Material, bool]:
    """``material`` with a constant ior of 0 (KHR_materials_ior's specular-glossiness compatibility mode) as
    :data:`INFINITE_IOR`, and whether it had one."""
    found = material.inputs.get("ior")
    if found is None or not isinstance(found.value, Constant) or found.constant != 0.0:
        return material, False
    inputs = dict(material.inputs, ior=dataclasses.replace(found, value=Constant(INFINITE_IOR)))
    return dataclasses.replace(material, inputs=inputs), True


UNLIT_RECORD = "unlit"  # key of the glTF state: what the unlit reading replaced, restored for a glTF written back
UNLIT_FACTORS = gltf_state.UNLIT_FACTORS
#: glTF inputs the unlit reading writes (through OpenPBR and back), which undoing it drops
UNLIT_WRITTEN = ("base_color", "emissive", "emissive_strength", "specular", "specular_color", "metallic")


def unlit_state(state: dict) -> bool:
    """Whether a glTF state (``extra["gltf"]``) holds KHR_materials_unlit."""
    return isinstance(state.get("extensions"), dict) and UNLIT in state["extensions"]


def _unlit_as_emission(material: Material, state: dict) -> Material | None:
    """A KHR_materials_unlit material read as what it renders: a black base (``base_color`` 0,
    ``metallic`` 0, no ``emissive`` or specular), to which :func:`_unlit_emission` adds the base colour as
    emission and a specular weight of 0. None for a lit material."""
    if not unlit_state(state):
        return None
    source = copy.copy(material)
    source.inputs = dict(material.inputs)
    for name in ("emissive", "specular", "specular_color"):  # (the weight is set on the result: no note)
        source.inputs.pop(name, None)
    for name, kind, value in (("base_color", "color3", (0.0, 0.0, 0.0)), ("metallic", "float", 0.0)):
        source.inputs[name] = Input(name, kind, Constant(value), material.location,
                                    colorspace="lin_rec709" if kind == "color3" else None)
    return source


def _unlit_emission(result: Material, material: Material, settings: Settings) -> list:
    """An unlit surface shows its base colour whatever the lighting, as an emitter with nothing to
    reflect does: OpenPBR's ``emission_color`` is the base colour as it is (factor, texture, colour
    space), at the luminance of glTF's emissive 1 (``Settings.nits_per_unit``). The extension stays in
    the glTF state with the constant metallic factor the reading replaced, so that a glTF written back
    is unlit again (:func:`_unlit_back`)."""
    base = material.inputs.get("base_color")
    if base is not None:
        emission = copy.deepcopy(base)
        emission.name = "emission_color"
    else:  # glTF's default base colour, white
        emission = Input("emission_color", "color3", Constant((1.0, 1.0, 1.0)), material.location,
                         colorspace="lin_rec709")
    result.inputs["emission_color"] = emission
    result.inputs["specular_weight"] = Input("specular_weight", "float", Constant(0.0), material.location)
    result.inputs["emission_luminance"] = Input("emission_luminance", "float", Constant(float(settings.nits_per_unit)),
                                                material.location)
    replaced = {"as_emission": True}  # (the record's presence marks the reading, factors or not)
    for name in UNLIT_FACTORS:
        entry = material.inputs.get(name)
        if entry is not None and isinstance(entry.value, Constant):
            value = entry.value.value
            replaced[name] = [float(v) for v in value] if isinstance(value, (tuple, list)) else float(value)
    state = result.extra.get("gltf")
    if isinstance(state, dict):
        result.extra["gltf"] = dict(state, **{UNLIT_RECORD: replaced})
    return [settings.context.diagnostic(
        CONVERTED, f"{material.name} (glTF -> OpenPBR): KHR_materials_unlit read as emission of the base colour "
                   f"({settings.nits_per_unit:g} nit(s), glTF's emissive 1) over a black base that does not reflect "
                   "(base_color 0, specular_weight 0): it shows its colour whatever the lighting; converted back to "
                   "glTF it is unlit again", (base.location if base is not None else material.location))]


def _unlit_back(translation: Translation, material: Material, state: dict) -> None:
    """The inverse of :func:`_unlit_emission` for a glTF output (:func:`_as_unlit`, the emission colour
    at glTF's emissive 1 the base colour again; the writer restores the extension from the state)."""
    record = state.get(UNLIT_RECORD) if isinstance(state.get(UNLIT_RECORD), dict) else {}
    translation.material.inputs = _as_unlit(translation.material.inputs, material.inputs.get("emission_color"),
                                            record, material.location)
    translation.diagnostics = [d for d in translation.diagnostics
                               if d.location.input not in ("emission_color", "emission_luminance", "specular_weight",
                                                           "base_color")]


def unlit_restored(material: Material) -> Material | None:
    """A ``gltf_pbr`` material that holds the unlit reading (:func:`_unlit_emission` through
    :func:`openpbr_to_gltf` for a .mtlx output: emission over a black base, the replaced factors in the
    state) as the unlit glTF material it came from, for a glTF output; None for any other."""
    state = material.gltf_state()
    if not unlit_state(state) or not isinstance(state.get(UNLIT_RECORD), dict):
        return None
    restored = copy.copy(material)
    restored.inputs = _as_unlit(material.inputs, material.inputs.get("emissive"), state[UNLIT_RECORD], material.location)
    return restored


def _as_unlit(inputs: dict, colour: Input | None, record: dict, location) -> dict:
    """glTF inputs with the unlit reading undone: ``colour`` (the emission it wrote) the base colour
    again; the emissive, the specular and the black, non-metallic base it wrote dropped; the constant
    factors it replaced (``record``, :data:`UNLIT_FACTORS`) restored."""
    out = {name: entry for name, entry in inputs.items() if name not in UNLIT_WRITTEN}
    if colour is not None:
        out["base_color"] = dataclasses.replace(copy.deepcopy(colour), name="base_color")
    for name, width in UNLIT_FACTORS.items():
        value = record.get(name)
        if value is not None:
            out[name] = Input(name, "color3" if width == 3 else "float", Constant(tuple(value) if width == 3 else value),
                              location, colorspace="lin_rec709" if width == 3 else None)
    return out


def _diffuse_transmission_in(result: Material, material: Material, state: dict, settings: Settings) -> list:
    """KHR_materials_diffuse_transmission on a thin glTF material (no volume) as OpenPBR's thin-walled
    subsurface: weight t, colour the transmission colour, all of it scattered forward (anisotropy 1),
    so that the diffuse reflection is (1 - t) baseColor as glTF's (the inverse of
    :func:`_thin_subsurface_as_diffuse_transmission`). Textured factors, or a volume (glTF's diffuse
    transmission into a volume is subsurface scattering, which OpenPBR parameterises differently),
    stay in the side channel."""
    extensions = state.get("extensions") if isinstance(state.get("extensions"), dict) else {}
    found = extensions.get(DIFFUSE_TRANSMISSION)
    if not isinstance(found, dict):
        return []
    thickness = material.inputs.get("thickness")
    volume = thickness is not None and getattr(thickness.value, "value", 1.0) != 0.0
    factor, color = found.get("diffuseTransmissionFactor", 0.0), found.get("diffuseTransmissionColorFactor", [1.0] * 3)
    numbers = isinstance(factor, (int, float)) and not isinstance(factor, bool) and isinstance(color, list) and \
        len(color) == 3 and all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in color)
    if volume or not numbers or any(key.endswith("Texture") for key in found) or not 0 <= factor <= 1:
        return []
    where = material.location
    if factor > 0:
        result.inputs["geometry_thin_walled"] = Input("geometry_thin_walled", "boolean", Constant(True), where)
        result.inputs["subsurface_weight"] = Input("subsurface_weight", "float", Constant(float(factor)), where)
        result.inputs["subsurface_color"] = Input("subsurface_color", "color3", Constant(tuple(float(c) for c in color)),
                                                  where, colorspace="lin_rec709")
        result.inputs["subsurface_scatter_anisotropy"] = Input("subsurface_scatter_anisotropy", "float", Constant(1.0),
                                                               where)
    kept = result.extra.get("gltf", {}).get("extensions")
    if isinstance(kept, dict):
        kept.pop(DIFFUSE_TRANSMISSION, None)
        if not kept:
            result.extra["gltf"].pop("extensions")
    return [settings.context.diagnostic(
        CONVERTED, f"{material.name} (glTF -> OpenPBR): KHR_materials_diffuse_transmission read as OpenPBR's thin-walled "
                   "subsurface (weight, colour, scattered forward: subsurface_scatter_anisotropy 1)", where)]


def _volume_of_diffuse_transmission(material: Material, state: dict, settings: Settings) -> list:
    """A volume that only KHR_materials_diffuse_transmission uses (no KHR_materials_transmission):
    OpenPBR's volume belongs to its specular transmission, so the volume is not carried (the diffuse
    transmission itself travels in the side channel, gltf_state)."""
    thickness = material.inputs.get("thickness")
    transmission = material.inputs.get("transmission")
    if _has_diffuse_transmission(state) and thickness is not None and \
            getattr(thickness.value, "value", 1.0) != 0.0 and \
            (transmission is None or getattr(transmission.value, "value", 1.0) == 0.0):
        return [settings.context.diagnostic(
            NOT_CARRIED, f"{material.name} (glTF -> OpenPBR): KHR_materials_volume serves only "
                         "KHR_materials_diffuse_transmission, which OpenPBR does not carry: its attenuation and "
                         "dispersion are not carried (its thickness travels in the side channel)", thickness.location)]
    return []


def _has_diffuse_transmission(state: dict) -> bool:
    extensions = state.get("extensions") if isinstance(state.get("extensions"), dict) else {}
    return DIFFUSE_TRANSMISSION in extensions
