"""A full metal dimmed by OpenPBR's ``specular_weight``, carried to Standard Surface by its coat's tint.

MaterialX's open_pbr_surface graph weights its metal (``metal_bsdf`` and ``metal_bsdf_tf``, generalized_schlick_bsdf
nodes) by ``specular_weight``: the whole Fresnel curve is scaled, the grazing edge included. Standard Surface's
conductor (an artistic IOR) ignores ``specular`` but for its edge colour, so the weight used to be folded into the base
colour (F0) and the 82-degree target. That is right at normal incidence, but the edge still reaches 1: weights of
0.6-0.8 rendered 0.5-0.9 mean CIEDE2000 off on the evaluator, and a weight of 0.1 up to 10.

Standard Surface multiplies everything under its coat by ``coat_attenuation = mix(1, coat_color, coat)``, which does
not depend on the view (MaterialX's standard_surface.mtlx). Its coat reflects by the dielectric Fresnel of
``coat_IOR``, which is 0 at every angle for an IOR of 1. So, on a metal without a coat, ``coat`` 1, ``coat_IOR`` 1 and
a grey ``coat_color`` of w scale the metal exactly as OpenPBR's weight w does. Under a coat of weight c and colour C,
the colour C' with ``mix(1, C', c) = w mix(1, C, c)`` does it: C' = w C - (1 - w)(1 - c) / c, a full coat's w C. The
rest of the material is translated as if its weight were 1.

The fold can still render closer where the edge colour's 82-degree solve cannot reach OpenPBR's tint for the
undimmed metal but can for the dimmed one, or where a wide-gamut base colour clips less once dimmed. So the candidate
search (:func:`.candidates.alternative_reading`) renders the fold beside the tint, and keeps it where it wins.
MaterialX's GLSL judged the two on 40 full metals (tests/benchmarks/bench_ss_metal_weight_glsl.py): mean CIEDE2000
0.99 with the fold, 0.53 with the tint; under 2.3: 37 with the fold, 40 with the tint; the tint was better by more
than 0.5 on 14 and worse by more than 0.5 on none.

This applies only where it is exact:
  * the inputs concerned are constants;
  * ``base_metalness`` is 1: the tint would also dim a dielectric share's diffuse, which OpenPBR's weight does not;
  * ``specular_weight`` is below 1;
  * C' is at least 0 in every channel;
  * under a coat, ``coat_darkening`` is 0: OpenPBR darkens the base under its coat by the base's own albedo, which
    the weight changes (a darkening folded into the base colour for a weight of 1 is not the dimmed metal's: 5.7 mean
    CIEDE2000 off on coated metals, in MaterialX's GLSL as on the evaluator);
  * there is no emission: Standard Surface's coat tints the emission beneath it, and fades it at grazing angles
    (``coat_emission_edf``).
"""

from __future__ import annotations

import copy

import numpy as np

from ..model import Constant, Input, Material
from ..rules.translation import APPROXIMATED, CONVERTED
from .common import Translation, Values

#: Standard Surface's coat inputs the dimming writes, and what they are for a coat that only tints
TINT_ONLY = {"coat": 1.0, "coat_IOR": 1.0, "coat_roughness": 0.0, "coat_anisotropy": 0.0,
             "coat_affect_roughness": 0.0, "coat_affect_color": 0.0}


def coat_tint(material: Material, values: Values) -> tuple[float, tuple[float, float, float] | None] | None:
    """(OpenPBR's ``specular_weight``, the coat colour that dims the metal by it: None where the source has no
    coat) where the dimming applies to ``material`` (see the module), else None."""
    names = ("base_metalness", "specular_weight", "coat_weight", "coat_color", "coat_darkening", "emission_luminance")
    if not all(values.is_constant(name) for name in names):
        return None
    metalness, weight, coat, luminance = (_scalar(values, name) for name in ("base_metalness", "specular_weight",
                                                                             "coat_weight", "emission_luminance"))
    if not (metalness >= 1.0 and 0.0 <= weight < 1.0 and luminance <= 0.0 and 0.0 <= coat <= 1.0):
        return None
    if coat <= 0.0:
        return weight, None
    if _scalar(values, "coat_darkening") > 0.0:
        return None  # (OpenPBR darkens the base under its coat by the base's albedo, which the weight changes)
    colour = np.asarray(values.constant("coat_color"), dtype=np.float64) * weight - (1.0 - weight) * (1.0 - coat) / coat
    if colour.shape != (3,) or np.any(colour < 0.0):
        return None
    return weight, tuple(float(c) for c in colour)


def undimmed(material: Material) -> Material:
    """``material`` with its ``specular_weight`` left out (its default, 1): what the mapping translates."""
    plain = copy.copy(material)
    plain.inputs = {name: entry for name, entry in material.inputs.items() if name != "specular_weight"}
    return plain


def dimmed(translation: Translation, source: Material, values: Values, tint, context, label: str) -> Translation:
    """``translation`` of :func:`undimmed` ``source``, its metal dimmed by the coat's tint (:func:`coat_tint`), with a
    note at ``specular_weight`` (and at each authored input of a coat of weight 0, which the tint takes the place of)."""
    weight, colour = tint
    result = translation.material
    entry = source.inputs["specular_weight"]
    coat_colour = result.inputs.get("coat_color")

    def written(name: str, type_name: str, value, like: Input | None = None) -> None:
        result.inputs[name] = Input(name, type_name, Constant(value), entry.location,
                                    colorspace=like.colorspace if like is not None else source.colorspace)

    notes = []
    if colour is None:
        for name, value in TINT_ONLY.items():
            written(name, "float", value)
        for name in ("coat_color", "coat_ior", "coat_roughness", "coat_roughness_anisotropy"):
            held = source.inputs.get(name)
            if held is not None and not _at_default(values, name):
                notes.append(context.diagnostic(CONVERTED, (
                    f"{source.name} ({label}): {name} is not carried: Standard Surface's coat holds the metal's "
                    "specular_weight instead; it has no effect while coat_weight is 0"), held.location))
        written("coat_color", "color3", (weight, weight, weight))
        how = (f"a coat of IOR 1, which reflects nothing, and grey colour {weight:g}, which dims everything beneath "
               "it (the source has no coat)")
    else:
        written("coat_color", "color3", colour, coat_colour)
        how = "the coat's colour, which dims everything beneath it, so that mix(1, coat_color, coat) is multiplied by it"
    note = context.diagnostic(CONVERTED, (
        f"{source.name} ({label}): specular_weight {weight:g} dims OpenPBR's whole metal (MaterialX's metal BSDF weight), "
        f"grazing edge included; Standard Surface's conductor ignores its specular, so the weight is written as {how}"),
        entry.location)
    return Translation(result, translation.diagnostics + [note] + notes, source, translation.folded, translation.read,
                       translation.origins, translation.quiet_drops, translation.about,
                       translation.mapping_only | {id(note) for note in [note] + notes})


def _scalar(values: Values, name: str) -> float:
    """A float input's constant (its default where unset; NaN where it holds none: every comparison then fails)."""
    return float(np.asarray(values.constant(name), dtype=np.float64).reshape(-1)[0])


def _at_default(values: Values, name: str) -> bool:
    value, default = values.constant(name), values.table[name].default
    return value is not None and np.allclose(np.asarray(value, dtype=np.float64), np.asarray(default, dtype=np.float64))


def fuzz_over_metal(translation: Translation, source: Material, values: Values, context, label: str) -> Translation:
    """``translation`` with a warning at ``fuzz_weight`` where the fuzz lies over metal: Standard Surface layers its
    sheen over the dielectric base only (MaterialX's standard_surface.mtlx: ``sheen_layer`` is beneath
    ``metalness_mix``'s dielectric side), so on a base of metalness m only (1 - m) of it shows (the red team's C4:
    glTF's SheenChair fabric, a metal with sheen, came out 15.3 mean CIEDE2000 off with a note that implied the sheen
    was kept; MaterialX's GLSL renders the written sheen as nothing)."""
    if not (values.is_constant("fuzz_weight") and values.is_constant("base_metalness")):
        return translation
    fuzz, metalness = _scalar(values, "fuzz_weight"), _scalar(values, "base_metalness")
    if not (fuzz > 0.0 and metalness > 0.0):
        return translation
    entry = source.inputs.get("fuzz_weight")
    shown = "none of it shows" if metalness >= 1.0 else f"only {1.0 - metalness:.0%} of it shows"
    translation.diagnostics.append(context.diagnostic(APPROXIMATED, (
        f"{source.name} ({label}): fuzz_weight: Standard Surface's sheen lies over its dielectric base only, not over "
        f"its metal: at base_metalness {metalness:g} {shown}"),
        entry.location if entry is not None else source.location.with_input("fuzz_weight")))
    return translation
