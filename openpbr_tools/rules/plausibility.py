"""Plausibility: values that are legal but physically unlikely, the kind a look-dev lead would flag.

These checks read constants only (a textured input is not judged here) and apply to OpenPBR
materials. Colour thresholds compare linear Rec.709 values, converted from the document colour
space; their defaults come from Filament's material guide (``schemas/plausibility.json``) and can be
overridden per project.
"""

from __future__ import annotations

from .. import colorspaces, tables
from ..diagnostics import Severity
from ..io.usd.types import is_eight_bit
from ..model import Texture
from ..resources import load_json
from . import Rule

METAL_TOO_DARK = Rule(
    "OPBR901", "metal-base-color-too-dark", Severity.INFO,
    "A metal whose base colour is darker than any real metal's reflectance.",
    "Real metals reflect 50-100% of light at normal incidence; Filament's guide asks for a luminance "
    "of at least 170 sRGB (0.40 linear). A dark metal is usually a dielectric colour left on a metal, "
    "or dirt that belongs in a mix. Info, not a warning: the bound is a heuristic (Filament's guidance), "
    "and real measured materials fall outside it (dark anodised or dyed metals).",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_metalness" type="float" value="1" />\n  <input name="base_color" type="color3" value="0.95, 0.64, 0.54" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_metalness" type="float" value="1" />\n  <input name="base_color" type="color3" value="0.1, 0.1, 0.1" />\n</open_pbr_surface>',
)
DIELECTRIC_OUT_OF_RANGE = Rule(
    "OPBR902", "dielectric-base-color-range", Severity.INFO,
    "A non-metal whose base colour is brighter or darker than real diffuse materials.",
    "Filament's guide gives sRGB 30-240 (tolerant) for non-metallic albedo: fresh snow is about 240, "
    "charcoal about 30. Pure white or black albedo breaks energy balance and exposure. Info, not a "
    "warning: the range is a heuristic, and real measured materials fall outside it (Musou Black, "
    "Vantablack below, Spectralon above).",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.5, 0.4, 0.3" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="1, 1, 1" />\n</open_pbr_surface>',
)
TRANSMISSIVE_METAL = Rule(
    "OPBR903", "transmission-on-metal", Severity.WARNING,
    "Transmission is set on a fully metallic surface, where it has no effect.",
    "In OpenPBR the metal slab is opaque; transmission only mixes into the dielectric base. "
    "The author probably meant a dielectric.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="transmission_weight" type="float" value="1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_metalness" type="float" value="1" />\n  <input name="transmission_weight" type="float" value="1" />\n</open_pbr_surface>',
)
FILM_WITHOUT_THICKNESS = Rule(
    "OPBR904", "thin-film-without-thickness", Severity.WARNING,
    "thin_film_weight is set but the film has zero thickness.",
    "A zero-thickness film produces no interference; the thin film has no visible effect.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="thin_film_weight" type="float" value="1" />\n  <input name="thin_film_thickness" type="float" value="0.4" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="thin_film_weight" type="float" value="1" />\n  <input name="thin_film_thickness" type="float" value="0" />\n</open_pbr_surface>',
)
IOR_BELOW_ONE = Rule(
    "OPBR905", "ior-below-one", Severity.WARNING,
    "An index of refraction below 1 (OpenPBR's specular, coat or thin film; a UsdPreviewSurface's ior).",
    "No common material has an IOR below 1 relative to air; values like 0.5 usually come from a "
    "'specular level' slider exported as an IOR. The coat's IOR below 1 inverts its Fresnel behaviour.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="coat_weight" type="float" value="1" />\n  <input name="coat_ior" type="float" value="1.5" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="coat_weight" type="float" value="1" />\n  <input name="coat_ior" type="float" value="0.5" />\n</open_pbr_surface>',
)
PARTIAL_METALNESS = Rule(
    "OPBR906", "partial-metalness", Severity.INFO,
    "A constant metalness between 0.1 and 0.9.",
    "Metalness is almost binary: intermediate values are meant for texture transitions (metal to "
    "rust), not for a whole material, which then looks like a blend of two materials.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_metalness" type="float" value="1" />\n  <input name="base_color" type="color3" value="0.9, 0.9, 0.9" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_metalness" type="float" value="0.5" />\n</open_pbr_surface>',
)
EMISSION_OFF = Rule(
    "OPBR907", "emission-no-effect", Severity.INFO,
    "Emission colour is set but luminance is 0, or luminance is set with a black colour.",
    "Either way nothing is emitted; usually half of an emissive set-up was lost in export.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="emission_luminance" type="float" value="100" />\n  <input name="emission_color" type="color3" value="1, 0.5, 0.2" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="emission_color" type="color3" value="1, 0.5, 0.2" />\n</open_pbr_surface>',
)
INVISIBLE = Rule(
    "OPBR908", "fully-transparent", Severity.WARNING,
    "geometry_opacity is 0, or a glTF material (gltf_pbr) is invisible everywhere: alphaMode BLEND with alpha 0, "
    "or MASK with alpha below alphaCutoff, and no base colour texture: the surface is invisible.",
    "The whole material renders nothing: no base, no reflection, no shadow. Usually an exporter mapping "
    "a transparency value onto opacity (glass wants transmission_weight 1, in glTF KHR_materials_transmission), "
    "or a holdout or ghosting override left in the asset; a holdout belongs to the render setup, not the "
    "material. glTF 2.0 (3.9.4): in BLEND mode alpha is coverage, and 0 draws nothing; in MASK mode a fragment "
    "whose alpha is below alphaCutoff is discarded (vertex colours only multiply alpha, so they cannot bring it "
    "back). Suppress it where the invisibility is meant.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="geometry_opacity" type="float" value="1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="geometry_opacity" type="float" value="0" />\n</open_pbr_surface>',
)

#: Below this linear luminance of base_weight * base_color a metal reflects (next to) nothing at normal incidence.
BLACK_METAL = 0.02

METAL_BLACK = Rule(
    "OPBR909", "metal-black", Severity.WARNING,
    f"A metal whose base colour (times base_weight, Standard Surface's base) has a luminance below {BLACK_METAL}: "
    "it reflects next to nothing at normal incidence and renders black (OpenPBR, Standard Surface).",
    "OpenPBR's metal reflects base_weight * base_color at normal incidence (its F0). No metal reflects under 2%: "
    "the darkest measured ones (physicallybased.info's silicon, 0.37 luminance) are far above it, and a dark "
    "anodised metal is a thin film, not a black F0. A black metal is a dielectric's black left on a metal, or an "
    "unset colour exported as 0. Reported instead of OPBR901. Not for glTF: its metallicFactor defaults to 1, so "
    "black text and trim are exported as black metals and render as meant (Khronos' AnisotropyDiscTest and "
    "IORTestGrid label their spheres so).",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_metalness" type="float" value="1" />\n  <input name="base_color" type="color3" value="0.56, 0.57, 0.58" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_metalness" type="float" value="1" />\n  <input name="base_color" type="color3" value="0, 0, 0" />\n</open_pbr_surface>',
)

_LUMINANCE = ('<image name="mask" type="float">\n  <input name="file" type="filename" value="mask.png" />\n</image>\n'
              '{scaled}<open_pbr_surface name="S" type="surfaceshader">\n  <input name="emission_color" type="color3" '
              'value="1, 0.25, 0.6" />\n  <input name="emission_luminance" type="float" nodename="{node}" />\n'
              '</open_pbr_surface>')
LUMINANCE_FROM_MASK = Rule(
    "OPBR910", "emission-luminance-from-mask", Severity.WARNING,
    "emission_luminance reads an 8-bit image as it is: at most 1 nit, a glow no display shows.",
    "OpenPBR's emission_luminance is in nits (cd/m^2; its nodedef's soft range is 0-1000, a lit screen is a few "
    "hundred): an 8-bit image holds 0-1, so read directly the surface emits at most 1 nit and looks unlit. It is "
    "what a translation of Standard Surface's emission (a 0-1 weight) or glTF's emissiveTexture gives when the "
    "luminance is wired to the mask: scale the mask by the luminance meant (a multiply node), or feed the mask to "
    "emission_color and set emission_luminance.",
    passing=_LUMINANCE.format(scaled='<multiply name="nits" type="float">\n  <input name="in1" type="float" '
                              'nodename="mask" />\n  <input name="in2" type="float" value="400" />\n</multiply>\n',
                              node="nits"),
    failing=_LUMINANCE.format(scaled="", node="mask"), example_files=("mask.png",),
)

SPECULAR_SATURATED = Rule(
    "OPBR911", "specular-weight-saturated", Severity.WARNING,
    "A specular_weight so large that the dielectric's reflectivity reaches 1 (specular_weight times the F0 of "
    "specular_ior, relative to the coat under a coat, at least 1): a mirror at every angle, past which more weight "
    "changes nothing.",
    "OpenPBR 1.1 (Specular): specular_weight scales the dielectric's normal-incidence reflectivity F0 = "
    "((n - 1)/(n + 1))^2 through its IOR, and \"we also allow the specular_weight to exceed 1\" to raise it; the "
    "scaled F0 is clamped below 1 (MaterialX's open_pbr_surface.mtlx, scaled_specular_F0). At 1 / F0 (25 at the "
    "default IOR 1.5) the base is a perfect mirror that hides its colour, subsurface and transmission; weights like "
    "100 are usually a percentage or an 8-bit level written into the weight.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_weight" type="float" value="1.5" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_weight" type="float" value="100" />\n</open_pbr_surface>',
)

RULES = (METAL_TOO_DARK, DIELECTRIC_OUT_OF_RANGE, TRANSMISSIVE_METAL, FILM_WITHOUT_THICKNESS,
         IOR_BELOW_ONE, PARTIAL_METALNESS, EMISSION_OFF, INVISIBLE, METAL_BLACK, LUMINANCE_FROM_MASK, SPECULAR_SATURATED)


class _Values:
    """Constants of one material with table defaults filled in; ``None`` for textured or broken inputs."""

    def __init__(self, material):
        self.material = material
        self.table = tables.table(material.model, material.version)

    def __call__(self, name):
        entry = self.material.inputs.get(name)
        if entry is None:
            parameter = self.table.get(name)
            return parameter.default if parameter is not None else None
        value = entry.constant
        if entry.type and self.table.get(name) and entry.type != self.table[name].type:
            return None
        return value

    def authored(self, name) -> bool:
        return name in self.material.inputs


#: Per model other than OpenPBR: its metalness, base colour and base weight inputs. Not glTF: its metallicFactor
#: defaults to 1, so black text and trim are exported as black metals and render as meant (Khronos'
#: AnisotropyDiscTest and IORTestGrid label their spheres so).
_OTHER_METALS = {"standard_surface": ("metalness", "base_color", "base")}


def _black_metal(material, asset, weights, limits, context):
    """OPBR909 for a Standard Surface metal: its conductor's F0 is its base colour times ``base``."""
    value = _Values(material)
    metal, colour, weight = _OTHER_METALS[material.model]
    metalness, base_color, scale = value(metal), value(colour), value(weight)
    if not (isinstance(base_color, tuple) and isinstance(metalness, float) and isinstance(scale, float)
            and value.authored(colour) and metalness >= limits["metalness_metal_above"]):
        return
    luminance = sum(w * c for w, c in zip(weights, _linear(material, asset, base_color))) * scale
    if luminance < BLACK_METAL:
        yield context.diagnostic(
            METAL_BLACK, f"{material.name}: a metal whose base colour luminance is {luminance:.3f}: it reflects next "
            "to nothing at normal incidence and renders black", material.inputs[colour].location,
            hint="give the metal its reflectance colour (real metals: luminance 0.4-1), or make it a dielectric")


def _linear(material, asset, rgb):
    space = material.colorspace or asset.colorspace
    if space in (None, "lin_rec709", "none") or space not in colorspaces.materialx_names():
        return tuple(float(c) for c in rgb)
    return tuple(float(c) for c in colorspaces.to_lin_rec709(rgb, space))


def check(asset, context):
    data = load_json("plausibility.json")
    limits = {k: context.threshold(k, v) for k, v in data["thresholds"].items()}
    weights = data["luminance_weights_lin_rec709"]
    for material in asset.materials:
        if material.model == "gltf_pbr" and material.version is not None:
            yield from _invisible_gltf(material, context)
        if material.model == "UsdPreviewSurface" and material.version is not None:
            yield from _preview_ior(material, context)
        if material.model in _OTHER_METALS and material.version is not None:
            yield from _black_metal(material, asset, weights, limits, context)
        if material.model != "open_pbr_surface" or material.version is None:
            continue
        value = _Values(material)
        metalness = value("base_metalness")
        base_color = value("base_color")
        if isinstance(base_color, tuple) and isinstance(metalness, float) and value.authored("base_color"):
            linear = _linear(material, asset, base_color)
            luminance = sum(w * c for w, c in zip(weights, linear))
            weight = value("base_weight")
            if metalness >= limits["metalness_metal_above"] and isinstance(weight, float) and \
                    luminance * weight < BLACK_METAL:
                yield context.diagnostic(
                    METAL_BLACK, f"{material.name}: a metal whose base_weight * base_color luminance is "
                    f"{luminance * weight:.3f}: it reflects next to nothing at normal incidence and renders black",
                    material.inputs["base_color"].location, hint="give the metal its reflectance colour (real metals: "
                    "luminance 0.4-1), or set base_metalness 0 for a black dielectric")
            elif metalness >= limits["metalness_metal_above"] and luminance < limits["metal_base_color_min_linear"]:
                yield context.diagnostic(
                    METAL_TOO_DARK,
                    f"{material.name}: metal base_color luminance {luminance:.3f} is below "
                    f"{limits['metal_base_color_min_linear']:.3f} (sRGB {limits['metal_base_color_min_srgb']:g})",
                    material.inputs["base_color"].location, hint="real metals reflect 50-100%: brighten base_color",
                )
            transmissive = value("transmission_weight")
            if metalness <= limits["metalness_dielectric_below"] and not (isinstance(transmissive, float) and transmissive >= 0.5):
                brightest = max(linear)
                if brightest > limits["dielectric_base_color_max_linear"] or brightest < limits["dielectric_base_color_min_linear"]:
                    side = "brighter" if brightest > limits["dielectric_base_color_max_linear"] else "darker"
                    yield context.diagnostic(
                        DIELECTRIC_OUT_OF_RANGE,
                        f"{material.name}: dielectric base_color is {side} than real diffuse materials "
                        f"(sRGB {limits['dielectric_base_color_min_srgb']:g}-{limits['dielectric_base_color_max_srgb']:g})",
                        material.inputs["base_color"].location,
                    )
        transmission = value("transmission_weight")
        if metalness == 1.0 and isinstance(transmission, float) and transmission > 0:
            yield context.diagnostic(
                TRANSMISSIVE_METAL, f"{material.name}: transmission_weight {transmission:g} on a full metal has no effect",
                material.inputs["transmission_weight"].location,
            )
        film = value("thin_film_weight")
        thickness = value("thin_film_thickness")
        if isinstance(film, float) and film > 0 and thickness == 0:
            yield context.diagnostic(
                FILM_WITHOUT_THICKNESS, f"{material.name}: thin_film_weight {film:g} with zero thickness",
                material.inputs["thin_film_weight"].location, hint="set thin_film_thickness (micrometres, e.g. 0.4)",
            )
        for name, needs in (("specular_ior", None), ("coat_ior", "coat_weight"), ("thin_film_ior", "thin_film_weight")):
            ior = value(name)
            active = value(needs) if needs else 1.0
            if value.authored(name) and isinstance(ior, float) and ior < 1.0 and isinstance(active, float) and active > 0:
                yield context.diagnostic(IOR_BELOW_ONE, f"{material.name}: {name} = {ior:g} is below 1",
                                         material.inputs[name].location)
        yield from _saturated(material, value, context)
        if (value.authored("base_metalness") and isinstance(metalness, float)
                and limits["metalness_dielectric_below"] < metalness < limits["metalness_metal_above"]):
            yield context.diagnostic(PARTIAL_METALNESS, f"{material.name}: base_metalness {metalness:g} is neither metal nor dielectric",
                                     material.inputs["base_metalness"].location)
        emitted = material.inputs.get("emission_luminance")
        mask = emitted.value if emitted is not None and isinstance(emitted.value, Texture) else None
        if mask is not None and is_eight_bit(mask.file) and _at_most_one(mask):
            yield context.diagnostic(
                LUMINANCE_FROM_MASK, f"{material.name}: emission_luminance reads the 8-bit image {mask.file!r} as it is, "
                "so the surface emits at most 1 nit (emission_luminance is in nits)", emitted.location,
                hint="multiply the mask by the luminance meant (e.g. 400 nits), or feed it to emission_color")
        luminance = value("emission_luminance")
        color = value("emission_color")
        if isinstance(luminance, float) and isinstance(color, tuple):
            if value.authored("emission_color") and luminance == 0 and max(color) > 0:
                yield context.diagnostic(EMISSION_OFF, f"{material.name}: emission_color is set but emission_luminance is 0",
                                         material.inputs["emission_color"].location, hint="set emission_luminance (nits)")
            elif luminance > 0 and max(color) == 0:
                yield context.diagnostic(EMISSION_OFF, f"{material.name}: emission_luminance {luminance:g} with a black emission_color",
                                         material.inputs["emission_luminance"].location)
        opacity = value("geometry_opacity")
        if value.authored("geometry_opacity") and opacity == 0:
            yield context.diagnostic(INVISIBLE, f"{material.name}: geometry_opacity is 0 (invisible)",
                                     material.inputs["geometry_opacity"].location)


def _at_most_one(texture) -> bool:
    """Whether a texture's scale and bias keep an 8-bit image's [0, 1] at or below 1 (none: as it is)."""
    def number(value, default):
        return float(max(value)) if isinstance(value, tuple) else float(value) if isinstance(value, (int, float)) else default
    return number(texture.scale, 1.0) + max(number(texture.bias, 0.0), 0.0) <= 1.0


def _invisible_gltf(material, context):
    """OPBR908 for gltf_pbr: one alpha everywhere (no base colour texture) that BLEND draws as nothing (0) or
    MASK cuts away (below the cutoff)."""
    value = _Values(material)
    mode, alpha, cutoff = value("alpha_mode"), value("alpha"), value("alpha_cutoff")
    if not isinstance(alpha, float) or mode not in (1, 2):
        return  # textured, broken, or OPAQUE (which ignores alpha)
    entry = material.inputs.get("alpha") or material.inputs.get("alpha_mode")
    if mode == 2 and alpha == 0:
        yield context.diagnostic(INVISIBLE, f"{material.name}: alphaMode BLEND with alpha 0 everywhere (invisible)",
                                 entry.location, hint="alpha is opacity: 1 is solid (for glass, use KHR_materials_transmission)")
    elif mode == 1 and isinstance(cutoff, float) and alpha < cutoff:
        yield context.diagnostic(INVISIBLE, f"{material.name}: alphaMode MASK with alpha {alpha:g} everywhere, below the "
                                 f"cutoff {cutoff:g}: every fragment is discarded (invisible)", entry.location,
                                 hint="raise baseColorFactor's alpha above alphaCutoff, or lower the cutoff")


def _saturated(material, value, context):
    """OPBR911: specular_weight x F0 at least 1 on a material with a dielectric share."""
    weight, ior, metalness = value("specular_weight"), value("specular_ior"), value("base_metalness")
    if not (value.authored("specular_weight") and isinstance(weight, float) and weight > 1.0
            and isinstance(ior, float) and ior > 0 and isinstance(metalness, float) and metalness < 1.0):
        return
    coat, coat_ior = value("coat_weight"), value("coat_ior")
    # (under a whole coat the base reflects relative to it: a smaller F0; a partial coat leaves a share of the base
    # uncoated, which reflects against air: the red team's H#20, specular_weight 100 under coat 0.25 was silent)
    relative = ior / coat_ior if isinstance(coat, float) and coat >= 1.0 and isinstance(coat_ior, float) \
        and coat_ior > 0 else ior
    f0 = ((relative - 1.0) / (relative + 1.0)) ** 2
    if f0 > 0 and weight * f0 >= 1.0:
        yield context.diagnostic(
            SPECULAR_SATURATED, f"{material.name}: specular_weight {weight:g} times the dielectric's F0 {f0:.3g} is "
            f"{weight * f0:.3g}: the reflectivity is clamped at 1, a mirror at every angle (any weight past "
            f"{1.0 / f0:.3g} changes nothing)", material.inputs["specular_weight"].location,
            hint="a weight of 0-1 dims the reflection, a little above 1 brightens it; a percentage is divided by 100")


def _preview_ior(material, context):
    """OPBR905 for a UsdPreviewSurface ``ior`` below 1: its Fresnel ((1 - n)/(1 + n))^2 reaches 1 at 0."""
    entry = material.inputs.get("ior")
    ior = entry.constant if entry is not None else None
    if isinstance(ior, float) and ior < 1.0:
        f0 = ((1.0 - ior) / (1.0 + ior)) ** 2 if ior > -1.0 else 1.0
        yield context.diagnostic(IOR_BELOW_ONE, f"{material.name}: ior = {ior:g} is below 1 (the preview's F0 "
                                 f"((1 - ior)/(1 + ior))^2 is {f0:.3g}{': a mirror' if f0 >= 0.999 else ''})",
                                 entry.location, hint="a glass or plastic is 1.4-1.6")
