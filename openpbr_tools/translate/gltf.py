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
  * the base colour of an opaque material (``base_weight * base_color``: glTF has no base weight,
    and a metal's base colour is its F0 in both models);
  * emission: colour normalised to glTF's [0, 1] factor with the rest moved to
    KHR_materials_emissive_strength; ``emission_luminance`` / ``nits_per_unit``.

Approximated (reported when visible):
  * glTF tints transmission with the base colour; OpenPBR has ``transmission_color``. A partly
    transmissive material gets a base colour mixed between its diffuse and transmission colours;
  * with ``transmission_depth`` > 0 the volume (KHR_materials_volume) gets attenuation colour and
    distance, and a thickness of one scene unit (glTF's thickness is the mesh's, unknown here; one
    unit is the path MaterialX's reference renders OpenPBR's absorption over);
  * ``specular_weight``/``specular_color`` as KHR_materials_specular agree at normal incidence;
    towards grazing angles glTF reaches ``specular`` untinted, OpenPBR the tinted Fresnel;
  * a metal's F82 edge tint, the coat's colour and IOR (glTF fixes 1.5), subsurface (folded into the
    base colour), fuzz as sheen (colour times weight; roughness copied). OpenPBR's darkening of the
    base under a coat is folded into the base colour (its view-independent factor); coming back,
    ``coat_darkening`` is 0.
"""

from __future__ import annotations

import numpy as np

from ..model import Material
from .common import Dropped, Mapping, Settings, Translation, coat_darkening_factor, differs, translate

WHITE = np.ones(3)


def _alphas_openpbr(r, a):
    a = np.clip(a, 0.0, 1.0)
    alpha_t = r ** 2 * np.sqrt(2.0 / (1.0 + (1.0 - a) ** 2))
    return alpha_t, (1.0 - a) * alpha_t


def gltf_roughness(r, a):
    _, alpha_b = _alphas_openpbr(r, a)
    return np.sqrt(alpha_b)


def gltf_anisotropy_strength(r, a):
    alpha_t, alpha_b = _alphas_openpbr(r, a)
    with np.errstate(divide="ignore", invalid="ignore"):
        s2 = np.where(alpha_b < 1.0, (np.minimum(alpha_t, 1.0) - alpha_b) / np.where(alpha_b < 1.0, 1.0 - alpha_b, 1.0), 0.0)
    return np.sqrt(np.clip(s2, 0.0, 1.0))


def openpbr_roughness(r_g, s):
    alpha_b = r_g ** 2
    alpha_t = alpha_b + (1.0 - alpha_b) * s ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(alpha_t > 0, 1.0 - alpha_b / np.where(alpha_t > 0, alpha_t, 1.0), 0.0)
    return np.sqrt(alpha_t * np.sqrt((1.0 + (1.0 - a) ** 2) / 2.0))


def openpbr_anisotropy(r_g, s):
    alpha_b = r_g ** 2
    alpha_t = alpha_b + (1.0 - alpha_b) * s ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(alpha_t > 0, 1.0 - alpha_b / np.where(alpha_t > 0, alpha_t, 1.0), 0.0)


def gltf_base_color(weight, color, transmission, transmission_color, depth, subsurface, subsurface_color,
                    metalness=0.0, specular_weight=1.0, coat_weight=0.0, coat_darkening=0.0, coat_ior=1.5):
    color = color * coat_darkening_factor(color, metalness, specular_weight, subsurface, subsurface_color,
                                          coat_weight, coat_darkening, coat_ior)
    diffuse = weight * color
    diffuse = diffuse + subsurface * (weight * subsurface_color - diffuse)
    tint = np.where(depth > 0, WHITE, transmission_color)
    return diffuse + transmission * (tint - diffuse)


def _base_color_matters(weight, color, transmission, transmission_color, depth, subsurface, subsurface_color, *coat):
    mixed_transmission = 0 < transmission < 1 and (depth > 0 or differs(transmission_color, weight * color))
    full_volume = transmission >= 1 and depth > 0 and differs(color, WHITE)
    return bool(subsurface > 0 or mixed_transmission or full_volume)


def _emissive(color, luminance):
    peak = np.max(color)
    return color / peak if peak > 1.0 else color


def _emissive_strength(color, luminance, nits_per_unit=1.0):
    peak = np.max(color)
    return luminance / nits_per_unit * (peak if peak > 1.0 else 1.0)


def to_gltf_mappings(settings: Settings) -> tuple[Mapping, ...]:
    mpu = settings.meters_per_unit or 1.0
    nits = settings.nits_per_unit
    base_sources = ("base_weight", "base_color", "transmission_weight", "transmission_color", "transmission_depth",
                    "subsurface_weight", "subsurface_color", "base_metalness", "specular_weight", "coat_weight",
                    "coat_darkening", "coat_ior")
    return (
        Mapping("base_color", base_sources, gltf_base_color, exact=False, matters=_base_color_matters,
                note="glTF's base colour also tints transmission and stands in for subsurface: colours mixed"),
        Mapping("metallic", ("base_metalness",)),
        Mapping("roughness", ("specular_roughness", "specular_roughness_anisotropy"), gltf_roughness,
                converted="roughness from OpenPBR's anisotropic alpha_b"),
        Mapping("anisotropy_strength", ("specular_roughness", "specular_roughness_anisotropy"), gltf_anisotropy_strength,
                converted="KHR_materials_anisotropy strength solved from OpenPBR's alpha_t and alpha_b"),
        Mapping("specular", ("specular_weight",), exact=False, matters=lambda w: w != 1.0,
                note="KHR_materials_specular matches OpenPBR's specular_weight at normal incidence only"),
        Mapping("specular_color", ("specular_color", "base_metalness"), lambda c, m: c, exact=False,
                matters=lambda c, m: differs(c, WHITE),
                note="glTF's specular colour tints dielectric F0 only; a metal's F82 edge tint is lost"),
        Mapping("ior", ("specular_ior",)),
        Mapping("transmission", ("transmission_weight",)),
        Mapping("attenuation_color", ("transmission_color", "transmission_depth"), lambda c, d: np.where(d > 0, c, WHITE)),
        Mapping("attenuation_distance", ("transmission_depth",), lambda d: np.where(d > 0, d * mpu, np.inf),
                converted=f"scene units to metres at {mpu:g} m per unit"),
        Mapping("thickness", ("transmission_depth", "geometry_thin_walled"),
                lambda d, thin: np.where((thin > 0.5) | (d <= 0), 0.0, mpu),
                exact=False, matters=lambda d, thin: d > 0 and thin < 0.5,
                note="glTF's volume thickness is the mesh's; set to one scene unit, the path MaterialX's "
                     "reference renders OpenPBR's absorption over"),
        Mapping("dispersion", ("transmission_dispersion_scale", "transmission_dispersion_abbe_number"),
                lambda s, v: np.where(v > 0, 20.0 * s / np.where(v > 0, v, 1.0), 0.0),
                converted="KHR_materials_dispersion = 20 * scale / Abbe number"),
        Mapping("sheen_color", ("fuzz_color", "fuzz_weight"), lambda c, w: c * w, exact=False, matters=lambda c, w: w > 0,
                note="fuzz (Zeltner) rendered as glTF sheen (Charlie); colour times weight"),
        Mapping("sheen_roughness", ("fuzz_roughness", "fuzz_weight"), lambda r, w: r, exact=False,
                matters=lambda r, w: w > 0, note="sheen roughness conventions differ"),
        Mapping("clearcoat", ("coat_weight",)),
        Mapping("clearcoat_roughness", ("coat_roughness",)),
        Mapping("iridescence", ("thin_film_weight",)),
        Mapping("iridescence_thickness", ("thin_film_thickness", "thin_film_weight"), lambda t, w: t * 1000.0,
                when=lambda t, w: w > 0, converted="micrometres to nanometres"),
        Mapping("iridescence_ior", ("thin_film_ior", "thin_film_weight"), lambda n, w: n, when=lambda n, w: w > 0),
        Mapping("emissive", ("emission_color", "emission_luminance"), _emissive, when=lambda c, l: l > 0),
        Mapping("emissive_strength", ("emission_color", "emission_luminance"), lambda c, l: _emissive_strength(c, l, nits),
                when=lambda c, l: l > 0, converted=f"nits at {nits:g} nit(s) per unit"),
        Mapping("alpha", ("geometry_opacity",)),
        Mapping("alpha_mode", ("geometry_opacity",), lambda o: np.where(o < 1.0, 2.0, 0.0)),
        Mapping("normal", ("geometry_normal",)),
        Mapping("tangent", ("geometry_tangent",)),
        Mapping("clearcoat_normal", ("geometry_coat_normal",)),
    )


DROPPED_TO_GLTF = (
    Dropped("coat_color", "glTF's clearcoat is colourless", matters=lambda c, w: w > 0 and differs(c, WHITE),
            needs=("coat_weight",)),
    Dropped("coat_ior", "glTF's clearcoat IOR is fixed at 1.5", matters=lambda n, w: w > 0 and abs(n - 1.5) > 1e-6,
            needs=("coat_weight",)),
    Dropped("coat_roughness_anisotropy", "glTF's clearcoat is isotropic", matters=lambda a, w: a > 0 and w > 0,
            needs=("coat_weight",)),
    Dropped("base_diffuse_roughness", "glTF's diffuse is Lambertian", matters=lambda r: r > 0),
    Dropped("transmission_scatter", "glTF has no volume scattering (not ratified)", matters=lambda c: np.max(c) > 0),
    Dropped("subsurface_radius", "glTF has no subsurface scattering", matters=lambda r, w: w > 0, needs=("subsurface_weight",)),
    Dropped("geometry_coat_tangent", "glTF uses the mesh's tangents"),
)


def from_gltf_mappings(settings: Settings) -> tuple[Mapping, ...]:
    mpu = settings.meters_per_unit or 1.0
    nits = settings.nits_per_unit
    return (
        Mapping("base_color", ("base_color",)),
        Mapping("base_metalness", ("metallic",)),
        Mapping("specular_roughness", ("roughness", "anisotropy_strength"), openpbr_roughness,
                converted="roughness from glTF's anisotropic alphas"),
        Mapping("specular_roughness_anisotropy", ("roughness", "anisotropy_strength"), openpbr_anisotropy,
                converted="anisotropy from glTF's alpha_t / alpha_b"),
        Mapping("specular_weight", ("specular",), exact=False, matters=lambda w: w != 1.0,
                note="KHR_materials_specular matches OpenPBR's specular_weight at normal incidence only"),
        Mapping("specular_color", ("specular_color",)),
        Mapping("specular_ior", ("ior",)),
        Mapping("transmission_weight", ("transmission",)),
        Mapping("transmission_color", ("base_color", "attenuation_color", "attenuation_distance", "transmission"),
                lambda c, a, d, t: np.where(np.isfinite(d) & (d > 0), a, c), exact=False, when=lambda c, a, d, t: t > 0,
                matters=lambda c, a, d, t: bool(0 < t < 1 or (np.isfinite(d) and d > 0 and differs(c, WHITE))),
                note="glTF tints transmission with the base colour (shared with the diffuse part, and on top of "
                     "a volume's attenuation); OpenPBR keeps one transmission colour"),
        Mapping("transmission_depth", ("attenuation_distance",), lambda d: np.where(np.isfinite(d), d / mpu, 0.0),
                converted=f"metres to scene units at {mpu:g} m per unit"),
        Mapping("geometry_thin_walled", ("transmission", "thickness"), lambda t, d: np.where((t > 0) & (d <= 0), 1.0, 0.0),
                converted="glTF transmission without a volume is thin-walled"),
        Mapping("transmission_dispersion_scale", ("dispersion",), lambda v: np.where(v > 0, 1.0, 0.0)),
        Mapping("transmission_dispersion_abbe_number", ("dispersion",),
                lambda v: np.where(v > 0, 20.0 / np.where(v > 0, v, 1.0), 20.0)),
        Mapping("fuzz_weight", ("sheen_color",), lambda c: np.max(c), exact=False, matters=lambda c: np.max(c) > 0,
                note="glTF sheen (Charlie) rendered as fuzz (Zeltner)"),
        Mapping("fuzz_color", ("sheen_color",), lambda c: c / np.max(c) if np.max(c) > 0 else WHITE),
        Mapping("fuzz_roughness", ("sheen_roughness",)),
        Mapping("coat_weight", ("clearcoat",)),
        Mapping("coat_roughness", ("clearcoat_roughness",)),
        Mapping("coat_ior", ("clearcoat",), lambda w: 1.5, when=lambda w: w > 0, converted="glTF's clearcoat IOR is 1.5"),
        Mapping("coat_darkening", ("clearcoat",), lambda w: 0.0, when=lambda w: w > 0,
                converted="glTF does not darken under a clearcoat"),
        Mapping("thin_film_weight", ("iridescence",)),
        Mapping("thin_film_thickness", ("iridescence_thickness",), lambda t: t / 1000.0, converted="nanometres to micrometres"),
        Mapping("thin_film_ior", ("iridescence_ior",)),
        Mapping("emission_color", ("emissive",), lambda c: c / np.max(c) if np.max(c) > 0 else WHITE),
        Mapping("emission_luminance", ("emissive", "emissive_strength"), lambda c, s: np.max(c) * s * nits,
                converted=f"nits at {nits:g} nit(s) per unit"),
        Mapping("geometry_opacity", ("alpha", "alpha_mode", "alpha_cutoff"),
                lambda a, m, c: np.where(m == 0, 1.0, np.where(m == 1, np.where(a >= c, 1.0, 0.0), a)),
                exact=False, matters=lambda a, m, c: m == 1, note="an alpha MASK becomes a binary opacity"),
        Mapping("geometry_normal", ("normal",)),
        Mapping("geometry_tangent", ("tangent",)),
        Mapping("geometry_coat_normal", ("clearcoat_normal",)),
    )


DROPPED_FROM_GLTF = (
    Dropped("occlusion", "OpenPBR has no ambient occlusion input (bake it into lighting)", matters=lambda v: v != 1.0),
    Dropped("anisotropy_rotation", "OpenPBR rotates anisotropy through the tangent", matters=lambda v: v != 0.0),
)


def openpbr_to_gltf(material: Material, settings: Settings | None = None) -> Translation:
    settings = settings or Settings()
    return translate(material, "gltf_pbr", to_gltf_mappings(settings), DROPPED_TO_GLTF, settings, "OpenPBR -> glTF")


def gltf_to_openpbr(material: Material, settings: Settings | None = None) -> Translation:
    settings = settings or Settings()
    return translate(material, "open_pbr_surface", from_gltf_mappings(settings), DROPPED_FROM_GLTF, settings,
                     "glTF -> OpenPBR")
