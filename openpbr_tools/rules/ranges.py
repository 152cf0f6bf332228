"""Ranges: is each constant inside the hard range (error) and the soft range (warning) of its
parameter table.

Hard ranges are the physically meaningful bounds (a weight outside [0, 1], a negative roughness);
soft ranges are the recommended UI ranges (specular_weight above 1, an IOR above 3). Where the
OpenPBR specification and MaterialX's node definition disagree, the table's ``range_note`` says
which bound the toolkit follows and why; the message repeats it.

Reflectance colours (``role: color`` with hard range [0, 1]) get two allowances, because real,
published materials need them: a metal's ``specular_color`` above 1 is accepted while the F82 edge
reflectivity it asks for stays at most 1 at every angle (OpenPBR's own example metals, cesium at
1.39 in blue, are authored so), and a colour outside [0, 1] in the document's colour space that lies
inside [0, 1] in ACEScg is a real colour that space cannot hold (measured gold in ``lin_rec709``):
an info (OPBR304), not an error: published measured data (gold, copper) is authored so and renders as
meant, so a warning would be a false alarm on every such library. Negative components stay errors even when the colour is real:
a negative reflectance makes path tracers' sampling weights negative.

Lengths in scene units (``transmission_depth``, ``subsurface_radius``) get no soft-range warning:
their node definitions' UI ranges assume one scene scale, and 2 (cm) is as normal as 0.02 (m).
"""

from __future__ import annotations

import difflib

from .. import tables
from ..diagnostics import Severity
from ..model import Connection, Location, Texture
from ..optics import F82_COSINE
from ..values import is_finite
from . import Rule, for_each_input
from .units import materialx_converted

HARD_RANGE = Rule(
    "OPBR301", "out-of-hard-range", Severity.ERROR,
    "A constant outside its parameter's valid range.",
    "Values outside the hard range have no physical meaning (a weight of 1.5, a negative IOR); "
    "renderers clamp them differently, so the material looks different everywhere.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_weight" type="float" value="1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_weight" type="float" value="1.5" />\n</open_pbr_surface>',
)
SOFT_RANGE = Rule(
    "OPBR302", "out-of-soft-range", Severity.WARNING,
    "A constant inside the valid range but outside the recommended one.",
    "Legal but unusual: an IOR of 4, a specular_weight of 2. Worth a second look; some renderers "
    "and exporters clamp to the soft range.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_ior" type="float" value="1.5" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_ior" type="float" value="4.5" />\n</open_pbr_surface>',
)
ENUM_VALUE = Rule(
    "OPBR303", "invalid-enum-value", Severity.ERROR,
    "An enumerated input set to a value outside its list.",
    "For instance UsdPreviewSurface's useSpecularWorkflow takes 0 or 1, glTF PBR's alpha_mode 0, 1 or 2.",
    passing='<UsdPreviewSurface name="S" type="surfaceshader">\n  <input name="useSpecularWorkflow" type="integer" value="1" />\n</UsdPreviewSurface>',
    failing='<UsdPreviewSurface name="S" type="surfaceshader">\n  <input name="useSpecularWorkflow" type="integer" value="2" />\n</UsdPreviewSurface>',
)

OUT_OF_GAMUT = Rule(
    "OPBR304", "colour-outside-document-gamut", Severity.INFO,
    "A reflectance colour outside [0, 1] in the document's colour space but inside it in ACEScg.",
    "Measured and spectrally derived colours are often outside the Rec.709 gamut: gold's normal-"
    "incidence reflectance is about (1.06, 0.77, 0.31) in linear Rec.709 and (0.93, 0.79, 0.37) in "
    "ACEScg. The colour is real, but a renderer working in the document's space reflects more light "
    "than it receives in the channel above 1 (and clamps or goes negative below 0), which OpenPBR's "
    "specification calls not sensible for albedos. Author the document in ACEScg (the message gives "
    "the converted value) or accept the small gain. A value above 1 even in ACEScg is no real "
    "reflectance, and a negative component makes a path tracer's sampling weights negative: both "
    "stay OPBR301, as does any colour above 1 in glTF, whose colours are linear Rec.709 by definition "
    "and whose schema stops at 1 (the Khronos glTF-Validator's VALUE_NOT_IN_RANGE).",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.93, 0.79, 0.37" colorspace="acescg" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="1.059, 0.773, 0.307" />\n</open_pbr_surface>',
)

RULES = (HARD_RANGE, SOFT_RANGE, ENUM_VALUE, OUT_OF_GAMUT)


def _components(value) -> tuple:
    if isinstance(value, (tuple, list)):
        return tuple(value)
    return (value,)


def _outside(values: tuple, bound, below: bool, exclusive: bool = False) -> list[int]:
    """Indices of components below (or above) ``bound`` (a scalar or per-component tuple); with
    ``exclusive``, on it too."""
    if bound is None:
        return []
    bounds = _components(bound)
    if len(bounds) == 1:
        bounds = bounds * len(values)
    if exclusive:
        return [i for i, (v, b) in enumerate(zip(values, bounds)) if (v <= b if below else v >= b)]
    return [i for i, (v, b) in enumerate(zip(values, bounds)) if (v < b if below else v > b)]


def _fmt(value) -> str:
    if isinstance(value, tuple):
        return "(" + ", ".join(f"{v:g}" for v in value) + ")"
    return f"{value:g}"


#: The part of the glTF property each KHR_materials_pbrSpecularGlossiness input the reader found is read from.
SPECULAR_GLOSSINESS_PARTS = {"diffuseColor": "RGB", "opacity": "A", "specularColor": "RGB", "glossiness": ""}


def check(asset, context):
    for observation in asset.observations:
        if observation.kind == "node_enum_value":  # an input of a node in a graph (MaterialX's nodedef enum)
            detail = observation.detail
            guess = difflib.get_close_matches(detail["value"], detail["allowed"], n=1, cutoff=0.5)
            yield context.diagnostic(
                ENUM_VALUE, f"{observation.location.input} = {detail['value']!r} is not one of {list(detail['allowed'])}",
                observation.location, hint=f"did you mean {guess[0]!r}?" if guess else None)
    yield from _time_samples(asset, context)
    yield from _specular_glossiness(asset, context)
    yield from _diffuse_transmission(asset, context)
    for material, table, entry in for_each_input(asset):
        parameter = table.get(entry.name)
        value = entry.constant
        converted = materialx_converted(entry, parameter, asset.format) if parameter is not None else None
        value = converted if converted is not None else value  # (OPBR604/OPBR607 say what the unit does)
        if parameter is not None and parameter.enum is not None and entry.allowed and entry.value is None:
            yield context.diagnostic(
                ENUM_VALUE, f"{entry.name}: {entry.raw} is not one of {', '.join(entry.allowed)}", entry.location)
            continue
        if parameter is None or value is None or isinstance(value, (bool, str)) or not is_finite(value):
            continue
        if entry.type and entry.type != parameter.type:
            continue  # reported as a type mismatch; its components do not line up with the range
        if parameter.enum is not None:
            if value not in parameter.enum:
                yield context.diagnostic(
                    ENUM_VALUE, f"{entry.name} = {_fmt(value)} is not one of {list(parameter.enum)}",
                    entry.location,
                )
            continue
        values = _components(value)
        if parameter.special_value is not None and values == (parameter.special_value,):
            continue  # (glTF's ior 0: a mode of its own, read by the translation as an infinite IOR)
        if parameter.default is None and parameter.hard_min_exclusive and values == (parameter.hard_min,) \
                and asset.format != "gltf":
            continue  # a MaterialX input without a default reads 0 when unset (gltf_pbr's attenuation_distance): its own
            # value, written out by converters (KhronosGroup's glTF-MaterialX-Converter); glTF's JSON forbids it
        note = f" ({parameter.range_note})" if parameter.range_note else ""
        low = _outside(values, parameter.hard_min, below=True, exclusive=parameter.hard_min_exclusive)
        high = _outside(values, parameter.hard_max, below=False)
        if (low or high) and _reflectance(parameter):
            if entry.name == "specular_color" and not low and _physical_metal_edge(material, table, values):
                continue
            # (a glTF colour is linear Rec.709 and the schema's range [0, 1]: no other space to author it in)
            wide = None if low or asset.format == "gltf" else \
                _in_acescg(values, entry.colorspace or material.colorspace or asset.colorspace)
            if wide is not None:
                yield context.diagnostic(
                    OUT_OF_GAMUT,
                    f"{entry.name} = {_fmt(value)} is outside [0, 1] in "
                    f"{entry.colorspace or material.colorspace or asset.colorspace or 'the default colour space'}"
                    f" but {_fmt(wide)} in ACEScg",
                    entry.location, hint="author the document in acescg to keep it in gamut",
                )
                continue
        if low or high:
            valid = _range(parameter.hard_min, parameter.hard_max, parameter.hard_min_exclusive)
            yield context.diagnostic(
                HARD_RANGE,
                f"{entry.name} = {_fmt(value)} is outside its valid range {valid}{note}",
                entry.location, hint=f"default is {_fmt(parameter.default) if parameter.default is not None else 'geometric'}",
            )
            continue
        if parameter.unit == "scene_length":
            continue
        low = _outside(values, parameter.soft_min, below=True)
        high = _outside(values, parameter.soft_max, below=False) and not parameter.soft_max_exceedable
        if low or high:
            soft_low = parameter.soft_min if parameter.soft_min is not None else parameter.hard_min
            soft_high = parameter.soft_max if parameter.soft_max is not None else parameter.hard_max
            yield context.diagnostic(
                SOFT_RANGE,
                f"{entry.name} = {_fmt(value)} is outside the recommended range {_range(soft_low, soft_high)}{note}",
                entry.location,
            )


def _time_samples(asset, context):
    """The other values a USD input takes: each time sample of an animated one, and its value in each variant
    that is not selected; each is held to the hard range (the value read, the default or first sample of the
    selected variant, is checked with the others above), and the first outside it is reported."""
    for observation in asset.observations:
        if observation.kind not in ("usd_time_samples", "usd_other_values"):
            continue
        detail = observation.detail
        values_at = [(f"at time {time:g} (a time sample)", value) for time, value in detail.get("samples", ())] + \
            list(detail.get("values", ()))
        parameter = tables.table(detail["model"]).get(detail["input"])
        if parameter is None or parameter.enum is not None or parameter.type in ("boolean", "string", "filename"):
            continue
        for where, value in values_at:
            if value is None or isinstance(value, (bool, str)):
                continue
            if not is_finite(value):  # (as a static NaN is: the red team's H#17, a NaN time sample passed)
                from .values import NON_FINITE  # lazy: a sibling rule module, as in _specular_glossiness

                yield context.diagnostic(NON_FINITE, f"{detail['input']} is {_fmt(value)} {where}",
                                         observation.location, hint="fix the value there")
                break
            values = _components(value)
            if _outside(values, parameter.hard_min, below=True, exclusive=parameter.hard_min_exclusive) or \
                    _outside(values, parameter.hard_max, below=False):
                valid = _range(parameter.hard_min, parameter.hard_max, parameter.hard_min_exclusive)
                yield context.diagnostic(
                    HARD_RANGE, f"{detail['input']} = {_fmt(value)} {where} is outside its valid range {valid}",
                    observation.location, hint="fix the value there")
                break


def _specular_glossiness(asset, context):
    """A glTF material's KHR_materials_pbrSpecularGlossiness factors (the reader's ``extra["gltf"]["spec_gloss"]``,
    which no generic rule walks) against the extension's schema, as the Khronos glTF-Validator checks them:
    every component in [0, 1] (OPBR301, a factor beside a texture too: the texture's scale), a value of the
    wrong type (OPBR202), one that is not finite (OPBR203), a texture index that points nowhere (OPBR802)."""
    from .structure import DANGLING  # lazy: sibling rule modules
    from .values import NON_FINITE, UNPARSABLE  # lazy: as above

    for material in asset.materials:
        state = material.gltf_state()
        found = state.get("spec_gloss") if isinstance(state.get("spec_gloss"), dict) else {}
        for name, entry in found.items():
            where = entry.location
            if entry.error is not None:
                yield context.diagnostic(UNPARSABLE, entry.error if entry.error.startswith(str(where.input))
                                         else f"{where.input}: {entry.error}", where)
                continue
            if isinstance(entry.value, Connection) and entry.value.dangling:
                yield context.diagnostic(DANGLING, f"{where.input}: {entry.value.reason or 'a texture that does not exist'}",
                                         where)
                continue
            value = entry.value.scale if isinstance(entry.value, Texture) else entry.constant
            if value is None or isinstance(value, (bool, str)):
                continue
            if not is_finite(value):
                yield context.diagnostic(NON_FINITE, f"{where.input} is {_fmt(value)}", where)
            elif any(v < 0.0 or v > 1.0 for v in _components(value)):
                part = SPECULAR_GLOSSINESS_PARTS.get(name, "")
                yield context.diagnostic(
                    HARD_RANGE, f"{where.input}{f' ({part})' if part else ''} = {_fmt(value)} is outside its "
                                "valid range [0, 1] (KHR_materials_pbrSpecularGlossiness)", where,
                    hint="the extension's schema: every component in [0, 1]")


#: KHR_materials_diffuse_transmission's factors (kept as the glTF reader's raw JSON: no gltf_pbr parameter
#: holds them) and the range its schema gives each: [0, 1], every component.
DIFFUSE_TRANSMISSION_FACTORS = ("diffuseTransmissionFactor", "diffuseTransmissionColorFactor")


def _diffuse_transmission(asset, context):
    """A glTF material's KHR_materials_diffuse_transmission factors outside [0, 1] (OPBR301 at the property;
    a conversion does not read such a factor, and says so)."""
    from ..io.gltf.slots import DIFFUSE_TRANSMISSION  # lazy: only glTF assets carry the extension

    for material in asset.materials:
        state = material.gltf_state()
        extensions = state.get("extensions") if isinstance(state.get("extensions"), dict) else {}
        found = extensions.get(DIFFUSE_TRANSMISSION)
        for name in DIFFUSE_TRANSMISSION_FACTORS if isinstance(found, dict) else ():
            value = found.get(name)
            values = value if isinstance(value, list) else [value]
            if all(isinstance(v, (int, float)) and not isinstance(v, bool) and is_finite(v) for v in values) and \
                    any(not 0.0 <= v <= 1.0 for v in values):
                shown = _fmt(tuple(float(v) for v in values) if isinstance(value, list) else float(value))
                yield context.diagnostic(
                    HARD_RANGE, f"{name} = {shown} is outside its valid range [0, 1] ({DIFFUSE_TRANSMISSION})",
                    Location(material.location.file, None, f"{material.location.path}/extensions/{DIFFUSE_TRANSMISSION}",
                             name),
                    hint="the extension's schema: every component in [0, 1]")


def _reflectance(parameter) -> bool:
    return (parameter.role == "color" and parameter.type == "color3"
            and _components(parameter.hard_min) in ((0.0,), (0.0, 0.0, 0.0))
            and _components(parameter.hard_max) in ((1.0,), (1.0, 1.0, 1.0)))


def _physical_metal_edge(material, table, tint: tuple) -> bool:
    """True for an OpenPBR metal (constant base_metalness 1) whose F82 edge tint asks for an edge
    reflectivity of at most 1: OpenPBR 1.1, "Metal": F(1/7) = specular_color * F_Schlick(1/7) with
    F0 = base_weight * base_color. (The F82 polynomial itself may pass 1 by about 1% nearer grazing,
    as on OpenPBR's own cesium example; that is the model's fit, not the asset's value.)"""
    if material.model != "open_pbr_surface":
        return False

    def constant(name):
        entry = material.inputs.get(name)
        if entry is None:
            parameter = table.get(name)
            return parameter.default if parameter is not None else None
        return entry.constant

    metalness, weight, colour = constant("base_metalness"), constant("base_weight"), constant("base_color")
    if metalness != 1 or not isinstance(weight, (int, float)) or not isinstance(colour, tuple) or len(colour) != 3:
        return False
    grazing = (1.0 - F82_COSINE) ** 5
    for c, t in zip(colour, tint):
        f0 = min(max(c * weight, 0.0), 1.0)
        if t * (f0 + (1.0 - f0) * grazing) > 1.0 + 1e-9:
            return False
    return True


def _in_acescg(values: tuple, colorspace: str | None) -> tuple | None:
    """The colour in ACEScg when it lies inside [0, 1] there (a real colour outside the document's
    gamut), else ``None`` (also for a space the toolkit cannot convert: OPBR4xx reports it)."""
    # lazy: colour-science loads only for an out-of-range colour
    from .. import colorspaces

    if len(values) != 3:
        return None
    if colorspace is not None and colorspace not in colorspaces.materialx_names():
        colorspace = colorspaces.materialx_equivalent(colorspace) or colorspace  # a USD name (lin_rec709_scene)
    try:
        linear = colorspaces.to_lin_rec709(values, colorspace)
        wide = tuple(float(c) for c in colorspaces.from_lin_rec709(linear, "acescg"))
    except (KeyError, ValueError):
        return None
    tolerance = 1e-4
    if all(-tolerance <= c <= 1.0 + tolerance for c in wide):
        return tuple(round(c, 4) for c in wide)
    return None


def _range(low, high, open_low: bool = False) -> str:
    left = "(-inf" if low is None else f"{'(' if open_low else '['}{_fmt(low)}"
    right = "inf)" if high is None else f"{_fmt(high)}]"
    return f"{left}, {right}"
