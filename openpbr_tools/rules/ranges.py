"""Ranges: is each constant inside the hard range (error) and the soft range (warning) of its
parameter table.

Hard ranges are the physically meaningful bounds (a weight outside [0, 1], a negative roughness);
soft ranges are the recommended UI ranges (specular_weight above 1, an IOR above 3). Where the
OpenPBR specification and MaterialX's node definition disagree, the table's ``range_note`` says
which bound the toolkit follows and why; the message repeats it.

Lengths in scene units (``transmission_depth``, ``subsurface_radius``) get no soft-range warning:
their node definitions' UI ranges assume one scene scale, and 2 (cm) is as normal as 0.02 (m).
"""

from __future__ import annotations

from ..diagnostics import Severity
from ..values import is_finite
from . import Rule, for_each_input

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

RULES = (HARD_RANGE, SOFT_RANGE, ENUM_VALUE)


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


def check(asset, context):
    for material, table, entry in for_each_input(asset):
        parameter = table.get(entry.name)
        value = entry.constant
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
        note = f" ({parameter.range_note})" if parameter.range_note else ""
        low = _outside(values, parameter.hard_min, below=True, exclusive=parameter.hard_min_exclusive)
        high = _outside(values, parameter.hard_max, below=False)
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
        high = _outside(values, parameter.soft_max, below=False)
        if low or high:
            soft_low = parameter.soft_min if parameter.soft_min is not None else parameter.hard_min
            soft_high = parameter.soft_max if parameter.soft_max is not None else parameter.hard_max
            yield context.diagnostic(
                SOFT_RANGE,
                f"{entry.name} = {_fmt(value)} is outside the recommended range {_range(soft_low, soft_high)}{note}",
                entry.location,
            )


def _range(low, high, open_low: bool = False) -> str:
    left = "(-inf" if low is None else f"{'(' if open_low else '['}{_fmt(low)}"
    right = "inf)" if high is None else f"{_fmt(high)}]"
    return f"{left}, {right}"
